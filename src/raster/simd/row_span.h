// packOnRow's estimate of a one-row triangle's span on the row's center line as a linear
// function of the shear (Halle's epipolar-plane image), shared by the AVX2 and AVX-512 kernels
// (128-bit AVX operations; each kernel evaluates it for 8 or 16 views per register). Internal
// linkage: each kernel file compiles its own copy with its own target flags.
#pragma once

#include <immintrin.h>

#include "../pipeline.h"

namespace mvr::raster::detail {
namespace {

/// On the center line of row ys.rowMin, the triangle's edges meet it at window x (pixels from
/// the first column's center) pa[j] + s·pb[j] for a view of shear s (lanes 0..2; an edge that
/// misses the line takes the first one that meets it). The estimate is unsnapped: a view can
/// cover a center only within slack0 + |s|·slack1 of it (snapping's half unit and more,
/// 2/256 px, plus float rounding of every step: 2^-16 of the largest magnitude, far more than
/// the relative 2^-24 each step adds).
struct RowSpan {
    __m128 pa, pb;
    float slack0, slack1;
};

/// false when the triangle misses the row's center line (no view covers a center of it).
inline bool rowSpan(const YSetup& ys, const ShearedTri& t, int width, RowSpan& r) {
    // Vertex j's window x is about alpha_j + s·beta_j (snapX of shearClipWc, unsnapped).
    const __m128i three = _mm_setr_epi32(-1, -1, -1, 0);
    const __m128 scale = _mm_set1_ps(0.5f * float(width));
    // Lanes from scalar loads: t and ys were just stored field by field, and a wide load of them
    // would wait for those stores (store-to-load forwarding cannot serve it).
    const __m128 q = _mm_setr_ps(t.q[0], t.q[1], t.q[2], 0.0f);
    const __m128 alpha = _mm_sub_ps(
        _mm_mul_ps(scale, _mm_add_ps(_mm_mul_ps(_mm_setr_ps(t.cx[0], t.cx[1], t.cx[2], 0.0f), q),
                                     _mm_set1_ps(1.0f))),
        _mm_set1_ps(0.5f));
    const __m128 beta =
        _mm_mul_ps(scale, _mm_mul_ps(_mm_setr_ps(t.wc[0], t.wc[1], t.wc[2], 0.0f), q));
    // The span's ends: where the edges a -> b = a + 1 meet the line, ends included (a vertex on
    // the line is the end of its two edges; an edge along the line is not needed: its ends are
    // those of the other two, or the triangle is degenerate and covers nothing).
    const __m128i d = _mm_sub_epi32(_mm_setr_epi32(ys.y[0], ys.y[1], ys.y[2], 0),
                                    _mm_set1_epi32(ys.rowMin * kSubpixel + kHalfSubpixel));
    const __m128i db = _mm_shuffle_epi32(d, _MM_SHUFFLE(3, 0, 2, 1));
    const __m128i zeroI = _mm_setzero_si128();
    const __m128i meets = _mm_and_si128(
        _mm_andnot_si128(
            _mm_cmpeq_epi32(d, db),
            _mm_or_si128(
                _mm_andnot_si128(_mm_cmpgt_epi32(d, zeroI),
                                 _mm_xor_si128(_mm_cmpgt_epi32(zeroI, db), _mm_set1_epi32(-1))),
                _mm_andnot_si128(_mm_cmpgt_epi32(zeroI, d),
                                 _mm_xor_si128(_mm_cmpgt_epi32(db, zeroI), _mm_set1_epi32(-1))))),
        three);
    const unsigned edges = unsigned(_mm_movemask_ps(_mm_castsi128_ps(meets)));
    if (edges == 0) return false;
    const __m128 tt = _mm_div_ps(_mm_cvtepi32_ps(d), _mm_cvtepi32_ps(_mm_sub_epi32(d, db)));
    const __m128 pa0 = _mm_add_ps(
        alpha,
        _mm_mul_ps(tt, _mm_sub_ps(_mm_shuffle_ps(alpha, alpha, _MM_SHUFFLE(3, 0, 2, 1)), alpha)));
    const __m128 pb0 = _mm_add_ps(
        beta,
        _mm_mul_ps(tt, _mm_sub_ps(_mm_shuffle_ps(beta, beta, _MM_SHUFFLE(3, 0, 2, 1)), beta)));
    const __m128i pick =
        _mm_blendv_epi8(_mm_set1_epi32(__builtin_ctz(edges)), _mm_setr_epi32(0, 1, 2, 3), meets);
    r.pa = _mm_permutevar_ps(pa0, pick), r.pb = _mm_permutevar_ps(pb0, pick);
    // |alpha| + scale and |beta| over the vertices: the magnitudes the rounding is relative to.
    const __m128 absMask = _mm_set1_ps(-0.0f);
    const __m128 fixed = _mm_add_ps(_mm_andnot_ps(absMask, alpha), scale),
                 shear = _mm_andnot_ps(absMask, beta);
    const __m128 mags01 = _mm_unpacklo_ps(fixed, shear);  // vertices 0 and 1, then vertex 2:
    const __m128 mags2 =
        _mm_and_ps(_mm_castsi128_ps(_mm_setr_epi32(-1, -1, 0, 0)), _mm_unpackhi_ps(fixed, shear));
    const __m128 mags = _mm_max_ps(_mm_max_ps(mags01, _mm_movehl_ps(mags01, mags01)), mags2);
    const float fixedMag = _mm_cvtss_f32(mags);
    const float shearMag = _mm_cvtss_f32(_mm_shuffle_ps(mags, mags, _MM_SHUFFLE(1, 1, 1, 1)));
    r.slack0 = 2.0f / float(kSubpixel) + fixedMag * (1.0f / 65536.0f);
    r.slack1 = shearMag * (1.0f / 65536.0f);
    return true;
}

/// Lane j of v (j in 0..2).
template <int j>
inline float lane(__m128 v) {
    return _mm_cvtss_f32(_mm_shuffle_ps(v, v, _MM_SHUFFLE(j, j, j, j)));
}

}  // namespace
}  // namespace mvr::raster::detail
