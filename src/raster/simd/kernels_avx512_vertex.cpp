// src/raster/simd/kernels_avx512_vertex.cpp — the AVX-512 vertex-stage kernels: vertex lighting
// (shadeVertices), transformPoints and the vectorized specularPow, 16 vertices per register.
#include "kernels_avx512_vertex.h"

#include <immintrin.h>

#include <cstddef>

#include "../cpu.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

namespace {

/// glm's scalar semantics, lane by lane: max(x, y) = x < y ? y : x; min(x, y) = y < x ? y : x.
inline __m512 glmMax(__m512 x, __m512 y) {
    return _mm512_mask_mov_ps(x, _mm512_cmp_ps_mask(x, y, _CMP_LT_OQ), y);
}
inline __m512 glmMin(__m512 x, __m512 y) {
    return _mm512_mask_mov_ps(x, _mm512_cmp_ps_mask(y, x, _CMP_LT_OQ), y);
}
inline __m512 dot3(__m512 ax, __m512 ay, __m512 az, __m512 bx, __m512 by, __m512 bz) {
    return _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(ax, bx), _mm512_mul_ps(ay, by)),
                         _mm512_mul_ps(az, bz));
}
/// glm::normalize: v * (1 / sqrt(dot(v, v))).
inline void normalize3(__m512& x, __m512& y, __m512& z) {
    const __m512 s = _mm512_div_ps(_mm512_set1_ps(1.0f), _mm512_sqrt_ps(dot3(x, y, z, x, y, z)));
    x = _mm512_mul_ps(x, s), y = _mm512_mul_ps(y, s), z = _mm512_mul_ps(z, s);
}

/// lighting.h's specularPow, 16 lanes: the same float / integer operations in the same order
/// (the final scaling m·2^a·2^b of the scalar code is computed alike: two multiplies).
inline __m512 specularPow16(__m512 x, float s) {
    using namespace pow_detail;
    const __mmask16 tiny = _mm512_cmp_ps_mask(x, _mm512_set1_ps(0x1p-126f), _CMP_LT_OQ);
    const __m512 xs = _mm512_mask_mul_ps(x, tiny, x, _mm512_set1_ps(0x1p23f));
    const __m512i t = _mm512_sub_epi32(_mm512_castps_si512(xs), _mm512_set1_epi32(kSqrtHalfBits));
    const __m512i e0 = _mm512_srai_epi32(t, 23);
    const __m512i e = _mm512_mask_sub_epi32(e0, tiny, e0, _mm512_set1_epi32(23));
    const __m512 f = _mm512_sub_ps(
        _mm512_castsi512_ps(_mm512_add_epi32(_mm512_and_si512(t, _mm512_set1_epi32(0x007fffff)),
                                             _mm512_set1_epi32(kSqrtHalfBits))),
        _mm512_set1_ps(1.0f));
    __m512 p = _mm512_set1_ps(kLog2[8]);
    for (int k = 7; k >= 0; --k) p = _mm512_add_ps(_mm512_mul_ps(p, f), _mm512_set1_ps(kLog2[k]));
    const __m512 l = _mm512_add_ps(_mm512_cvtepi32_ps(e), _mm512_mul_ps(f, p));
    __m512 y = _mm512_mul_ps(_mm512_set1_ps(s), l);
    y = _mm512_max_ps(y, _mm512_set1_ps(-kYMax));  // y > −Y ? y : −Y (NaN → −Y), as the scalar code
    y = _mm512_min_ps(y, _mm512_set1_ps(kYMax));  // y < Y ? y : Y
    const __m512 rnd = _mm512_set1_ps(kRound);
    const __m512 nf = _mm512_sub_ps(_mm512_add_ps(y, rnd), rnd);
    const __m512 r = _mm512_sub_ps(y, nf);
    __m512 q = _mm512_set1_ps(kExp2[5]);
    for (int k = 4; k >= 0; --k) q = _mm512_add_ps(_mm512_mul_ps(q, r), _mm512_set1_ps(kExp2[k]));
    const __m512 m = _mm512_add_ps(_mm512_set1_ps(1.0f), _mm512_mul_ps(r, q));
    const __m512i n = _mm512_cvttps_epi32(nf);  // nf is an integer: exact
    const __m512i a = _mm512_srai_epi32(n, 1), b = _mm512_sub_epi32(n, a);
    const __m512i bias = _mm512_set1_epi32(127);
    __m512 res = _mm512_mul_ps(
        _mm512_mul_ps(m, _mm512_castsi512_ps(_mm512_slli_epi32(_mm512_add_epi32(a, bias), 23))),
        _mm512_castsi512_ps(_mm512_slli_epi32(_mm512_add_epi32(b, bias), 23)));
    res = _mm512_mask_mov_ps(res, _mm512_cmp_ps_mask(x, _mm512_setzero_ps(), _CMP_EQ_OQ),
                             _mm512_set1_ps(powOfZero(s)));
    return _mm512_add_ps(res, _mm512_sub_ps(x, x));
}

