// AVX-512 kernels (F/BW/VL/DQ; -ffp-contract=off). Same operations and order as the scalar loops
// in kernels_tail.h. The vertex-stage kernels (shadeVertices, transformPoints, specularPow) are in
// kernels_avx512_vertex.cpp; avx512Kernels() below is the table of both files.
#include <immintrin.h>

#include <cstddef>

#include "../cpu.h"
#include "kernels_avx512_vertex.h"
#include "kernels_tail.h"
#include "row_span.h"

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

/// rowSnapX: 16 vertices a pass, each view's x as projectX snaps it; a pair interleaved in
/// registers (two permutes), other rows scattered at stride nv.
void rowSnapX(const float* cx, const float* w, const float* q, std::size_t n, const float* shears,
              int nv, float convergence, float width, std::int32_t* sxv) {
    const __m512 gb = _mm512_set1_ps(kGuardBand), ngb = _mm512_set1_ps(-kGuardBand);
    const __m512 wd = _mm512_set1_ps(width), C = _mm512_set1_ps(convergence);
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    // pair: out[2i] = view 0's lane i, out[2i + 1] = view 1's (16 + i in permutex2var's terms)
    const __m512i pairLo =
        _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
    const __m512i pairHi = _mm512_add_epi32(pairLo, _mm512_set1_epi32(8));
    const __m512i strided = _mm512_mullo_epi32(lane, _mm512_set1_epi32(nv));
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        const __m512 X = _mm512_loadu_ps(cx + i), W = _mm512_loadu_ps(w + i),
                     Q = _mm512_loadu_ps(q + i);
        const __m512 wc = _mm512_sub_ps(W, C);
        const __m512 lo = _mm512_mul_ps(ngb, W), hi = _mm512_mul_ps(gb, W);
        auto viewX = [&](float s) {
            const __m512 x = _mm512_add_ps(X, _mm512_mul_ps(_mm512_set1_ps(s), wc));
            const __mmask16 clip = __mmask16(_mm512_cmp_ps_mask(x, lo, _CMP_LT_OQ) |
                                             _mm512_cmp_ps_mask(x, hi, _CMP_GT_OQ));
            return _mm512_maskz_mov_epi32(__mmask16(~clip), snap(x, Q, wd));
        };
        std::int32_t* out = sxv + i * std::size_t(nv);
        if (nv == 2) {
            const __m512i a = viewX(shears[0]), b = viewX(shears[1]);
            _mm512_storeu_si512(out, _mm512_permutex2var_epi32(a, pairLo, b));
            _mm512_storeu_si512(out + 16, _mm512_permutex2var_epi32(a, pairHi, b));
        } else {
            for (int k = 0; k < nv; ++k)
                _mm512_i32scatter_epi32(out + k, strided, viewX(shears[k]), 4);
        }
    }
    rowSnapXTail(cx + i, w + i, q + i, n - i, shears, nv, convergence, width,
                 sxv + i * std::size_t(nv));
}

void rowClipX(const float* cx, const float* w, std::size_t n, float lo, float hi, float convergence,
              std::uint8_t* any) {
    const __m512 gb = _mm512_set1_ps(kGuardBand), ngb = _mm512_set1_ps(-kGuardBand);
    const __m512 L = _mm512_set1_ps(lo), H = _mm512_set1_ps(hi), C = _mm512_set1_ps(convergence);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        const __m512 X = _mm512_loadu_ps(cx + i), W = _mm512_loadu_ps(w + i);
        const __m512 wc = _mm512_sub_ps(W, C);
        const __m512 xl = _mm512_add_ps(X, _mm512_mul_ps(L, wc));
        const __m512 xh = _mm512_add_ps(X, _mm512_mul_ps(H, wc));
        const __m512 left = _mm512_mul_ps(ngb, W), right = _mm512_mul_ps(gb, W);
        const __m512i c = _mm512_or_si512(bitIf(_mm512_cmp_ps_mask(xl, left, _CMP_LT_OQ) |
                                                    _mm512_cmp_ps_mask(xh, left, _CMP_LT_OQ),
                                                kClipLeft),
                                          bitIf(_mm512_cmp_ps_mask(xl, right, _CMP_GT_OQ) |
                                                    _mm512_cmp_ps_mask(xh, right, _CMP_GT_OQ),
                                                kClipRight));
        __m128i* out = reinterpret_cast<__m128i*>(any + i);
        _mm_storeu_si128(out, _mm_or_si128(_mm_loadu_si128(out), _mm512_cvtepi32_epi8(c)));
    }
    rowClipXTail(cx + i, w + i, n - i, lo, hi, convergence, any + i);
}

inline __mmask16 liveMask(int n, int k) {
    return n - k >= 16 ? __mmask16(0xffff) : __mmask16((1u << (n - k)) - 1u);
}

