// AVX-512 kernels (F/BW/VL/DQ; -ffp-contract=off). Same operations and order as the scalar loops
// in kernels_tail.h.
#include <immintrin.h>

#include "../cpu.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

namespace {

inline __m512i bitIf(__mmask16 m, int bit) {
    return _mm512_maskz_mov_epi32(m, _mm512_set1_epi32(bit));
}
inline __m512i snap(__m512 v, __m512 q, __m512 size) {
    const __m512 half = _mm512_set1_ps(0.5f);
    __m512 t = _mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(v, q), half), half);
    t = _mm512_mul_ps(_mm512_mul_ps(t, size), _mm512_set1_ps(float(kSubpixel)));
    return _mm512_cvtps_epi32(t);  // MXCSR: round to nearest even, as lrintf
}

void projectYZW(const float* y, const float* z, const float* w, std::size_t n, float height,
                std::uint8_t* code, float* q, std::int32_t* sy, float* zw) {
    const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f),
                 half = _mm512_set1_ps(0.5f);
    const __m512 gb = _mm512_set1_ps(kGuardBand), ngb = _mm512_set1_ps(-kGuardBand);
    const __m512 h = _mm512_set1_ps(height);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        const __m512 Y = _mm512_loadu_ps(y + i), Z = _mm512_loadu_ps(z + i),
                     W = _mm512_loadu_ps(w + i);
        const __m512 nW = _mm512_castsi512_ps(
            _mm512_xor_si512(_mm512_castps_si512(W), _mm512_set1_epi32(std::int32_t(0x80000000u))));
        __m512i c = bitIf(_mm512_cmp_ps_mask(Z, nW, _CMP_LT_OQ), kClipNear);
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Z, W, _CMP_GT_OQ), kClipFar));
        c = _mm512_or_si512(
            c, bitIf(_mm512_cmp_ps_mask(Y, _mm512_mul_ps(ngb, W), _CMP_LT_OQ), kClipBottom));
        c = _mm512_or_si512(
            c, bitIf(_mm512_cmp_ps_mask(Y, _mm512_mul_ps(gb, W), _CMP_GT_OQ), kClipTop));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, nW, _CMP_LT_OQ), kOutBottom));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, W, _CMP_GT_OQ), kOutTop));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(W, zero, _CMP_NGT_UQ), kClipNear));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(code + i), _mm512_cvtepi32_epi8(c));
        const __m512 Q = _mm512_div_ps(one, W);
        _mm512_storeu_ps(q + i, Q);
        const __mmask16 ok = _mm512_testn_epi32_mask(c, _mm512_set1_epi32(kClipYZW));
        _mm512_storeu_si512(sy + i, _mm512_maskz_mov_epi32(ok, snap(Y, Q, h)));
        __m512 d = _mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(Z, Q), half), half);
        d = _mm512_mask_mov_ps(d, _mm512_cmp_ps_mask(d, zero, _CMP_LT_OQ),
                               zero);  // std::clamp order
        d = _mm512_mask_mov_ps(d, _mm512_cmp_ps_mask(one, d, _CMP_LT_OQ), one);
        _mm512_storeu_ps(zw + i, d);
    }
    projectYZWTail(y + i, z + i, w + i, n - i, height, code + i, q + i, sy + i, zw + i);
}

void projectX(const float* x, const float* w, const float* q, std::size_t n, float width,
              std::uint8_t* code, std::int32_t* sx) {
    const __m512 gb = _mm512_set1_ps(kGuardBand), ngb = _mm512_set1_ps(-kGuardBand);
    const __m512 wd = _mm512_set1_ps(width);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        const __m512 X = _mm512_loadu_ps(x + i), W = _mm512_loadu_ps(w + i);
        const __m512 nW = _mm512_castsi512_ps(
            _mm512_xor_si512(_mm512_castps_si512(W), _mm512_set1_epi32(std::int32_t(0x80000000u))));
        __m512i c = bitIf(_mm512_cmp_ps_mask(X, _mm512_mul_ps(ngb, W), _CMP_LT_OQ), kClipLeft);
        c = _mm512_or_si512(
            c, bitIf(_mm512_cmp_ps_mask(X, _mm512_mul_ps(gb, W), _CMP_GT_OQ), kClipRight));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(X, nW, _CMP_LT_OQ), kOutLeft));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(X, W, _CMP_GT_OQ), kOutRight));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(code + i), _mm512_cvtepi32_epi8(c));
        const __mmask16 ok = _mm512_testn_epi32_mask(c, _mm512_set1_epi32(kClipX));
        _mm512_storeu_si512(sx + i,
                            _mm512_maskz_mov_epi32(ok, snap(X, _mm512_loadu_ps(q + i), wd)));
    }
    projectXTail(x + i, w + i, q + i, n - i, width, code + i, sx + i);
}

