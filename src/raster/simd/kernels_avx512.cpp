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
    const __m512 zero = _mm512_setzero_ps(), one = _mm512_set1_ps(1.0f), half = _mm512_set1_ps(0.5f);
    const __m512 gb = _mm512_set1_ps(kGuardBand), ngb = _mm512_set1_ps(-kGuardBand);
    const __m512 h = _mm512_set1_ps(height);
    std::size_t i = 0;
    for (; i + 16 <= n; i += 16) {
        const __m512 Y = _mm512_loadu_ps(y + i), Z = _mm512_loadu_ps(z + i), W = _mm512_loadu_ps(w + i);
        const __m512 nW = _mm512_castsi512_ps(
            _mm512_xor_si512(_mm512_castps_si512(W), _mm512_set1_epi32(std::int32_t(0x80000000u))));
        __m512i c = bitIf(_mm512_cmp_ps_mask(Z, nW, _CMP_LT_OQ), kClipNear);
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Z, W, _CMP_GT_OQ), kClipFar));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, _mm512_mul_ps(ngb, W), _CMP_LT_OQ), kClipBottom));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, _mm512_mul_ps(gb, W), _CMP_GT_OQ), kClipTop));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, nW, _CMP_LT_OQ), kOutBottom));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(Y, W, _CMP_GT_OQ), kOutTop));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(W, zero, _CMP_NGT_UQ), kClipNear));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(code + i), _mm512_cvtepi32_epi8(c));
        const __m512 Q = _mm512_div_ps(one, W);
        _mm512_storeu_ps(q + i, Q);
        const __mmask16 ok = _mm512_testn_epi32_mask(c, _mm512_set1_epi32(kClipYZW));
        _mm512_storeu_si512(sy + i, _mm512_maskz_mov_epi32(ok, snap(Y, Q, h)));
        __m512 d = _mm512_add_ps(_mm512_mul_ps(_mm512_mul_ps(Z, Q), half), half);
        d = _mm512_mask_mov_ps(d, _mm512_cmp_ps_mask(d, zero, _CMP_LT_OQ), zero);  // std::clamp order
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
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(X, _mm512_mul_ps(gb, W), _CMP_GT_OQ), kClipRight));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(X, nW, _CMP_LT_OQ), kOutLeft));
        c = _mm512_or_si512(c, bitIf(_mm512_cmp_ps_mask(X, W, _CMP_GT_OQ), kOutRight));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(code + i), _mm512_cvtepi32_epi8(c));
        const __mmask16 ok = _mm512_testn_epi32_mask(c, _mm512_set1_epi32(kClipX));
        _mm512_storeu_si512(sx + i, _mm512_maskz_mov_epi32(ok, snap(X, _mm512_loadu_ps(q + i), wd)));
    }
    projectXTail(x + i, w + i, q + i, n - i, width, code + i, sx + i);
}

}  // namespace

const Kernels* avx512Kernels() {
    static const Kernels k{&projectYZW, &projectX};
    return &k;
}

}  // namespace mvr::raster::detail