/// The x extent's pixel-center columns of 16 lanes (setupViewsTail's colMin / colMax).
inline void columnRange(__m512i xlo, __m512i xhi, int width, __m512i& colMin, __m512i& colMax) {
    const __m512i half = _mm512_set1_epi32(kHalfSubpixel);
    colMin = _mm512_max_epi32(_mm512_setzero_si512(),
                              _mm512_srai_epi32(_mm512_add_epi32(_mm512_sub_epi32(xlo, half),
                                                                 _mm512_set1_epi32(kSubpixel - 1)),
                                                kSubpixelBits));
    colMax = _mm512_min_epi32(_mm512_set1_epi32(width - 1),
                              _mm512_srai_epi32(_mm512_sub_epi32(xhi, half), kSubpixelBits));
}

/// setupCore's results for 16 lanes, in registers (drawSheared shades from them directly).
struct Cover16 {
    __m512i mask, colMin, area, e[3], sx[3], sy[3], bias[3];
};

/// setupCore's operations without the stores. OneRow: every lane's rowMax == rowMin (sy is not
/// computed: no lane has a second row of centers).
template <bool OneRow>
inline Cover16 cover16(__m512i X0, __m512i X1, __m512i X2, const __m512i Y[3], __m512i rowMin,
                       __m512i rowMax, int width) {
    Cover16 c{};
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
    const __m512i dyShared[3] = {_mm512_sub_epi32(Y[2], Y[1]), _mm512_sub_epi32(Y[0], Y[2]),
                                 _mm512_sub_epi32(Y[1], Y[0])};
    const __m512i yr20 = _mm512_sub_epi32(yr[2], yr[0]);
    const __m512i xlo = _mm512_min_epi32(X0, _mm512_min_epi32(X1, X2));
    const __m512i xhi = _mm512_max_epi32(X0, _mm512_max_epi32(X1, X2));
    __m512i colMax;
    columnRange(xlo, xhi, width, c.colMin, colMax);
    const __mmask16 empty = _mm512_cmpgt_epi32_mask(c.colMin, colMax);
    const __m512i cols = _mm512_sub_epi32(colMax, c.colMin);
    const __mmask16 small =
        __mmask16(rowsSmall & _mm512_cmple_epi32_mask(cols, one) &
                  _mm512_cmplt_epi32_mask(_mm512_sub_epi32(xhi, xlo), span) & ~empty);
    const __m512i px0 = _mm512_add_epi32(_mm512_slli_epi32(c.colMin, kSubpixelBits), half);
    const __m512i xr[3] = {_mm512_sub_epi32(X0, px0), _mm512_sub_epi32(X1, px0),
                           _mm512_sub_epi32(X2, px0)};
    __m512i dx[3] = {_mm512_sub_epi32(xr[2], xr[1]), _mm512_sub_epi32(xr[0], xr[2]),
                     _mm512_sub_epi32(xr[1], xr[0])};
    __m512i area =
        _mm512_sub_epi32(_mm512_mullo_epi32(dx[2], yr20),
                         _mm512_mullo_epi32(dyShared[2], _mm512_sub_epi32(xr[2], xr[0])));
    const __m512i flip = _mm512_srai_epi32(area, 31);
    c.area = _mm512_sub_epi32(_mm512_xor_si512(area, flip), flip);
    __m512i any[4] = {zero, zero, zero, zero};
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        dx[i] = _mm512_sub_epi32(_mm512_xor_si512(dx[i], flip), flip);
        const __m512i dy = _mm512_sub_epi32(_mm512_xor_si512(dyShared[i], flip), flip);
        const __mmask16 tl =
            _mm512_cmplt_epi32_mask(dy, zero) |
            (_mm512_cmpeq_epi32_mask(dy, zero) & _mm512_cmplt_epi32_mask(dx[i], zero));
        c.bias[i] = _mm512_maskz_mov_epi32(tl, one);
        c.e[i] = _mm512_add_epi32(
            _mm512_sub_epi32(_mm512_mullo_epi32(dy, xr[a]), _mm512_mullo_epi32(dx[i], yr[a])),
            c.bias[i]);
        c.sx[i] = _mm512_slli_epi32(_mm512_sub_epi32(zero, dy), kSubpixelBits);
        const __m512i em1 = _mm512_sub_epi32(c.e[i], one);
        any[0] = _mm512_or_si512(any[0], em1);
        any[1] = _mm512_or_si512(any[1], _mm512_add_epi32(em1, c.sx[i]));
        if constexpr (!OneRow) {
            c.sy[i] = _mm512_slli_epi32(dx[i], kSubpixelBits);
            any[2] = _mm512_or_si512(any[2], _mm512_add_epi32(em1, c.sy[i]));
            any[3] =
                _mm512_or_si512(any[3], _mm512_add_epi32(_mm512_add_epi32(em1, c.sx[i]), c.sy[i]));
        }
    }
    const __mmask16 wide = _mm512_cmpgt_epi32_mask(colMax, c.colMin);
    __m512i mask = zero;
    for (int j = 0; j < (OneRow ? 2 : 4); ++j) {
        const __mmask16 valid = j == 0   ? __mmask16(0xffff)
                                : j == 1 ? wide
                                : j == 2 ? tall
                                         : __mmask16(tall & wide);
        const __mmask16 in = _mm512_cmpge_epi32_mask(any[j], zero) & valid;
        mask = _mm512_mask_or_epi32(mask, in, mask, _mm512_set1_epi32(1 << j));
    }
    mask = _mm512_maskz_mov_epi32(_mm512_cmpneq_epi32_mask(c.area, zero), mask);
    mask = _mm512_mask_mov_epi32(mask, __mmask16(~small & ~empty), _mm512_set1_epi32(-1));
    c.mask = _mm512_maskz_mov_epi32(__mmask16(~empty), mask);
    return c;
}

