// setupLanes with AVX-512: all 16 lanes in one pass — setupViews' operations (kernels_avx512.cpp)
// with the y terms loaded per lane instead of broadcast.
#include <immintrin.h>

#include "../lanes.h"

namespace mvr::raster::detail {

namespace {

std::uint32_t setupLanes(TriangleLanes& l, int n, int width) {
    const __mmask16 live = n >= kLaneCount ? __mmask16(0xffff) : __mmask16((1u << n) - 1u);
    const __m512i zero = _mm512_setzero_si512(), one = _mm512_set1_epi32(1);
    const __m512i half = _mm512_set1_epi32(kHalfSubpixel);
    const __m512i X0 = _mm512_maskz_loadu_epi32(live, l.x[0]);
    const __m512i X1 = _mm512_maskz_loadu_epi32(live, l.x[1]);
    const __m512i X2 = _mm512_maskz_loadu_epi32(live, l.x[2]);
    const __m512i Y[3] = {_mm512_maskz_loadu_epi32(live, l.y[0]), _mm512_maskz_loadu_epi32(live, l.y[1]),
                          _mm512_maskz_loadu_epi32(live, l.y[2])};
    const __m512i rowMin = _mm512_maskz_loadu_epi32(live, l.rowMin);
    const __m512i rowMax = _mm512_maskz_loadu_epi32(live, l.rowMax);
    const __mmask16 tall = _mm512_cmpgt_epi32_mask(rowMax, rowMin);
    const __mmask16 rowsSmall = _mm512_cmple_epi32_mask(_mm512_sub_epi32(rowMax, rowMin), one);
    const __m512i py0 = _mm512_add_epi32(_mm512_slli_epi32(rowMin, kSubpixelBits), half);
    const __m512i yr[3] = {_mm512_sub_epi32(Y[0], py0), _mm512_sub_epi32(Y[1], py0), _mm512_sub_epi32(Y[2], py0)};
    // setupY's Δy: dy[0] = y2 − y1, dy[1] = y0 − y2, dy[2] = y1 − y0.
    const __m512i dyShared[3] = {_mm512_sub_epi32(Y[2], Y[1]), _mm512_sub_epi32(Y[0], Y[2]),
                                 _mm512_sub_epi32(Y[1], Y[0])};
    const __m512i yr20 = _mm512_sub_epi32(yr[2], yr[0]);
    const __m512i xlo = _mm512_min_epi32(X0, _mm512_min_epi32(X1, X2));
    const __m512i xhi = _mm512_max_epi32(X0, _mm512_max_epi32(X1, X2));
    const __m512i colMin = _mm512_max_epi32(
        zero, _mm512_srai_epi32(_mm512_add_epi32(_mm512_sub_epi32(xlo, half), _mm512_set1_epi32(kSubpixel - 1)),
                                kSubpixelBits));
    const __m512i colMax = _mm512_min_epi32(_mm512_set1_epi32(width - 1),
                                            _mm512_srai_epi32(_mm512_sub_epi32(xhi, half), kSubpixelBits));
    const __mmask16 empty = _mm512_cmpgt_epi32_mask(colMin, colMax);
    const __m512i cols = _mm512_sub_epi32(colMax, colMin);
    const __mmask16 small = __mmask16(rowsSmall & _mm512_cmple_epi32_mask(cols, one) & ~empty);
    const __m512i px0 = _mm512_add_epi32(_mm512_slli_epi32(colMin, kSubpixelBits), half);
    const __m512i xr[3] = {_mm512_sub_epi32(X0, px0), _mm512_sub_epi32(X1, px0), _mm512_sub_epi32(X2, px0)};
    __m512i dx[3] = {_mm512_sub_epi32(xr[2], xr[1]), _mm512_sub_epi32(xr[0], xr[2]),
                     _mm512_sub_epi32(xr[1], xr[0])};
    __m512i area = _mm512_sub_epi32(_mm512_mullo_epi32(dx[2], yr20),
                                    _mm512_mullo_epi32(dyShared[2], _mm512_sub_epi32(xr[2], xr[0])));
    const __m512i flip = _mm512_srai_epi32(area, 31);
    area = _mm512_sub_epi32(_mm512_xor_si512(area, flip), flip);
    __m512i any[4] = {zero, zero, zero, zero};
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        dx[i] = _mm512_sub_epi32(_mm512_xor_si512(dx[i], flip), flip);
        const __m512i dy = _mm512_sub_epi32(_mm512_xor_si512(dyShared[i], flip), flip);
        const __mmask16 tl = _mm512_cmplt_epi32_mask(dy, zero) |
                             (_mm512_cmpeq_epi32_mask(dy, zero) & _mm512_cmplt_epi32_mask(dx[i], zero));
        const __m512i bias = _mm512_maskz_mov_epi32(tl, one);
        const __m512i e = _mm512_add_epi32(
            _mm512_sub_epi32(_mm512_mullo_epi32(dy, xr[a]), _mm512_mullo_epi32(dx[i], yr[a])), bias);
        const __m512i sx = _mm512_slli_epi32(_mm512_sub_epi32(zero, dy), kSubpixelBits);
        const __m512i sy = _mm512_slli_epi32(dx[i], kSubpixelBits);
        _mm512_storeu_si512(l.out.e[i], e);
        _mm512_storeu_si512(l.out.sx[i], sx);
        _mm512_storeu_si512(l.out.sy[i], sy);
        _mm512_storeu_si512(l.out.bias[i], bias);
        const __m512i em1 = _mm512_sub_epi32(e, one);
        any[0] = _mm512_or_si512(any[0], em1);
        any[1] = _mm512_or_si512(any[1], _mm512_add_epi32(em1, sx));
        any[2] = _mm512_or_si512(any[2], _mm512_add_epi32(em1, sy));
        any[3] = _mm512_or_si512(any[3], _mm512_add_epi32(_mm512_add_epi32(em1, sx), sy));
    }
    const __mmask16 wide = _mm512_cmpgt_epi32_mask(colMax, colMin);
    __m512i mask = zero;
    for (int j = 0; j < 4; ++j) {
        const __mmask16 valid = j == 0 ? __mmask16(0xffff) : j == 1 ? wide : j == 2 ? tall : __mmask16(tall & wide);
        const __mmask16 in = _mm512_cmpge_epi32_mask(any[j], zero) & valid;
        mask = _mm512_mask_or_epi32(mask, in, mask, _mm512_set1_epi32(1 << j));
    }
    mask = _mm512_maskz_mov_epi32(_mm512_cmpneq_epi32_mask(area, zero), mask);
    mask = _mm512_mask_mov_epi32(mask, __mmask16(~small & ~empty), _mm512_set1_epi32(-1));
    mask = _mm512_maskz_mov_epi32(__mmask16(~empty), mask);
    _mm512_storeu_si512(l.out.mask, mask);
    _mm512_storeu_si512(l.out.colMin, colMin);
    _mm512_storeu_si512(l.out.area, area);
    return std::uint32_t(_mm512_test_epi32_mask(mask, mask) & live);
}

}  // namespace

SetupLanesFn setupLanesAvx512() { return &setupLanes; }

}  // namespace mvr::raster::detail