/// The coverage setup of 16 lanes — setupViewsTail's integer operations — from each lane's snapped
/// x of the three vertices, snapped y and row range (broadcast by setupViews: one triangle's
/// views; loaded per lane by setupLanes: (triangle, view) pairs). Writes columns [k, k + 16) of
/// `o` (whole registers: lanes past the live ones are never read) and returns the live lanes
/// whose mask is not 0.
inline std::uint32_t setupCore(__m512i X0, __m512i X1, __m512i X2, const __m512i Y[3],
                               __m512i rowMin, __m512i rowMax, __mmask16 live, int width,
                               ViewsSetup& o, int k) {
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
    const __m512i half = _mm512_set1_epi32(kHalfSubpixel);
    const __mmask16 tall = _mm512_cmpgt_epi32_mask(rowMax, rowMin);
    const __m512i span = _mm512_set1_epi32(kSmallSpan);
    const __m512i ylo = _mm512_min_epi32(Y[0], _mm512_min_epi32(Y[1], Y[2]));
    const __m512i yhi = _mm512_max_epi32(Y[0], _mm512_max_epi32(Y[1], Y[2]));
    const __mmask16 rowsSmall = _mm512_cmple_epi32_mask(_mm512_sub_epi32(rowMax, rowMin), one) &
                                _mm512_cmplt_epi32_mask(_mm512_sub_epi32(yhi, ylo), span);
    const __m512i py0 = _mm512_add_epi32(_mm512_slli_epi32(rowMin, kSubpixelBits), half);
    const __m512i yr[3] = {_mm512_sub_epi32(Y[0], py0), _mm512_sub_epi32(Y[1], py0),
                           _mm512_sub_epi32(Y[2], py0)};
    // setupY's Δy: dy[0] = y2 − y1, dy[1] = y0 − y2, dy[2] = y1 − y0.
    const __m512i dyShared[3] = {_mm512_sub_epi32(Y[2], Y[1]), _mm512_sub_epi32(Y[0], Y[2]),
                                 _mm512_sub_epi32(Y[1], Y[0])};
    const __m512i yr20 = _mm512_sub_epi32(yr[2], yr[0]);
    const __m512i xlo = _mm512_min_epi32(X0, _mm512_min_epi32(X1, X2));
    const __m512i xhi = _mm512_max_epi32(X0, _mm512_max_epi32(X1, X2));
    const __m512i colMin = _mm512_max_epi32(
        zero, _mm512_srai_epi32(
                  _mm512_add_epi32(_mm512_sub_epi32(xlo, half), _mm512_set1_epi32(kSubpixel - 1)),
                  kSubpixelBits));
    const __m512i colMax =
        _mm512_min_epi32(_mm512_set1_epi32(width - 1),
                         _mm512_srai_epi32(_mm512_sub_epi32(xhi, half), kSubpixelBits));
    const __mmask16 empty = _mm512_cmpgt_epi32_mask(colMin, colMax);
    const __m512i cols = _mm512_sub_epi32(colMax, colMin);
    const __mmask16 small =
        __mmask16(rowsSmall & _mm512_cmple_epi32_mask(cols, one) &
                  _mm512_cmplt_epi32_mask(_mm512_sub_epi32(xhi, xlo), span) & ~empty);
    const __m512i px0 = _mm512_add_epi32(_mm512_slli_epi32(colMin, kSubpixelBits), half);
    const __m512i xr[3] = {_mm512_sub_epi32(X0, px0), _mm512_sub_epi32(X1, px0),
                           _mm512_sub_epi32(X2, px0)};
    __m512i dx[3] = {_mm512_sub_epi32(xr[2], xr[1]), _mm512_sub_epi32(xr[0], xr[2]),
                     _mm512_sub_epi32(xr[1], xr[0])};
    __m512i area =
        _mm512_sub_epi32(_mm512_mullo_epi32(dx[2], yr20),
                         _mm512_mullo_epi32(dyShared[2], _mm512_sub_epi32(xr[2], xr[0])));
    const __m512i flip = _mm512_srai_epi32(area, 31);
    area = _mm512_sub_epi32(_mm512_xor_si512(area, flip), flip);
    __m512i any[4] = {zero, zero, zero, zero};
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        dx[i] = _mm512_sub_epi32(_mm512_xor_si512(dx[i], flip), flip);
        const __m512i dy = _mm512_sub_epi32(_mm512_xor_si512(dyShared[i], flip), flip);
        const __mmask16 tl =
            _mm512_cmplt_epi32_mask(dy, zero) |
            (_mm512_cmpeq_epi32_mask(dy, zero) & _mm512_cmplt_epi32_mask(dx[i], zero));
        const __m512i bias = _mm512_maskz_mov_epi32(tl, one);
        const __m512i e = _mm512_add_epi32(
            _mm512_sub_epi32(_mm512_mullo_epi32(dy, xr[a]), _mm512_mullo_epi32(dx[i], yr[a])),
            bias);
        const __m512i sx = _mm512_slli_epi32(_mm512_sub_epi32(zero, dy), kSubpixelBits);
        const __m512i sy = _mm512_slli_epi32(dx[i], kSubpixelBits);
        _mm512_storeu_si512(o.e[i] + k, e);
        _mm512_storeu_si512(o.sx[i] + k, sx);
        _mm512_storeu_si512(o.sy[i] + k, sy);
        _mm512_storeu_si512(o.bias[i] + k, bias);
        const __m512i em1 = _mm512_sub_epi32(e, one);
        any[0] = _mm512_or_si512(any[0], em1);
        any[1] = _mm512_or_si512(any[1], _mm512_add_epi32(em1, sx));
        any[2] = _mm512_or_si512(any[2], _mm512_add_epi32(em1, sy));
        any[3] = _mm512_or_si512(any[3], _mm512_add_epi32(_mm512_add_epi32(em1, sx), sy));
    }
    const __mmask16 wide = _mm512_cmpgt_epi32_mask(colMax, colMin);
    __m512i mask = zero;
    for (int j = 0; j < 4; ++j) {
        const __mmask16 valid = j == 0   ? __mmask16(0xffff)
                                : j == 1 ? wide
                                : j == 2 ? tall
                                         : __mmask16(tall & wide);
        const __mmask16 in = _mm512_cmpge_epi32_mask(any[j], zero) & valid;
        mask = _mm512_mask_or_epi32(mask, in, mask, _mm512_set1_epi32(1 << j));
    }
    mask = _mm512_maskz_mov_epi32(_mm512_cmpneq_epi32_mask(area, zero), mask);
    mask = _mm512_mask_mov_epi32(mask, __mmask16(~small & ~empty), _mm512_set1_epi32(-1));
    mask = _mm512_maskz_mov_epi32(__mmask16(~empty), mask);
    _mm512_storeu_si512(o.mask + k, mask);
    _mm512_storeu_si512(o.colMin + k, colMin);
    _mm512_storeu_si512(o.area + k, area);
    return std::uint32_t(_mm512_test_epi32_mask(mask, mask) & live);
}