/// The coverage setup of 16 lanes — setupViewsTail's integer operations — from each lane's snapped
/// x of the three vertices, snapped y and row range (broadcast by setupViews: one triangle's
/// views; loaded per lane by setupLanes: (triangle, view) pairs). Writes columns [k, k + 16) of
/// `o` (whole registers: lanes past the live ones are never read) and returns the live lanes
/// whose mask is not 0.
inline std::uint32_t storeCover(const Cover16& c, __mmask16 live, ViewsSetup& o, int k) {
    for (int i = 0; i < 3; ++i) {
        _mm512_storeu_si512(o.e[i] + k, c.e[i]);
        _mm512_storeu_si512(o.sx[i] + k, c.sx[i]);
        _mm512_storeu_si512(o.sy[i] + k, c.sy[i]);
        _mm512_storeu_si512(o.bias[i] + k, c.bias[i]);
    }
    _mm512_storeu_si512(o.mask + k, c.mask);
    _mm512_storeu_si512(o.colMin + k, c.colMin);
    _mm512_storeu_si512(o.area + k, c.area);
    return std::uint32_t(_mm512_test_epi32_mask(c.mask, c.mask) & live);
}

inline std::uint32_t setupCore(__m512i X0, __m512i X1, __m512i X2, const __m512i Y[3],
                               __m512i rowMin, __m512i rowMax, __mmask16 live, int width,
                               ViewsSetup& o, int k) {
    return storeCover(cover16<false>(X0, X1, X2, Y, rowMin, rowMax, width), live, o, k);
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
        const __mmask16 live = liveMask(n, k);
        lanes |= std::uint64_t(setupCore(
                     _mm512_maskz_loadu_epi32(live, x0 + k), _mm512_maskz_loadu_epi32(live, x1 + k),
                     _mm512_maskz_loadu_epi32(live, x2 + k), Y, rowMin, rowMax, live, width, o, k))
                 << k;
    }
    return lanes;
}

/// A sheared row's snapped x per view from its shear s (setupSheared's operations).
struct ShearX16 {
    __m512 cx[3], wc[3], q[3], wd;
    ShearX16(const ShearedTri& t, int width) : wd(_mm512_set1_ps(float(width))) {
        for (int j = 0; j < 3; ++j) {
            cx[j] = _mm512_set1_ps(t.cx[j]);
            wc[j] = _mm512_set1_ps(t.wc[j]);
            q[j] = _mm512_set1_ps(t.q[j]);
        }
    }
    void operator()(__m512 s, __m512i X[3]) const {
        for (int j = 0; j < 3; ++j)
            X[j] = snap(_mm512_add_ps(cx[j], _mm512_mul_ps(s, wc[j])), q[j], wd);
    }
};

inline std::uint32_t culledBits(const std::uint64_t* culled, int k) {
    return culled ? std::uint32_t(culled[k >> 6] >> (k & 63)) & 0xffffu : 0u;
}

/// The first `count` lanes of v stored at p (a masked store: nothing past them is written).
inline void storeFirst(std::int32_t* p, int count, __m512i v) {
    _mm512_mask_storeu_epi32(p, __mmask16((1u << count) - 1u), v);
}

/// The positions k + lane of the lanes of `keep`, as bytes at view[0, popcount) (16 written).
inline void packViews16(__mmask16 keep, int k, std::uint8_t* view) {
    const __m512i idx =
        _mm512_add_epi32(_mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
                         _mm512_set1_epi32(k));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(view),
                     _mm512_cvtepi32_epi8(_mm512_maskz_compress_epi32(keep, idx)));
}

/// The AVX2 packSheared with 16 lanes: the views with a pixel-center column and not culled,
/// their x packed in view order into xs.
inline int packSheared16(const ShearedTri& t, const float* shears, int n,
                         const std::uint64_t* culled, int width, ViewsX& xs) {
    const ShearX16 deriveX(t, width);
    int m = 0;
    for (int k = 0; k < n; k += 16) {
        const __mmask16 live = liveMask(n, k);
        __m512i X[3];
        deriveX(_mm512_maskz_loadu_ps(live, shears + k), X);
        __m512i colMin, colMax;
        columnRange(_mm512_min_epi32(X[0], _mm512_min_epi32(X[1], X[2])),
                    _mm512_max_epi32(X[0], _mm512_max_epi32(X[1], X[2])), width, colMin, colMax);
        const __mmask16 keep =
            __mmask16(_mm512_cmple_epi32_mask(colMin, colMax) & live & ~culledBits(culled, k));
        if (!keep) continue;
        const int count = __builtin_popcount(unsigned(keep));
        for (int j = 0; j < 3; ++j)
            storeFirst(xs.x[j] + m, count, _mm512_maskz_compress_epi32(keep, X[j]));
        packViews16(keep, k, xs.view + m);
        m += count;
    }
    return m;
}

