// AVX2 kernels (compiled with -mavx2 -mfma; no FMA is formed: -ffp-contract=off). Same operations
// and order as the scalar loops in kernels_tail.h.
#include <immintrin.h>

#include "../cpu.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

namespace {

inline __m256i bitIf(__m256 mask, int bit) {
    return _mm256_and_si256(_mm256_castps_si256(mask), _mm256_set1_epi32(bit));
}
inline void storeCodes(__m256i codes, std::uint8_t* out) {
    alignas(32) std::int32_t tmp[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(tmp), codes);
    for (int k = 0; k < 8; ++k) out[k] = static_cast<std::uint8_t>(tmp[k]);
}
/// lrintf(((v·q)·0.5 + 0.5)·size·256) with the scalar operation order.
inline __m256i snap(__m256 v, __m256 q, __m256 size) {
    const __m256 half = _mm256_set1_ps(0.5f);
    __m256 t = _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(v, q), half), half);
    t = _mm256_mul_ps(_mm256_mul_ps(t, size), _mm256_set1_ps(float(kSubpixel)));
    return _mm256_cvtps_epi32(t);
}

void projectYZW(const float* y, const float* z, const float* w, std::size_t n, float height,
                std::uint8_t* code, float* q, std::int32_t* sy, float* zw) {
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f);
    const __m256 gb = _mm256_set1_ps(kGuardBand), ngb = _mm256_set1_ps(-kGuardBand);
    const __m256 sign = _mm256_set1_ps(-0.0f), h = _mm256_set1_ps(height);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256 Y = _mm256_loadu_ps(y + i), Z = _mm256_loadu_ps(z + i), W = _mm256_loadu_ps(w + i);
        const __m256 nW = _mm256_xor_ps(W, sign);
        __m256i c = bitIf(_mm256_cmp_ps(Z, nW, _CMP_LT_OQ), kClipNear);
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Z, W, _CMP_GT_OQ), kClipFar));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Y, _mm256_mul_ps(ngb, W), _CMP_LT_OQ), kClipBottom));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Y, _mm256_mul_ps(gb, W), _CMP_GT_OQ), kClipTop));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Y, nW, _CMP_LT_OQ), kOutBottom));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Y, W, _CMP_GT_OQ), kOutTop));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(W, zero, _CMP_NGT_UQ), kClipNear));
        storeCodes(c, code + i);
        const __m256 Q = _mm256_div_ps(one, W);
        _mm256_storeu_ps(q + i, Q);
        const __m256i clipped = _mm256_cmpgt_epi32(_mm256_and_si256(c, _mm256_set1_epi32(kClipYZW)),
                                                   _mm256_setzero_si256());
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sy + i),
                            _mm256_andnot_si256(clipped, snap(Y, Q, h)));
        __m256 d = _mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(Z, Q), half), half);
        d = _mm256_blendv_ps(d, zero, _mm256_cmp_ps(d, zero, _CMP_LT_OQ));  // std::clamp order
        d = _mm256_blendv_ps(d, one, _mm256_cmp_ps(one, d, _CMP_LT_OQ));
        _mm256_storeu_ps(zw + i, d);
    }
    projectYZWTail(y + i, z + i, w + i, n - i, height, code + i, q + i, sy + i, zw + i);
}

void projectX(const float* x, const float* w, const float* q, std::size_t n, float width,
              std::uint8_t* code, std::int32_t* sx) {
    const __m256 gb = _mm256_set1_ps(kGuardBand), ngb = _mm256_set1_ps(-kGuardBand);
    const __m256 sign = _mm256_set1_ps(-0.0f), wd = _mm256_set1_ps(width);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256 X = _mm256_loadu_ps(x + i), W = _mm256_loadu_ps(w + i);
        const __m256 nW = _mm256_xor_ps(W, sign);
        __m256i c = bitIf(_mm256_cmp_ps(X, _mm256_mul_ps(ngb, W), _CMP_LT_OQ), kClipLeft);
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(X, _mm256_mul_ps(gb, W), _CMP_GT_OQ), kClipRight));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(X, nW, _CMP_LT_OQ), kOutLeft));
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(X, W, _CMP_GT_OQ), kOutRight));
        storeCodes(c, code + i);
        const __m256i clipped = _mm256_cmpgt_epi32(_mm256_and_si256(c, _mm256_set1_epi32(kClipX)),
                                                   _mm256_setzero_si256());
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(sx + i),
                            _mm256_andnot_si256(clipped, snap(X, _mm256_loadu_ps(q + i), wd)));
    }
    projectXTail(x + i, w + i, q + i, n - i, width, code + i, sx + i);
}

}  // namespace

const Kernels* avx2Kernels() {
    static const Kernels k{&projectYZW, &projectX};
    return &k;
}

}  // namespace mvr::raster::detail