/// setupViews, 16 views per pass (the scalar reference: setupViewsTail).
std::uint64_t setupViews(const YSetup& ys, const std::int32_t* x0, const std::int32_t* x1,
                         const std::int32_t* x2, int n, int width, ViewsSetup& o) {
    static_assert(kMaxViews % 16 == 0);
    const __m512i Y[3] = {_mm512_set1_epi32(ys.y[0]), _mm512_set1_epi32(ys.y[1]),
                          _mm512_set1_epi32(ys.y[2])};
    const __m512i rowMin = _mm512_set1_epi32(ys.rowMin), rowMax = _mm512_set1_epi32(ys.rowMax);
    std::uint64_t lanes = 0;
    for (int k = 0; k < n; k += 16) {
        const __mmask16 live = n - k >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - k)) - 1u);
        lanes |= std::uint64_t(setupCore(
                     _mm512_maskz_loadu_epi32(live, x0 + k), _mm512_maskz_loadu_epi32(live, x1 + k),
                     _mm512_maskz_loadu_epi32(live, x2 + k), Y, rowMin, rowMax, live, width, o, k))
                 << k;
    }
    return lanes;
}

/// setupSheared: x derived 16 views per pass (shearClipWc, snap: the scalar order), the views
/// with a column packed with vpcompressd (register form), then setupCore 16 packed views a pass.
std::uint64_t setupSheared(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                           int width, ViewsSetup& o, ViewsX& xs) {
    const __m512 wd = _mm512_set1_ps(float(width));
    const __m512i half = _mm512_set1_epi32(kHalfSubpixel);
    const __m512 cx[3] = {_mm512_set1_ps(t.cx[0]), _mm512_set1_ps(t.cx[1]),
                          _mm512_set1_ps(t.cx[2])};
    const __m512 wc[3] = {_mm512_set1_ps(t.wc[0]), _mm512_set1_ps(t.wc[1]),
                          _mm512_set1_ps(t.wc[2])};
    const __m512 q[3] = {_mm512_set1_ps(t.q[0]), _mm512_set1_ps(t.q[1]), _mm512_set1_ps(t.q[2])};
    const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    int m = 0;
    for (int k = 0; k < n; k += 16) {
        const __mmask16 live = n - k >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - k)) - 1u);
        const __m512 s = _mm512_maskz_loadu_ps(live, shears + k);
        __m512i X[3];
        for (int j = 0; j < 3; ++j)
            X[j] = snap(_mm512_add_ps(cx[j], _mm512_mul_ps(s, wc[j])), q[j], wd);
        // A pixel-center column (setupCore's colMin <= colMax)?
        const __m512i xlo = _mm512_min_epi32(X[0], _mm512_min_epi32(X[1], X[2]));
        const __m512i xhi = _mm512_max_epi32(X[0], _mm512_max_epi32(X[1], X[2]));
        const __m512i colMin = _mm512_max_epi32(
            _mm512_setzero_si512(),
            _mm512_srai_epi32(
                _mm512_add_epi32(_mm512_sub_epi32(xlo, half), _mm512_set1_epi32(kSubpixel - 1)),
                kSubpixelBits));
        const __m512i colMax =
            _mm512_min_epi32(_mm512_set1_epi32(width - 1),
                             _mm512_srai_epi32(_mm512_sub_epi32(xhi, half), kSubpixelBits));
        const __mmask16 keep = _mm512_cmple_epi32_mask(colMin, colMax) & live;
        if (!keep) continue;
        for (int j = 0; j < 3; ++j)
            _mm512_storeu_si512(xs.x[j] + m, _mm512_maskz_compress_epi32(keep, X[j]));
        const __m512i idx = _mm512_add_epi32(iota, _mm512_set1_epi32(k));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(xs.view + m),
                         _mm512_cvtepi32_epi8(_mm512_maskz_compress_epi32(keep, idx)));
        m += __builtin_popcount(unsigned(keep));
    }
    const __m512i Y[3] = {_mm512_set1_epi32(ys.y[0]), _mm512_set1_epi32(ys.y[1]),
                          _mm512_set1_epi32(ys.y[2])};
    const __m512i rowMin = _mm512_set1_epi32(ys.rowMin), rowMax = _mm512_set1_epi32(ys.rowMax);
    std::uint64_t lanes = 0;
    for (int i = 0; i < m; i += 16) {
        const __mmask16 live = m - i >= 16 ? __mmask16(0xffff) : __mmask16((1u << (m - i)) - 1u);
        lanes |= std::uint64_t(setupCore(
                     _mm512_loadu_si512(xs.x[0] + i), _mm512_loadu_si512(xs.x[1] + i),
                     _mm512_loadu_si512(xs.x[2] + i), Y, rowMin, rowMax, live, width, o, i))
                 << i;
    }
    return lanes;
}