/// setupSheared: x derived 16 views per pass and the views with a column packed
/// (packSheared16), then setupCore 16 packed views a pass.
std::uint64_t setupSheared(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                           int width, ViewsSetup& o, ViewsX& xs) {
    const int m = packSheared16(t, shears, n, nullptr, width, xs);
    const __m512i Y[3] = {_mm512_set1_epi32(ys.y[0]), _mm512_set1_epi32(ys.y[1]),
                          _mm512_set1_epi32(ys.y[2])};
    const __m512i rowMin = _mm512_set1_epi32(ys.rowMin), rowMax = _mm512_set1_epi32(ys.rowMax);
    std::uint64_t lanes = 0;
    for (int i = 0; i < m; i += 16) {
        const __mmask16 live = liveMask(m, i);
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

/// FragmentSink's Vertex color of 16 fragments: the vertex colors a[j][channel] interpolated
/// perspective-correctly from the screen barycentrics l and the vertices' 1/w q, packed as
/// packColor packs them.
inline __m512i vertexColor16(const __m512 l[3], const __m512 q[3], const __m512 a[3][3]) {
    const __m512 fzero = _mm512_setzero_ps(), fone = _mm512_set1_ps(1.0f);
    const __m512 p0 = _mm512_mul_ps(l[0], q[0]), p1 = _mm512_mul_ps(l[1], q[1]),
                 p2 = _mm512_mul_ps(l[2], q[2]);
    const __m512 inv = _mm512_div_ps(fone, _mm512_add_ps(_mm512_add_ps(p0, p1), p2));
    __m512i packed = _mm512_set1_epi32(std::int32_t(0xff000000u));
    for (int ch = 0; ch < 3; ++ch) {
        const __m512 v = _mm512_mul_ps(
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(p0, a[0][ch]), _mm512_mul_ps(p1, a[1][ch])),
                          _mm512_mul_ps(p2, a[2][ch])),
            inv);
        // quantizeUnorm8: std::clamp(v, 0, 1) · 255 + 0.5, truncated to 8 bits.
        __m512 t = _mm512_mask_mov_ps(v, _mm512_cmp_ps_mask(v, fzero, _CMP_LT_OQ), fzero);
        t = _mm512_mask_mov_ps(t, _mm512_cmp_ps_mask(fone, t, _CMP_LT_OQ), fone);
        t = _mm512_add_ps(_mm512_mul_ps(t, _mm512_set1_ps(255.0f)), _mm512_set1_ps(0.5f));
        const __m512i u = _mm512_and_si512(_mm512_cvttps_epi32(t), _mm512_set1_epi32(0xff));
        packed = _mm512_or_si512(packed, _mm512_slli_epi32(u, 8 * ch));
    }
    return packed;
}