/// 16 glm::vec3 (48 contiguous floats) → x, y, z registers: three loads and two permutes per
/// component instead of gathers.
struct AosIdx {
    __m512i lo[3], hi[3];  ///< component k: lanes from (a, b), then the rest from c
    AosIdx() {
        alignas(64) std::int32_t l[3][16], h[3][16];
        for (int k = 0; k < 3; ++k) {
            for (int j = 0; j < 16; ++j) {
                const int pos = 3 * j + k;
                l[k][j] = pos < 32 ? pos : 0;
                h[k][j] = pos < 32 ? j : 16 + pos - 32;
            }
            lo[k] = _mm512_load_si512(l[k]);
            hi[k] = _mm512_load_si512(h[k]);
        }
    }
};
inline void loadVec3x16(const AosIdx& ix, const float* src, __m512& x, __m512& y, __m512& z) {
    const __m512 a = _mm512_loadu_ps(src), b = _mm512_loadu_ps(src + 16),
                 c = _mm512_loadu_ps(src + 32);
    x = _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, ix.lo[0], b), ix.hi[0], c);
    y = _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, ix.lo[1], b), ix.hi[1], c);
    z = _mm512_permutex2var_ps(_mm512_permutex2var_ps(a, ix.lo[2], b), ix.hi[2], c);
}
/// x, y, z registers → 48 interleaved floats.
struct SoaIdx {
    __m512i xy[3], z[3];  ///< output register r: pick x / y lanes, then z lanes
    SoaIdx() {
        alignas(64) std::int32_t a[3][16], b[3][16];
        for (int r = 0; r < 3; ++r) {
            for (int q = 0; q < 16; ++q) {
                const int pos = 16 * r + q, j = pos / 3, k = pos % 3;
                a[r][q] = k == 0 ? j : k == 1 ? 16 + j : 0;
                b[r][q] = k == 2 ? 16 + j : q;
            }
            xy[r] = _mm512_load_si512(a[r]);
            z[r] = _mm512_load_si512(b[r]);
        }
    }
};
inline void storeVec3x16(const SoaIdx& ix, float* dst, __m512 x, __m512 y, __m512 z) {
    for (int r = 0; r < 3; ++r) {
        _mm512_storeu_ps(dst + 16 * r, _mm512_permutex2var_ps(
                                           _mm512_permutex2var_ps(x, ix.xy[r], y), ix.z[r], z));
    }
}
}  // namespace

