// setupLanes with AVX2: two passes of 8 lanes — the AVX-512 kernel's operations with vector
// compare results instead of mask registers.
#include <algorithm>

#include <immintrin.h>

#include "../lanes.h"

namespace mvr::raster::detail {

namespace {

inline __m256i loadLanes(const std::int32_t* p, __m256i live) {
    return _mm256_maskload_epi32(reinterpret_cast<const int*>(p), live);
}
inline void store(std::int32_t* p, __m256i v) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }
inline __m256i cmple(__m256i a, __m256i b) {  // a <= b as all-ones lanes
    return _mm256_xor_si256(_mm256_cmpgt_epi32(a, b), _mm256_set1_epi32(-1));
}

std::uint32_t setupLanes8(TriangleLanes& l, int base, int n, int width) {
    const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32(n - base), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1), ones = _mm256_set1_epi32(-1);
    const __m256i half = _mm256_set1_epi32(kHalfSubpixel);
    const __m256i X0 = loadLanes(l.x[0] + base, live), X1 = loadLanes(l.x[1] + base, live),
                  X2 = loadLanes(l.x[2] + base, live);
    const __m256i Y[3] = {loadLanes(l.y[0] + base, live), loadLanes(l.y[1] + base, live),
                          loadLanes(l.y[2] + base, live)};
    const __m256i rowMin = loadLanes(l.rowMin + base, live), rowMax = loadLanes(l.rowMax + base, live);
    const __m256i tall = _mm256_cmpgt_epi32(rowMax, rowMin);
    const __m256i rowsSmall = cmple(_mm256_sub_epi32(rowMax, rowMin), one);
    const __m256i py0 = _mm256_add_epi32(_mm256_slli_epi32(rowMin, kSubpixelBits), half);
    const __m256i yr[3] = {_mm256_sub_epi32(Y[0], py0), _mm256_sub_epi32(Y[1], py0), _mm256_sub_epi32(Y[2], py0)};
    const __m256i dyShared[3] = {_mm256_sub_epi32(Y[2], Y[1]), _mm256_sub_epi32(Y[0], Y[2]),
                                 _mm256_sub_epi32(Y[1], Y[0])};
    const __m256i yr20 = _mm256_sub_epi32(yr[2], yr[0]);
    const __m256i xlo = _mm256_min_epi32(X0, _mm256_min_epi32(X1, X2));
    const __m256i xhi = _mm256_max_epi32(X0, _mm256_max_epi32(X1, X2));
    const __m256i colMin = _mm256_max_epi32(
        zero, _mm256_srai_epi32(_mm256_add_epi32(_mm256_sub_epi32(xlo, half), _mm256_set1_epi32(kSubpixel - 1)),
                                kSubpixelBits));
    const __m256i colMax = _mm256_min_epi32(_mm256_set1_epi32(width - 1),
                                            _mm256_srai_epi32(_mm256_sub_epi32(xhi, half), kSubpixelBits));
    const __m256i empty = _mm256_cmpgt_epi32(colMin, colMax);
    const __m256i cols = _mm256_sub_epi32(colMax, colMin);
    const __m256i small = _mm256_andnot_si256(empty, _mm256_and_si256(rowsSmall, cmple(cols, one)));
    const __m256i px0 = _mm256_add_epi32(_mm256_slli_epi32(colMin, kSubpixelBits), half);
    const __m256i xr[3] = {_mm256_sub_epi32(X0, px0), _mm256_sub_epi32(X1, px0), _mm256_sub_epi32(X2, px0)};
    __m256i dx[3] = {_mm256_sub_epi32(xr[2], xr[1]), _mm256_sub_epi32(xr[0], xr[2]),
                     _mm256_sub_epi32(xr[1], xr[0])};
    __m256i area = _mm256_sub_epi32(_mm256_mullo_epi32(dx[2], yr20),
                                    _mm256_mullo_epi32(dyShared[2], _mm256_sub_epi32(xr[2], xr[0])));
    const __m256i flip = _mm256_srai_epi32(area, 31);
    area = _mm256_sub_epi32(_mm256_xor_si256(area, flip), flip);
    __m256i any[4] = {zero, zero, zero, zero};
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        dx[i] = _mm256_sub_epi32(_mm256_xor_si256(dx[i], flip), flip);
        const __m256i dy = _mm256_sub_epi32(_mm256_xor_si256(dyShared[i], flip), flip);
        const __m256i tl = _mm256_or_si256(_mm256_cmpgt_epi32(zero, dy),
                                           _mm256_and_si256(_mm256_cmpeq_epi32(dy, zero), _mm256_cmpgt_epi32(zero, dx[i])));
        const __m256i bias = _mm256_and_si256(tl, one);
        const __m256i e = _mm256_add_epi32(
            _mm256_sub_epi32(_mm256_mullo_epi32(dy, xr[a]), _mm256_mullo_epi32(dx[i], yr[a])), bias);
        const __m256i sx = _mm256_slli_epi32(_mm256_sub_epi32(zero, dy), kSubpixelBits);
        const __m256i sy = _mm256_slli_epi32(dx[i], kSubpixelBits);
        store(l.out.e[i] + base, e);
        store(l.out.sx[i] + base, sx);
        store(l.out.sy[i] + base, sy);
        store(l.out.bias[i] + base, bias);
        const __m256i em1 = _mm256_sub_epi32(e, one);
        any[0] = _mm256_or_si256(any[0], em1);
        any[1] = _mm256_or_si256(any[1], _mm256_add_epi32(em1, sx));
        any[2] = _mm256_or_si256(any[2], _mm256_add_epi32(em1, sy));
        any[3] = _mm256_or_si256(any[3], _mm256_add_epi32(_mm256_add_epi32(em1, sx), sy));
    }
    const __m256i wide = _mm256_cmpgt_epi32(colMax, colMin);
    const __m256i valid[4] = {ones, wide, tall, _mm256_and_si256(tall, wide)};
    __m256i mask = zero;
    for (int j = 0; j < 4; ++j) {
        const __m256i in = _mm256_andnot_si256(_mm256_cmpgt_epi32(zero, any[j]), valid[j]);  // any >= 0
        mask = _mm256_or_si256(mask, _mm256_and_si256(in, _mm256_set1_epi32(1 << j)));
    }
    mask = _mm256_andnot_si256(_mm256_cmpeq_epi32(area, zero), mask);
    mask = _mm256_blendv_epi8(ones, mask, _mm256_or_si256(small, empty));  // general walk: −1
    mask = _mm256_andnot_si256(empty, mask);
    store(l.out.mask + base, mask);
    store(l.out.colMin + base, colMin);
    store(l.out.area + base, area);
    const __m256i nonzero = _mm256_andnot_si256(_mm256_cmpeq_epi32(mask, zero), live);
    return std::uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(nonzero))) << base;
}

std::uint32_t setupLanes(TriangleLanes& l, int n, int width) {
    std::uint32_t lanes = setupLanes8(l, 0, n, width);
    if (n > 8) lanes |= setupLanes8(l, 8, n, width);
    return lanes;
}

}  // namespace

SetupLanesFn setupLanesAvx2() { return &setupLanes; }

}  // namespace mvr::raster::detail