/// drawLanes (lanes.h): cover16 of the 16 lanes, then the covered centres a pass per centre
/// (a lane's lowest remaining one), with shadeGroup16's operations; a lane's depth, 1/w and flat
/// color gathered from its slot's FragmentTri, its vertex colors picked from its slot's column
/// of SlotColors in registers or read lane by lane. The passes write in another order than the
/// queue's walk (lane by lane): they run only when no two fragments share a pixel, which one
/// conflict detection over every pass's offsets checks first; otherwise the setup is stored
/// for the walk (setupLanes' stores) and its lanes returned.
__attribute__((target("avx512cd"))) std::uint32_t drawLanes(
    TriangleLanes& l, int n, int width, const std::uint8_t* laneSlot, const std::uint8_t* laneView,
    const SlotColors& s, const FragmentTri* slotFrag, bool flat, const LaneImages& img) {
    const __mmask16 live = n >= kLaneCount ? __mmask16(0xffff) : __mmask16((1u << n) - 1u);
    const __m512i Y[3] = {_mm512_maskz_loadu_epi32(live, l.y[0]),
                          _mm512_maskz_loadu_epi32(live, l.y[1]),
                          _mm512_maskz_loadu_epi32(live, l.y[2])};
    const __m512i rowMin = _mm512_maskz_loadu_epi32(live, l.rowMin);
    const Cover16 c = cover16<false>(_mm512_maskz_loadu_epi32(live, l.x[0]),
                                     _mm512_maskz_loadu_epi32(live, l.x[1]),
                                     _mm512_maskz_loadu_epi32(live, l.x[2]), Y, rowMin,
                                     _mm512_maskz_loadu_epi32(live, l.rowMax), width);
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
    // The ordered walk's lanes, their setup stored as setupLanes stores it.
    auto walk = [&] { return storeCover(c, live, l.out, 0); };
    if (_mm512_mask_cmplt_epi32_mask(live, c.mask, zero)) return walk();  // a general walk
    __m512i rem = _mm512_maskz_mov_epi32(live, c.mask);
    if (!_mm512_test_epi32_mask(rem, rem)) return kLanesDrawn;  // nothing covered
    // Each pass's pixel offsets; every pass's live offsets side by side in `all`, the rest
    // distinct negative values (conflict detection compares every lane).
    const __m512i W = _mm512_set1_epi32(width);
    const __m512i views =
        _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(laneView)));
    const __m512i base =
        _mm512_add_epi32(_mm512_mullo_epi32(views, _mm512_set1_epi32(img.viewStride)),
                         _mm512_set1_epi32(img.origin));
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    __m512i all = _mm512_sub_epi32(_mm512_set1_epi32(-1), lane);
    __m512i off[4];
    __mmask16 act[4], right[4], up[4];  // per pass: its lanes, and which centre of the 2×2
    int passes = 0, count = 0;
    for (__mmask16 todo = _mm512_test_epi32_mask(rem, rem); todo;
         todo = _mm512_test_epi32_mask(rem, rem)) {
        const __m512i lo = _mm512_and_si512(rem, _mm512_sub_epi32(zero, rem));
        rem = _mm512_xor_si512(rem, lo);
        const __mmask16 cx = _mm512_test_epi32_mask(lo, _mm512_set1_epi32(0xA));
        const __mmask16 cy = _mm512_test_epi32_mask(lo, _mm512_set1_epi32(0xC));
        const __m512i x = _mm512_mask_add_epi32(c.colMin, cx, c.colMin, one);
        const __m512i row = _mm512_mask_add_epi32(rowMin, cy, rowMin, one);
        const __m512i o = _mm512_add_epi32(_mm512_sub_epi32(base, _mm512_mullo_epi32(row, W)), x);
        const int k = __builtin_popcount(unsigned(todo));
        if (count + k > 16) return walk();
        all = _mm512_mask_expand_epi32(all, __mmask16(((1u << k) - 1u) << count),
                                       _mm512_maskz_compress_epi32(todo, o));
        count += k;
        off[passes] = o, act[passes] = todo, right[passes] = cx, up[passes] = cy;
        ++passes;
    }
    const __m512i conflicts = _mm512_conflict_epi32(all);
    if (_mm512_test_epi32_mask(conflicts, conflicts)) return walk();
    // No two fragments share a pixel: the passes' order does not matter.
    const __m512i slots =
        _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(laneSlot)));
    __m512 z[3];
    // A lane's slot inputs gathered from the slots' FragmentTri (64 bytes each: 16 floats).
    static_assert(sizeof(FragmentTri) == 16 * sizeof(float));
    const float* tris = reinterpret_cast<const float*>(slotFrag);
    const __m512i slot16 = _mm512_slli_epi32(slots, 4);
    auto slotField = [&](std::size_t offset) {
        return _mm512_i32gather_ps(
            _mm512_add_epi32(slot16, _mm512_set1_epi32(std::int32_t(offset / sizeof(float)))), tris,
            4);
    };
    for (int j = 0; j < 3; ++j) z[j] = slotField(offsetof(FragmentTri, z) + j * sizeof(float));
    const __m512 fzero = _mm512_setzero_ps(), fone = _mm512_set1_ps(1.0f);
    const __m512 invArea = _mm512_div_ps(fone, _mm512_cvtepi32_ps(c.area));
    __m512 q[3], a[3][3];
    for (auto& aj : a)
        for (auto& ac : aj) ac = fzero;
    unsigned colorsRead = 0;
    __m512i flatColor = zero;
    bool haveInputs = false;
    for (int p = 0; p < passes; ++p) {
        const __mmask16 cx = right[p], cy = up[p];
        __m512 lb[3];
        for (int i = 0; i < 3; ++i) {
            __m512i ei = _mm512_mask_add_epi32(c.e[i], cx, c.e[i], c.sx[i]);
            ei = _mm512_mask_add_epi32(ei, cy, ei, c.sy[i]);
            ei = _mm512_sub_epi32(ei, c.bias[i]);
            lb[i] = _mm512_mul_ps(_mm512_cvtepi32_ps(ei), invArea);
        }
        const __m512 zf =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(lb[0], z[0]), _mm512_mul_ps(lb[1], z[1])),
                          _mm512_mul_ps(lb[2], z[2]));
        const __m512 d = _mm512_mask_i32gather_ps(fzero, act[p], off[p], img.depth, 4);
        const __mmask16 pass = _mm512_mask_cmp_ps_mask(act[p], zf, d, _CMP_LT_OQ);
        if (!pass) continue;
        if (!haveInputs) {
            haveInputs = true;
            if (flat) {
                flatColor = _mm512_castps_si512(slotField(offsetof(FragmentTri, flat)));
            } else {
                for (int j = 0; j < 3; ++j)
                    q[j] = slotField(offsetof(FragmentTri, q) + j * sizeof(float));
            }
        }
        if (!flat) {
            // The vertex colors of the passing lanes not read yet: by component at queue time
            // (s.colors), or lane by lane from the slots' FragmentTri.
            if (s.colors) {
                if (!colorsRead)
                    for (int j = 0; j < 3; ++j)
                        for (int ch = 0; ch < 3; ++ch)
                            a[j][ch] = _mm512_permutexvar_ps(slots, _mm512_load_ps(s.a[j][ch]));
                colorsRead = 1;
            } else {
                for (unsigned k = pass & ~colorsRead; k; k &= k - 1) {
                    const int lk = __builtin_ctz(k);
                    const __mmask16 bit = __mmask16(1u << lk);
                    const FragmentTri& t = slotFrag[laneSlot[lk]];
                    for (int j = 0; j < 3; ++j)
                        for (int ch = 0; ch < 3; ++ch)
                            a[j][ch] = _mm512_mask_broadcastss_ps(a[j][ch], bit,
                                                                  _mm_load_ss(t.attr[j] + ch));
                }
                colorsRead |= pass;
            }
        }
        const __m512i packed = flat ? flatColor : vertexColor16(lb, q, a);
        _mm512_mask_i32scatter_ps(img.depth, pass, off[p], zf, 4);
        _mm512_mask_i32scatter_epi32(img.color, pass, off[p], packed, 4);
    }
    return kLanesDrawn;
}