namespace avx512 {

/// shadeVerticesTail with 16 vertices per register: transformPoint / transformDir / lighting.h's
/// shadeBlinnPhong (with specularPow) in their operation order.
void shadeVertices(const glm::vec3* positions, const glm::vec3* normals, std::size_t n,
                   const glm::mat4& W, const glm::mat3& N, const ShadingContext& ctx,
                   const Material& m, float* color) {
    static const AosIdx aos;
    static const SoaIdx soa;
    const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f);
    const glm::vec3 ambient = ctx.ambient * m.albedo;
    const __m512 specular = _mm512_set1_ps(m.specular);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        __m512 px, py, pz, nx, ny, nz;
        loadVec3x16(aos, &positions[i].x, px, py, pz);
        loadVec3x16(aos, &normals[i].x, nx, ny, nz);
        __m512 wp[3], nn[3];
        for (int r = 0; r < 3; ++r) {
            wp[r] = _mm512_add_ps(
                _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(W[0][r]), px),
                                            _mm512_mul_ps(_mm512_set1_ps(W[1][r]), py)),
                              _mm512_mul_ps(_mm512_set1_ps(W[2][r]), pz)),
                _mm512_set1_ps(W[3][r]));
            nn[r] = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(N[0][r]), nx),
                                                _mm512_mul_ps(_mm512_set1_ps(N[1][r]), ny)),
                                  _mm512_mul_ps(_mm512_set1_ps(N[2][r]), nz));
        }
        nx = nn[0], ny = nn[1], nz = nn[2];
        normalize3(nx, ny, nz);
        __m512 vx = _mm512_sub_ps(_mm512_set1_ps(ctx.centerEye.x), wp[0]);
        __m512 vy = _mm512_sub_ps(_mm512_set1_ps(ctx.centerEye.y), wp[1]);
        __m512 vz = _mm512_sub_ps(_mm512_set1_ps(ctx.centerEye.z), wp[2]);
        normalize3(vx, vy, vz);
        __m512 cr = _mm512_set1_ps(ambient.x), cg = _mm512_set1_ps(ambient.y),
               cb = _mm512_set1_ps(ambient.z);
        for (const DirectionalLight& l : ctx.lights) {
            const __m512 lx = _mm512_set1_ps(l.towardLight.x), ly = _mm512_set1_ps(l.towardLight.y),
                         lz = _mm512_set1_ps(l.towardLight.z);
            const __m512 nl = dot3(nx, ny, nz, lx, ly, lz);
            const __mmask16 lit = _mm512_cmp_ps_mask(nl, zero, _CMP_GT_OQ);
            if (!lit) continue;
            __m512 hx = _mm512_add_ps(lx, vx), hy = _mm512_add_ps(ly, vy),
                   hz = _mm512_add_ps(lz, vz);
            normalize3(hx, hy, hz);
            const __m512 nh = dot3(nx, ny, nz, hx, hy, hz);
            // std::max(dot, 0) = dot < 0 ? 0 : dot.
            const __m512 base =
                _mm512_mask_mov_ps(nh, _mm512_cmp_ps_mask(nh, zero, _CMP_LT_OQ), zero);
            const __m512 spec = _mm512_mul_ps(specular, specularPow16(base, m.shininess));
            cr = _mm512_mask_add_ps(
                cr, lit, cr,
                _mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(nl, _mm512_set1_ps(m.albedo.x)), spec),
                              _mm512_set1_ps(l.color.x)));
            cg = _mm512_mask_add_ps(
                cg, lit, cg,
                _mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(nl, _mm512_set1_ps(m.albedo.y)), spec),
                              _mm512_set1_ps(l.color.y)));
            cb = _mm512_mask_add_ps(
                cb, lit, cb,
                _mm512_mul_ps(_mm512_add_ps(_mm512_mul_ps(nl, _mm512_set1_ps(m.albedo.z)), spec),
                              _mm512_set1_ps(l.color.z)));
        }
        // glm::clamp(c, 0, 1) = min(max(c, 0), 1).
        cr = glmMin(glmMax(cr, zero), one);
        cg = glmMin(glmMax(cg, zero), one);
        cb = glmMin(glmMax(cb, zero), one);
        storeVec3x16(soa, color + 3 * i, cr, cg, cb);
    }
    // The tail through the scalar table: lighting.h's shadeBlinnPhong is an inline function with
    // external linkage; an out-of-line copy compiled here, with this file's target flags, is
    // one the linker may keep for every caller (tests/raster/simd_objects.cmake).
    scalarKernels().shadeVertices(positions + i, normals + i, n - i, W, N, ctx, m, color + 3 * i);
}

/// transformPointsTail with 16 vertices per register.
void transformPoints(const glm::vec3* positions, std::size_t n, const glm::mat4& M, float* x,
                     float* y, float* z, float* w) {
    static const AosIdx aos;
    float* out[4] = {x, y, z, w};
    __m512 c[4][4];
    for (int col = 0; col < 4; ++col)
        for (int r = 0; r < 4; ++r) c[col][r] = _mm512_set1_ps(M[col][r]);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        __m512 px, py, pz;
        loadVec3x16(aos, &positions[i].x, px, py, pz);
        for (int r = 0; r < 4; ++r) {
            const __m512 v = _mm512_add_ps(
                _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(c[0][r], px), _mm512_mul_ps(c[1][r], py)),
                              _mm512_mul_ps(c[2][r], pz)),
                c[3][r]);
            _mm512_storeu_ps(out[r] + i, v);
        }
    }
    transformPointsTail(positions + i, n - i, M, x + i, y + i, z + i, w + i);
}

void specularPowN(const float* x, std::size_t n, float s, float* out) {
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16)
        _mm512_storeu_ps(out + i, specularPow16(_mm512_loadu_ps(x + i), s));
    specularPowTail(x + i, n - i, s, out + i);
}

}  // namespace avx512

}  // namespace mvr::raster::detail