/// setupLanes: all 16 lanes in one pass.
std::uint32_t setupLanes(TriangleLanes& l, int n, int width) {
    const __mmask16 live = n >= kLaneCount ? __mmask16(0xffff) : __mmask16((1u << n) - 1u);
    const __m512i Y[3] = {_mm512_maskz_loadu_epi32(live, l.y[0]),
                          _mm512_maskz_loadu_epi32(live, l.y[1]),
                          _mm512_maskz_loadu_epi32(live, l.y[2])};
    return setupCore(_mm512_maskz_loadu_epi32(live, l.x[0]), _mm512_maskz_loadu_epi32(live, l.x[1]),
                     _mm512_maskz_loadu_epi32(live, l.x[2]), Y,
                     _mm512_maskz_loadu_epi32(live, l.rowMin),
                     _mm512_maskz_loadu_epi32(live, l.rowMax), live, width, l.out, 0);
}

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
    shadeVerticesTail(positions + i, normals + i, n - i, W, N, ctx, m, color + 3 * i);
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

}  // namespace

const Kernels* avx512Kernels() {
    // shadeLanes and drawSheared: the AVX2 kernels (8 lanes of fragments; their gathers of
    // view pointers serve AVX-512 CPUs too). drawSheared against this table's 16-lane
    // setupSheared + shadeLanes on a Sapphire Rapids host: 100 views 142 -> 104 ms
    // (src/raster/README.md).
    static const Kernels k{&projectYZW,    &projectX,        &setupViews,
                           &shadeVertices, &transformPoints, &specularPowN,
                           &setupLanes,    &setupSheared,    avx2Kernels()->shadeLanes,
                           avx2Kernels()->drawSheared};
    return &k;
}

}  // namespace mvr::raster::detail