/// The AVX2 packOnRow with 16 lanes (the same estimate of each view's span on the row's
/// center line, the same slack): the shears of the views that may cover a center of the row
/// into ps, their positions into xs.view.
template <bool Culled>
inline int packOnRow16(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                       const std::uint64_t* culled, int width, float* ps, ViewsX& xs) {
    RowSpan r;
    if (!rowSpan(ys, t, width, r)) return 0;
    const __m512 slack0 = _mm512_set1_ps(r.slack0), slack1 = _mm512_set1_ps(r.slack1);
    const __m512 A[3] = {_mm512_set1_ps(lane<0>(r.pa)), _mm512_set1_ps(lane<1>(r.pa)),
                         _mm512_set1_ps(lane<2>(r.pa))};
    const __m512 B[3] = {_mm512_set1_ps(lane<0>(r.pb)), _mm512_set1_ps(lane<1>(r.pb)),
                         _mm512_set1_ps(lane<2>(r.pb))};
    const __m512 zero = _mm512_setzero_ps(), lastCol = _mm512_set1_ps(float(width - 1));
    int m = 0;
    for (int k = 0; k < n; k += 16) {
        const __mmask16 live = liveMask(n, k);
        const __m512 s = _mm512_maskz_loadu_ps(live, shears + k);
        const __m512 e0 = _mm512_fmadd_ps(s, B[0], A[0]), e1 = _mm512_fmadd_ps(s, B[1], A[1]),
                     e2 = _mm512_fmadd_ps(s, B[2], A[2]);
        const __m512 slack = _mm512_fmadd_ps(_mm512_abs_ps(s), slack1, slack0);
        const __m512 lo =
            _mm512_max_ps(zero, _mm512_sub_ps(_mm512_min_ps(e0, _mm512_min_ps(e1, e2)), slack));
        const __m512 c = _mm512_min_ps(
            lastCol,
            _mm512_roundscale_ps(_mm512_add_ps(_mm512_max_ps(e0, _mm512_max_ps(e1, e2)), slack),
                                 _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
        __mmask16 keep = _mm512_cmp_ps_mask(lo, c, _CMP_LE_OQ) & live;
        if constexpr (Culled) keep &= __mmask16(~culledBits(culled, k));
        // No branch on an empty group (whether a group keeps a view follows no pattern: a
        // mispredicted branch cost more than the stores; single thread, 100 views 157.5 ->
        // 152.2 ms): nothing is kept, m does not move, the next group overwrites the stores.
        _mm512_storeu_ps(ps + m, _mm512_maskz_compress_ps(keep, s));
        packViews16(keep, k, xs.view + m);
        m += __builtin_popcount(unsigned(keep));
    }
    return m;
}

/// A triangle's fragment inputs broadcast to 16 lanes.
struct LaneFragment16 {
    __m512 z[3], q[3], a[3][3];
    __m512i flatColor, top, W;
    bool flat;
};

inline LaneFragment16 laneFragment16(const FragmentTri& tri, bool flat, int rowMin, int width,
                                     int height) {
    LaneFragment16 f;
    for (int j = 0; j < 3; ++j) {
        f.z[j] = _mm512_set1_ps(tri.z[j]);
        f.q[j] = _mm512_set1_ps(tri.q[j]);
        for (int c = 0; c < 3; ++c) f.a[j][c] = _mm512_set1_ps(flat ? 0.0f : tri.attr[j][c]);
    }
    f.flatColor = _mm512_set1_epi32(std::int32_t(tri.flat));
    f.top = _mm512_set1_epi32(height - 1 - rowMin), f.W = _mm512_set1_epi32(width);
    f.flat = flat;
    return f;
}

/// The AVX2 shadeGroup with 16 lanes: per pass the lowest covered center of every lane,
/// FragmentSink's operations, the depth gathered from each lane's view (masked: only the live
/// lanes' slots are read), the passing fragments scattered into their views (scatter against
/// the AVX2 kernel's store loop: 45 views 49.9 -> 47.4 ms, 100 views 84.0 -> 80.4 ms).
template <bool OneRow, bool Block>
inline void shadeGroup16(const LaneFragment16& f, const Cover16& c, __m512i rem, __mmask16 live,
                         const std::uint8_t* slot, float* const* depth, std::uint32_t* const* color,
                         std::int32_t blockStride) {
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
    const __m512 fzero = _mm512_setzero_ps(), fone = _mm512_set1_ps(1.0f);
    const __m512i slots =
        _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(slot)));
    // Block: a lane's pixel is at a 32-bit offset from depth[0] / color[0] (its slot's image at
    // slot · blockStride; 16 lanes per gather and scatter). Otherwise the views' addresses are
    // gathered from the tables (64-bit, 8 lanes per gather and scatter).
    __m512i dLo = zero, dHi = zero, cLo = zero, cHi = zero, block = zero;
    if constexpr (Block) {
        block = _mm512_mullo_epi32(slots, _mm512_set1_epi32(blockStride));
    } else {
        const auto* depthTable = reinterpret_cast<const long long*>(depth);
        dLo = _mm512_mask_i32gather_epi64(zero, __mmask8(live), _mm512_castsi512_si256(slots),
                                          depthTable, 8);
        dHi = _mm512_mask_i32gather_epi64(zero, __mmask8(live >> 8),
                                          _mm512_extracti64x4_epi64(slots, 1), depthTable, 8);
        const auto* colorTable = reinterpret_cast<const long long*>(color);
        cLo = _mm512_mask_i32gather_epi64(zero, __mmask8(live), _mm512_castsi512_si256(slots),
                                          colorTable, 8);
        cHi = _mm512_mask_i32gather_epi64(zero, __mmask8(live >> 8),
                                          _mm512_extracti64x4_epi64(slots, 1), colorTable, 8);
    }
    const __m512 invArea = _mm512_div_ps(fone, _mm512_cvtepi32_ps(c.area));
    for (__mmask16 todo = _mm512_test_epi32_mask(rem, rem); todo;
         todo = _mm512_test_epi32_mask(rem, rem)) {
        const __m512i low = _mm512_and_si512(rem, _mm512_sub_epi32(zero, rem));
        rem = _mm512_xor_si512(rem, low);
        const __mmask16 active = todo;  // low > 0 exactly where rem was not 0
        const __mmask16 cx = _mm512_test_epi32_mask(low, _mm512_set1_epi32(0xA));
        const __mmask16 cy =
            OneRow ? __mmask16(0) : _mm512_test_epi32_mask(low, _mm512_set1_epi32(0xC));
        __m512 l[3];
        for (int i = 0; i < 3; ++i) {
            __m512i ei = _mm512_mask_add_epi32(c.e[i], cx, c.e[i], c.sx[i]);
            if constexpr (!OneRow) ei = _mm512_mask_add_epi32(ei, cy, ei, c.sy[i]);
            ei = _mm512_sub_epi32(ei, c.bias[i]);
            l[i] = _mm512_mul_ps(_mm512_cvtepi32_ps(ei), invArea);
        }
        const __m512 zf =
            _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(l[0], f.z[0]), _mm512_mul_ps(l[1], f.z[1])),
                          _mm512_mul_ps(l[2], f.z[2]));
        const __m512i x = _mm512_mask_add_epi32(c.colMin, cx, c.colMin, one);
        const __m512i index = _mm512_add_epi32(
            _mm512_mullo_epi32(_mm512_mask_sub_epi32(f.top, cy, f.top, one), f.W), x);
        __m512i off = zero, offLo = zero, offHi = zero;
        __m512 d;
        if constexpr (Block) {
            off = _mm512_add_epi32(block, index);
            d = _mm512_mask_i32gather_ps(fzero, active, off, depth[0], 4);
        } else {
            offLo = _mm512_slli_epi64(_mm512_cvtepi32_epi64(_mm512_castsi512_si256(index)), 2);
            offHi =
                _mm512_slli_epi64(_mm512_cvtepi32_epi64(_mm512_extracti64x4_epi64(index, 1)), 2);
            const __m256 gLo = _mm512_mask_i64gather_ps(_mm256_setzero_ps(), __mmask8(active),
                                                        _mm512_add_epi64(dLo, offLo), nullptr, 1);
            const __m256 gHi = _mm512_mask_i64gather_ps(_mm256_setzero_ps(), __mmask8(active >> 8),
                                                        _mm512_add_epi64(dHi, offHi), nullptr, 1);
            d = _mm512_insertf32x8(_mm512_castps256_ps512(gLo), gHi, 1);
        }
        const unsigned pass = _mm512_mask_cmp_ps_mask(active, zf, d, _CMP_LT_OQ);
        if (!pass) continue;
        const __m512i packed = f.flat ? f.flatColor : vertexColor16(l, f.q, f.a);
        // The passing fragments into their lanes' views (distinct images: no two lanes of a
        // group write the same address).
        if constexpr (Block) {
            _mm512_mask_i32scatter_ps(depth[0], __mmask16(pass), off, zf, 4);
            _mm512_mask_i32scatter_epi32(color[0], __mmask16(pass), off, packed, 4);
            continue;
        }
        _mm512_mask_i64scatter_ps(nullptr, __mmask8(pass), _mm512_add_epi64(dLo, offLo),
                                  _mm512_castps512_ps256(zf), 1);
        _mm512_mask_i64scatter_ps(nullptr, __mmask8(pass >> 8), _mm512_add_epi64(dHi, offHi),
                                  _mm512_extractf32x8_ps(zf, 1), 1);
        _mm512_mask_i64scatter_epi32(nullptr, __mmask8(pass), _mm512_add_epi64(cLo, offLo),
                                     _mm512_castsi512_si256(packed), 1);
        _mm512_mask_i64scatter_epi32(nullptr, __mmask8(pass >> 8), _mm512_add_epi64(cHi, offHi),
                                     _mm512_extracti64x4_epi64(packed, 1), 1);
    }
}

/// The AVX2 drawPacked with 16 lanes: per 16 packed views cover16 and shadeGroup16; the views
/// left to the general walk moved to the front of xs.
template <bool OneRow>
int drawPacked16(const YSetup& ys, int m, int width, int height, const FragmentTri& tri, bool flat,
                 float* const* depth, std::uint32_t* const* color, std::int32_t blockStride,
                 ViewsX& xs, const ShearX16* deriveX = nullptr, const float* ps = nullptr) {
    const __m512i zero = _mm512_setzero_si512();
    const __m512i Y[3] = {_mm512_set1_epi32(ys.y[0]), _mm512_set1_epi32(ys.y[1]),
                          _mm512_set1_epi32(ys.y[2])};
    const __m512i rowMin = _mm512_set1_epi32(ys.rowMin), rowMax = _mm512_set1_epi32(ys.rowMax);
    LaneFragment16 f;
    bool haveFragment = false;
    int general = 0;
    for (int i = 0; i < m; i += 16) {
        const __mmask16 live = liveMask(m, i);
        __m512i X[3];
        if (deriveX) {
            (*deriveX)(_mm512_maskz_loadu_ps(live, ps + i), X);
        } else {
            for (int j = 0; j < 3; ++j) X[j] = _mm512_maskz_loadu_epi32(live, xs.x[j] + i);
        }
        const Cover16 c = cover16<OneRow>(X[0], X[1], X[2], Y, rowMin, rowMax, width);
        const __mmask16 negative = _mm512_cmplt_epi32_mask(c.mask, zero) & live;
        const __mmask16 drawn = __mmask16(live & ~negative);
        const __m512i rem = _mm512_maskz_mov_epi32(drawn, c.mask);
        if (_mm512_test_epi32_mask(rem, rem)) {
            if (!haveFragment) f = laneFragment16(tri, flat, ys.rowMin, width, height);
            haveFragment = true;
            if (blockStride > 0) {
                shadeGroup16<OneRow, true>(f, c, rem, drawn, xs.view + i, depth, color,
                                           blockStride);
            } else {
                shadeGroup16<OneRow, false>(f, c, rem, drawn, xs.view + i, depth, color, 0);
            }
        }
        if (!negative) continue;
        // General lanes to the front (general <= i: positions already read).
        const int count = __builtin_popcount(unsigned(negative));
        for (int j = 0; j < 3; ++j)
            storeFirst(xs.x[j] + general, count, _mm512_maskz_compress_epi32(negative, X[j]));
        const __m512i views =
            _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(xs.view + i)));
        _mm_mask_storeu_epi8(xs.view + general, __mmask16((1u << count) - 1u),
                             _mm512_cvtepi32_epi8(_mm512_maskz_compress_epi32(negative, views)));
        general += count;
    }
    return general;
}

/// drawSheared, 16 views per register (the AVX2 kernel's structure and operations).
int drawSheared(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                const std::uint64_t* culled, int width, int height, const FragmentTri& tri,
                bool flat, float* const* depth, std::uint32_t* const* color,
                std::int32_t blockStride, ViewsX& xs) {
    if (ys.rowMax == ys.rowMin) {
        alignas(64) float ps[kMaxViews + 16];  // + room for a whole register's store
        const int m = culled ? packOnRow16<true>(ys, t, shears, n, culled, width, ps, xs)
                             : packOnRow16<false>(ys, t, shears, n, nullptr, width, ps, xs);
        if (m == 0) return 0;
        const ShearX16 deriveX(t, width);
        return drawPacked16<true>(ys, m, width, height, tri, flat, depth, color, blockStride, xs,
                                  &deriveX, ps);
    }
    const int m = packSheared16(t, shears, n, culled, width, xs);
    return m == 0 ? 0
                  : drawPacked16<false>(ys, m, width, height, tri, flat, depth, color, blockStride,
                                        xs);
}

}  // namespace

const Kernels* avx512Kernels() {
    // shadeLanes: the AVX2 kernel (its 8-lane gathers of view pointers serve AVX-512 CPUs too).
    // drawLanes' conflict detection is AVX-512 CD (every AVX-512 CPU so far has it).
    static const Kernels k = [] {
        __builtin_cpu_init();
        return Kernels{&projectYZW,
                       &projectX,
                       &setupViews,
                       &avx512::shadeVertices,
                       &avx512::transformPoints,
                       &avx512::specularPowN,
                       &setupLanes,
                       &setupSheared,
                       avx2Kernels()->shadeLanes,
                       &drawSheared,
                       &rowClipX,
                       __builtin_cpu_supports("avx512cd") ? &drawLanes : nullptr,
                       &rowSnapX};
    }();
    return &k;
}

}  // namespace mvr::raster::detail
