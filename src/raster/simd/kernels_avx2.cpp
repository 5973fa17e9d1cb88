// AVX2 kernels (compiled with -mavx2 -mfma; the compiler forms no FMA: -ffp-contract=off). Same
// operations and order as the scalar loops in kernels_tail.h. (packOnRow's explicit FMAs only
// estimate which views to draw, with a margin; nothing drawn depends on their rounding.)
#include <algorithm>
#include <array>
#include <cstring>

#include <immintrin.h>

#include "../cpu.h"
#include "kernels_tail.h"
#include "row_span.h"

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
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f),
                 half = _mm256_set1_ps(0.5f);
    const __m256 gb = _mm256_set1_ps(kGuardBand), ngb = _mm256_set1_ps(-kGuardBand);
    const __m256 sign = _mm256_set1_ps(-0.0f), h = _mm256_set1_ps(height);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256 Y = _mm256_loadu_ps(y + i), Z = _mm256_loadu_ps(z + i),
                     W = _mm256_loadu_ps(w + i);
        const __m256 nW = _mm256_xor_ps(W, sign);
        __m256i c = bitIf(_mm256_cmp_ps(Z, nW, _CMP_LT_OQ), kClipNear);
        c = _mm256_or_si256(c, bitIf(_mm256_cmp_ps(Z, W, _CMP_GT_OQ), kClipFar));
        c = _mm256_or_si256(
            c, bitIf(_mm256_cmp_ps(Y, _mm256_mul_ps(ngb, W), _CMP_LT_OQ), kClipBottom));
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
        c = _mm256_or_si256(c,
                            bitIf(_mm256_cmp_ps(X, _mm256_mul_ps(gb, W), _CMP_GT_OQ), kClipRight));
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

/// rowSnapX: 8 vertices a pass, each view's x as projectX snaps it; a pair interleaved in
/// registers, other rows through a tile in the stack.
void rowSnapX(const float* cx, const float* w, const float* q, std::size_t n, const float* shears,
              int nv, float convergence, float width, std::int32_t* sxv) {
    const __m256 gb = _mm256_set1_ps(kGuardBand), ngb = _mm256_set1_ps(-kGuardBand);
    const __m256 wd = _mm256_set1_ps(width), C = _mm256_set1_ps(convergence);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256 X = _mm256_loadu_ps(cx + i), W = _mm256_loadu_ps(w + i),
                     Q = _mm256_loadu_ps(q + i);
        const __m256 wc = _mm256_sub_ps(W, C);
        const __m256 lo = _mm256_mul_ps(ngb, W), hi = _mm256_mul_ps(gb, W);
        auto viewX = [&](float s) {
            const __m256 x = _mm256_add_ps(X, _mm256_mul_ps(_mm256_set1_ps(s), wc));
            const __m256 clip =
                _mm256_or_ps(_mm256_cmp_ps(x, lo, _CMP_LT_OQ), _mm256_cmp_ps(x, hi, _CMP_GT_OQ));
            return _mm256_andnot_si256(_mm256_castps_si256(clip), snap(x, Q, wd));
        };
        std::int32_t* out = sxv + i * std::size_t(nv);
        if (nv == 2) {
            const __m256i a = viewX(shears[0]), b = viewX(shears[1]);
            const __m256i l = _mm256_unpacklo_epi32(a, b), h = _mm256_unpackhi_epi32(a, b);
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(out),
                                _mm256_permute2x128_si256(l, h, 0x20));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 8),
                                _mm256_permute2x128_si256(l, h, 0x31));
        } else {
            alignas(32) std::int32_t tile[kLaneBlock][8];
            for (int k = 0; k < nv; ++k)
                _mm256_store_si256(reinterpret_cast<__m256i*>(tile[k]), viewX(shears[k]));
            for (int j = 0; j < 8; ++j)
                for (int k = 0; k < nv; ++k) out[j * nv + k] = tile[k][j];
        }
    }
    rowSnapXTail(cx + i, w + i, q + i, n - i, shears, nv, convergence, width,
                 sxv + i * std::size_t(nv));
}

void rowClipX(const float* cx, const float* w, std::size_t n, float lo, float hi, float convergence,
              std::uint8_t* any) {
    const __m256 gb = _mm256_set1_ps(kGuardBand), ngb = _mm256_set1_ps(-kGuardBand);
    const __m256 L = _mm256_set1_ps(lo), H = _mm256_set1_ps(hi), C = _mm256_set1_ps(convergence);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const __m256 X = _mm256_loadu_ps(cx + i), W = _mm256_loadu_ps(w + i);
        const __m256 wc = _mm256_sub_ps(W, C);
        const __m256 xl = _mm256_add_ps(X, _mm256_mul_ps(L, wc));
        const __m256 xh = _mm256_add_ps(X, _mm256_mul_ps(H, wc));
        const __m256 left = _mm256_mul_ps(ngb, W), right = _mm256_mul_ps(gb, W);
        const __m256i c = _mm256_or_si256(bitIf(_mm256_or_ps(_mm256_cmp_ps(xl, left, _CMP_LT_OQ),
                                                             _mm256_cmp_ps(xh, left, _CMP_LT_OQ)),
                                                kClipLeft),
                                          bitIf(_mm256_or_ps(_mm256_cmp_ps(xl, right, _CMP_GT_OQ),
                                                             _mm256_cmp_ps(xh, right, _CMP_GT_OQ)),
                                                kClipRight));
        // 8 codes as bytes (each < 256: the packs do not saturate), OR-ed into any[i, i + 8)
        const __m128i w16 =
            _mm_packs_epi32(_mm256_castsi256_si128(c), _mm256_extracti128_si256(c, 1));
        const __m128i b8 = _mm_packus_epi16(w16, w16);
        std::uint64_t bytes;
        std::memcpy(&bytes, &b8, 8);
        std::uint64_t old;
        std::memcpy(&old, any + i, 8);
        old |= bytes;
        std::memcpy(any + i, &old, 8);
    }
    rowClipXTail(cx + i, w + i, n - i, lo, hi, convergence, any + i);
}

inline __m256i loadLanes(const std::int32_t* p, __m256i live) {
    return _mm256_maskload_epi32(reinterpret_cast<const int*>(p), live);
}
inline __m256i load(const std::int32_t* p) {
    return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
}
inline void store(std::int32_t* p, __m256i v) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v);
}
inline __m256i cmple(__m256i a, __m256i b) {  // a <= b as all-ones lanes
    return _mm256_xor_si256(_mm256_cmpgt_epi32(a, b), _mm256_set1_epi32(-1));
}

/// The pixel-center columns [colMin, colMax] of 8 lanes' x extents [xlo, xhi] within [0, width)
/// (setupViewsTail's colMin / colMax; empty when colMin > colMax).
inline void columnRange(__m256i xlo, __m256i xhi, int width, __m256i& colMin, __m256i& colMax) {
    const __m256i half = _mm256_set1_epi32(kHalfSubpixel);
    colMin = _mm256_max_epi32(_mm256_setzero_si256(),
                              _mm256_srai_epi32(_mm256_add_epi32(_mm256_sub_epi32(xlo, half),
                                                                 _mm256_set1_epi32(kSubpixel - 1)),
                                                kSubpixelBits));
    colMax = _mm256_min_epi32(_mm256_set1_epi32(width - 1),
                              _mm256_srai_epi32(_mm256_sub_epi32(xhi, half), kSubpixelBits));
}

/// setupViewsTail's results for 8 lanes, in registers (setupCore stores them into a ViewsSetup;
/// drawSheared shades from them directly).
struct Cover {
    __m256i mask, colMin, area, e[3], sx[3], sy[3], bias[3];
};

/// The coverage setup of 8 lanes — setupViewsTail's integer operations — from each lane's snapped
/// x of the three vertices, snapped y and row range (broadcast by setupViews: one triangle's
/// views; loaded per lane by setupLanes: (triangle, view) pairs). Lanes that are not live hold
/// unspecified values. OneRow: every lane's rowMax == rowMin (then sy is not computed: no lane
/// has a second row of centers).
template <bool OneRow = false>
inline Cover cover(__m256i X0, __m256i X1, __m256i X2, const __m256i Y[3], __m256i rowMin,
                   __m256i rowMax, int width) {
    Cover c{};  // OneRow leaves sy at 0
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1),
                  ones = _mm256_set1_epi32(-1);
    const __m256i half = _mm256_set1_epi32(kHalfSubpixel);
    const __m256i tall = _mm256_cmpgt_epi32(rowMax, rowMin);
    const __m256i span = _mm256_set1_epi32(kSmallSpan);
    const __m256i ylo = _mm256_min_epi32(Y[0], _mm256_min_epi32(Y[1], Y[2]));
    const __m256i yhi = _mm256_max_epi32(Y[0], _mm256_max_epi32(Y[1], Y[2]));
    const __m256i rowsSmall =
        _mm256_and_si256(cmple(_mm256_sub_epi32(rowMax, rowMin), one),
                         _mm256_cmpgt_epi32(span, _mm256_sub_epi32(yhi, ylo)));
    const __m256i py0 = _mm256_add_epi32(_mm256_slli_epi32(rowMin, kSubpixelBits), half);
    const __m256i yr[3] = {_mm256_sub_epi32(Y[0], py0), _mm256_sub_epi32(Y[1], py0),
                           _mm256_sub_epi32(Y[2], py0)};
    const __m256i dyShared[3] = {_mm256_sub_epi32(Y[2], Y[1]), _mm256_sub_epi32(Y[0], Y[2]),
                                 _mm256_sub_epi32(Y[1], Y[0])};
    const __m256i yr20 = _mm256_sub_epi32(yr[2], yr[0]);
    const __m256i xlo = _mm256_min_epi32(X0, _mm256_min_epi32(X1, X2));
    const __m256i xhi = _mm256_max_epi32(X0, _mm256_max_epi32(X1, X2));
    __m256i colMax;
    columnRange(xlo, xhi, width, c.colMin, colMax);
    const __m256i empty = _mm256_cmpgt_epi32(c.colMin, colMax);
    const __m256i cols = _mm256_sub_epi32(colMax, c.colMin);
    const __m256i small = _mm256_andnot_si256(
        empty, _mm256_and_si256(_mm256_and_si256(rowsSmall, cmple(cols, one)),
                                _mm256_cmpgt_epi32(span, _mm256_sub_epi32(xhi, xlo))));
    const __m256i px0 = _mm256_add_epi32(_mm256_slli_epi32(c.colMin, kSubpixelBits), half);
    const __m256i xr[3] = {_mm256_sub_epi32(X0, px0), _mm256_sub_epi32(X1, px0),
                           _mm256_sub_epi32(X2, px0)};
    __m256i dx[3] = {_mm256_sub_epi32(xr[2], xr[1]), _mm256_sub_epi32(xr[0], xr[2]),
                     _mm256_sub_epi32(xr[1], xr[0])};
    __m256i area =
        _mm256_sub_epi32(_mm256_mullo_epi32(dx[2], yr20),
                         _mm256_mullo_epi32(dyShared[2], _mm256_sub_epi32(xr[2], xr[0])));
    const __m256i flip = _mm256_srai_epi32(area, 31);
    c.area = _mm256_sub_epi32(_mm256_xor_si256(area, flip), flip);
    __m256i any[4] = {zero, zero, zero, zero};
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        dx[i] = _mm256_sub_epi32(_mm256_xor_si256(dx[i], flip), flip);
        const __m256i dy = _mm256_sub_epi32(_mm256_xor_si256(dyShared[i], flip), flip);
        const __m256i tl = _mm256_or_si256(
            _mm256_cmpgt_epi32(zero, dy),
            _mm256_and_si256(_mm256_cmpeq_epi32(dy, zero), _mm256_cmpgt_epi32(zero, dx[i])));
        c.bias[i] = _mm256_and_si256(tl, one);
        c.e[i] = _mm256_add_epi32(
            _mm256_sub_epi32(_mm256_mullo_epi32(dy, xr[a]), _mm256_mullo_epi32(dx[i], yr[a])),
            c.bias[i]);
        c.sx[i] = _mm256_slli_epi32(_mm256_sub_epi32(zero, dy), kSubpixelBits);
        const __m256i em1 = _mm256_sub_epi32(c.e[i], one);
        any[0] = _mm256_or_si256(any[0], em1);
        any[1] = _mm256_or_si256(any[1], _mm256_add_epi32(em1, c.sx[i]));
        if constexpr (!OneRow) {
            c.sy[i] = _mm256_slli_epi32(dx[i], kSubpixelBits);
            any[2] = _mm256_or_si256(any[2], _mm256_add_epi32(em1, c.sy[i]));
            any[3] =
                _mm256_or_si256(any[3], _mm256_add_epi32(_mm256_add_epi32(em1, c.sx[i]), c.sy[i]));
        }
    }
    const __m256i wide = _mm256_cmpgt_epi32(colMax, c.colMin);
    const __m256i valid[4] = {ones, wide, tall, _mm256_and_si256(tall, wide)};
    __m256i mask = zero;
    for (int j = 0; j < (OneRow ? 2 : 4); ++j) {
        const __m256i in =
            _mm256_andnot_si256(_mm256_cmpgt_epi32(zero, any[j]), valid[j]);  // any >= 0
        mask = _mm256_or_si256(mask, _mm256_and_si256(in, _mm256_set1_epi32(1 << j)));
    }
    mask = _mm256_andnot_si256(_mm256_cmpeq_epi32(c.area, zero), mask);
    mask = _mm256_blendv_epi8(ones, mask, _mm256_or_si256(small, empty));  // general walk: −1
    c.mask = _mm256_andnot_si256(empty, mask);
    return c;
}

/// cover() of 8 lanes stored into columns [k, k + 8) of `o`. `live`: all-ones lanes. Returns
/// the live lanes whose mask is not 0, as bits from k.
inline std::uint64_t setupCore(__m256i X0, __m256i X1, __m256i X2, const __m256i Y[3],
                               __m256i rowMin, __m256i rowMax, __m256i live, int width,
                               ViewsSetup& o, int k) {
    const Cover c = cover(X0, X1, X2, Y, rowMin, rowMax, width);
    for (int i = 0; i < 3; ++i) {
        store(o.e[i] + k, c.e[i]);
        store(o.sx[i] + k, c.sx[i]);
        store(o.sy[i] + k, c.sy[i]);
        store(o.bias[i] + k, c.bias[i]);
    }
    store(o.mask + k, c.mask);
    store(o.colMin + k, c.colMin);
    store(o.area + k, c.area);
    const __m256i nonzero =
        _mm256_andnot_si256(_mm256_cmpeq_epi32(c.mask, _mm256_setzero_si256()), live);
    return std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(nonzero)))) << k;
}

/// Lanes [k, k + 8) live below n, as all-ones lanes.
inline __m256i liveLanes(int n, int k) {
    return _mm256_cmpgt_epi32(_mm256_set1_epi32(n - k), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
}

/// setupViews, 8 views per pass (the scalar reference: setupViewsTail).
std::uint64_t setupViews(const YSetup& ys, const std::int32_t* x0, const std::int32_t* x1,
                         const std::int32_t* x2, int n, int width, ViewsSetup& o) {
    const __m256i Y[3] = {_mm256_set1_epi32(ys.y[0]), _mm256_set1_epi32(ys.y[1]),
                          _mm256_set1_epi32(ys.y[2])};
    const __m256i rowMin = _mm256_set1_epi32(ys.rowMin), rowMax = _mm256_set1_epi32(ys.rowMax);
    std::uint64_t lanes = 0;
    for (int k = 0; k < n; k += 8) {
        const __m256i live = liveLanes(n, k);
        lanes |= setupCore(loadLanes(x0 + k, live), loadLanes(x1 + k, live),
                           loadLanes(x2 + k, live), Y, rowMin, rowMax, live, width, o, k);
    }
    return lanes;
}

/// kPack.lanes[mask]: the lanes of mask's set bits first, in order (3 bits each);
/// kPack.bytes[mask]: the same lanes as bytes (packed views' positions, branch-free: a loop over
/// the kept lanes cost a mispredicted branch per triangle and pass).
struct PackTables {
    std::array<std::uint32_t, 256> lanes{};
    std::array<std::uint64_t, 256> bytes{};
};
const PackTables kPack = [] {
    PackTables table;
    for (unsigned mask = 0; mask < 256; ++mask) {
        int slot = 0;
        for (unsigned lane = 0; lane < 8; ++lane) {
            if (!(mask & (1u << lane))) continue;
            table.lanes[mask] |= lane << (3 * slot);
            table.bytes[mask] |= std::uint64_t(lane) << (8 * slot);
            ++slot;
        }
    }
    return table;
}();

/// The permutation that moves the lanes of `keep` to the front, in order.
inline __m256i packPermutation(unsigned keep) {
    return _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32(std::int32_t(kPack.lanes[keep])),
                                              _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21)),
                            _mm256_set1_epi32(7));
}
/// Appends the positions k + lane of the lanes of `keep` to `view` (8 bytes written; k + 7 < 256:
/// no carry between bytes).
inline void packViews(unsigned keep, int k, std::uint8_t* view) {
    const std::uint64_t views = kPack.bytes[keep] + std::uint64_t(k) * 0x0101010101010101ull;
    std::memcpy(view, &views, sizeof views);
}

/// A sheared row's snapped x per view from its shear s: snap(cx + s·wc, q, width) per vertex
/// (shearClipWc, snapX: the scalar order).
struct ShearX {
    __m256 cx[3], wc[3], q[3], wd;
    ShearX(const ShearedTri& t, int width) : wd(_mm256_set1_ps(float(width))) {
        for (int j = 0; j < 3; ++j) {
            cx[j] = _mm256_set1_ps(t.cx[j]);
            wc[j] = _mm256_set1_ps(t.wc[j]);
            q[j] = _mm256_set1_ps(t.q[j]);
        }
    }
    void operator()(__m256 s, __m256i X[3]) const {
        for (int j = 0; j < 3; ++j)
            X[j] = snap(_mm256_add_ps(cx[j], _mm256_mul_ps(s, wc[j])), q[j], wd);
    }
};

/// The x of n <= kMaxViews views of a sheared row derived 8 views per pass (shearClipWc, snap:
/// the scalar order), the views with a pixel-center column (setupCore's colMin <= colMax) and not
/// in `culled` (drawSheared's bits; nullptr: none) packed in view order into `xs` (a permutation
/// from a table of the 256 masks). Returns how many.
inline int packSheared(const ShearedTri& t, const float* shears, int n, const std::uint64_t* culled,
                       int width, ViewsX& xs) {
    const ShearX deriveX(t, width);
    int m = 0;
    for (int k = 0; k < n; k += 8) {
        const __m256i live = liveLanes(n, k);
        const __m256 s = _mm256_maskload_ps(shears + k, live);
        __m256i X[3];
        deriveX(s, X);
        const __m256i xlo = _mm256_min_epi32(X[0], _mm256_min_epi32(X[1], X[2]));
        const __m256i xhi = _mm256_max_epi32(X[0], _mm256_max_epi32(X[1], X[2]));
        __m256i colMin, colMax;
        columnRange(xlo, xhi, width, colMin, colMax);
        const unsigned keep = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(
                                  _mm256_and_si256(cmple(colMin, colMax), live)))) &
                              ~unsigned(culled ? culled[k >> 6] >> (k & 63) : 0) & 0xffu;
        if (!keep) continue;
        const __m256i perm = packPermutation(keep);
        for (int j = 0; j < 3; ++j) store(xs.x[j] + m, _mm256_permutevar8x32_epi32(X[j], perm));
        packViews(keep, k, xs.view + m);  // ViewsX::view has room
        m += __builtin_popcount(keep);
    }
    return m;
}

/// setupSheared: packSheared, then setupCore 8 packed views a pass.
std::uint64_t setupSheared(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                           int width, ViewsSetup& o, ViewsX& xs) {
    const int m = packSheared(t, shears, n, nullptr, width, xs);
    const __m256i Y[3] = {_mm256_set1_epi32(ys.y[0]), _mm256_set1_epi32(ys.y[1]),
                          _mm256_set1_epi32(ys.y[2])};
    const __m256i rowMin = _mm256_set1_epi32(ys.rowMin), rowMax = _mm256_set1_epi32(ys.rowMax);
    std::uint64_t lanes = 0;
    for (int i = 0; i < m; i += 8) {
        const __m256i live = liveLanes(m, i);
        lanes |= setupCore(loadLanes(xs.x[0] + i, live), loadLanes(xs.x[1] + i, live),
                           loadLanes(xs.x[2] + i, live), Y, rowMin, rowMax, live, width, o, i);
    }
    return lanes;
}

/// A triangle's fragment inputs broadcast to 8 lanes (shadeGroup).
struct LaneFragment {
    __m256 z[3], q[3], a[3][3];
    __m256i flatColor, top, W;
    bool flat;
};

inline LaneFragment laneFragment(const FragmentTri& tri, bool flat, int rowMin, int width,
                                 int height) {
    LaneFragment f;
    for (int j = 0; j < 3; ++j) {
        f.z[j] = _mm256_set1_ps(tri.z[j]);
        f.q[j] = _mm256_set1_ps(tri.q[j]);
        for (int c = 0; c < 3; ++c) f.a[j][c] = _mm256_set1_ps(flat ? 0.0f : tri.attr[j][c]);
    }
    f.flatColor = _mm256_set1_epi32(std::int32_t(tri.flat));
    f.top = _mm256_set1_epi32(height - 1 - rowMin), f.W = _mm256_set1_epi32(width);
    f.flat = flat;
    return f;
}

/// The fragments of 8 lanes side by side: `rem` holds each lane's covered 2×2 centers (0: none),
/// lane k draws into depth[slot[k]] / color[slot[k]] (all 8 bytes of `slot` must index the
/// tables). Per pass the lowest covered center of every lane (a lane with several covered
/// centers takes one pass each), FragmentSink's operations on vectors, the depth of each lane's
/// pixel gathered from its own view, and the passing fragments written lane by lane. OneRow:
/// no lane has centers 2 or 3 (cover<true>: sy is not read).
/// Block: the images lie in one block (drawSheared's blockStride): a lane's pixel is a 32-bit
/// offset from depth[0] / color[0], one gather of 8 lanes instead of the views' addresses
/// gathered from the tables and two gathers of 4.
template <bool OneRow = false, bool Block = false>
inline void shadeGroup(const LaneFragment& f, const Cover& c, __m256i rem, const std::uint8_t* slot,
                       float* const* depth, std::uint32_t* const* color,
                       std::int32_t blockStride = 0) {
    const __m256i zero = _mm256_setzero_si256(), one = _mm256_set1_epi32(1);
    const __m256 fzero = _mm256_setzero_ps(), fone = _mm256_set1_ps(1.0f);
    // The lanes' views: slot[k] picks their images' addresses (gathered, 64-bit).
    const __m256i slots =
        _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(slot)));
    __m256i dLo = zero, dHi = zero, block = zero;
    if constexpr (Block) {
        block = _mm256_mullo_epi32(slots, _mm256_set1_epi32(blockStride));
    } else {
        const auto* depthTable = reinterpret_cast<const long long*>(depth);
        dLo = _mm256_i32gather_epi64(depthTable, _mm256_castsi256_si128(slots), 8);
        dHi = _mm256_i32gather_epi64(depthTable, _mm256_extracti128_si256(slots, 1), 8);
    }
    const __m256 invArea = _mm256_div_ps(fone, _mm256_cvtepi32_ps(c.area));
    while (!_mm256_testz_si256(rem, rem)) {
        const __m256i low = _mm256_and_si256(rem, _mm256_sub_epi32(zero, rem));
        rem = _mm256_xor_si256(rem, low);
        const __m256i active = _mm256_cmpgt_epi32(low, zero);
        // Column j & 1 (centers 1 and 3), row j >> 1 (centers 2 and 3).
        const __m256i cx = _mm256_cmpgt_epi32(_mm256_and_si256(low, _mm256_set1_epi32(0xA)), zero);
        const __m256i cy =
            OneRow ? zero : _mm256_cmpgt_epi32(_mm256_and_si256(low, _mm256_set1_epi32(0xC)), zero);
        __m256 l[3];
        for (int i = 0; i < 3; ++i) {
            __m256i ei = _mm256_add_epi32(c.e[i], _mm256_and_si256(cx, c.sx[i]));
            if constexpr (!OneRow) ei = _mm256_add_epi32(ei, _mm256_and_si256(cy, c.sy[i]));
            ei = _mm256_sub_epi32(ei, c.bias[i]);
            l[i] = _mm256_mul_ps(_mm256_cvtepi32_ps(ei), invArea);
        }
        const __m256 zf =
            _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(l[0], f.z[0]), _mm256_mul_ps(l[1], f.z[1])),
                          _mm256_mul_ps(l[2], f.z[2]));
        const __m256i x = _mm256_add_epi32(c.colMin, _mm256_and_si256(cx, one));
        const __m256i index = _mm256_add_epi32(
            _mm256_mullo_epi32(_mm256_sub_epi32(f.top, _mm256_and_si256(cy, one)), f.W), x);
        // The lanes' depth: their view's image at their pixel.
        const __m256 am = _mm256_castsi256_ps(active);
        __m256i off = index;
        __m256 d;
        if constexpr (Block) {
            off = _mm256_add_epi32(block, index);
            d = _mm256_mask_i32gather_ps(fzero, depth[0], off, am, 4);
        } else {
            const __m256i offLo =
                _mm256_slli_epi64(_mm256_cvtepi32_epi64(_mm256_castsi256_si128(index)), 2);
            const __m256i offHi =
                _mm256_slli_epi64(_mm256_cvtepi32_epi64(_mm256_extracti128_si256(index, 1)), 2);
            const __m128 gLo =
                _mm256_mask_i64gather_ps(_mm_setzero_ps(), nullptr, _mm256_add_epi64(dLo, offLo),
                                         _mm256_castps256_ps128(am), 1);
            const __m128 gHi =
                _mm256_mask_i64gather_ps(_mm_setzero_ps(), nullptr, _mm256_add_epi64(dHi, offHi),
                                         _mm256_extractf128_ps(am, 1), 1);
            d = _mm256_set_m128(gHi, gLo);
        }
        const unsigned pass =
            unsigned(_mm256_movemask_ps(_mm256_and_ps(_mm256_cmp_ps(zf, d, _CMP_LT_OQ), am)));
        if (!pass) continue;
        __m256i packed = f.flatColor;
        if (!f.flat) {
            const __m256 p0 = _mm256_mul_ps(l[0], f.q[0]), p1 = _mm256_mul_ps(l[1], f.q[1]),
                         p2 = _mm256_mul_ps(l[2], f.q[2]);
            const __m256 inv = _mm256_div_ps(fone, _mm256_add_ps(_mm256_add_ps(p0, p1), p2));
            packed = _mm256_set1_epi32(std::int32_t(0xff000000u));
            for (int ch = 0; ch < 3; ++ch) {
                const __m256 v = _mm256_mul_ps(
                    _mm256_add_ps(
                        _mm256_add_ps(_mm256_mul_ps(p0, f.a[0][ch]), _mm256_mul_ps(p1, f.a[1][ch])),
                        _mm256_mul_ps(p2, f.a[2][ch])),
                    inv);
                // quantizeUnorm8: std::clamp(v, 0, 1) · 255 + 0.5, truncated to 8 bits.
                __m256 t = _mm256_blendv_ps(v, fzero, _mm256_cmp_ps(v, fzero, _CMP_LT_OQ));
                t = _mm256_blendv_ps(t, fone, _mm256_cmp_ps(fone, t, _CMP_LT_OQ));
                t = _mm256_add_ps(_mm256_mul_ps(t, _mm256_set1_ps(255.0f)), _mm256_set1_ps(0.5f));
                const __m256i u = _mm256_and_si256(_mm256_cvttps_epi32(t), _mm256_set1_epi32(0xff));
                packed = _mm256_or_si256(packed, _mm256_slli_epi32(u, 8 * ch));
            }
        }
        alignas(32) float zs[8];
        alignas(32) std::int32_t is[8], cs[8];
        _mm256_store_ps(zs, zf);
        store(is, off);
        store(cs, packed);
        for (unsigned m = pass; m; m &= m - 1) {
            const int k = __builtin_ctz(m);
            if constexpr (Block) {
                depth[0][is[k]] = zs[k];
                color[0][is[k]] = std::uint32_t(cs[k]);
                continue;
            }
            depth[slot[k]][is[k]] = zs[k];
            color[slot[k]][is[k]] = std::uint32_t(cs[k]);
        }
    }
}

/// shadeLanes: 8 lanes of the ViewsSetup a pass (shadeGroup).
std::uint64_t shadeLanes(const ViewsSetup& s, std::uint64_t lanes, int rowMin, int width,
                         int height, const FragmentTri& tri, bool flat, const std::uint8_t* slot,
                         float* const* depth, std::uint32_t* const* color) {
    const __m256i zero = _mm256_setzero_si256();
    const __m256i bitOf = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const LaneFragment f = laneFragment(tri, flat, rowMin, width, height);
    std::uint64_t general = 0;
    for (int g = 0; g < 64; g += 8) {
        const unsigned bits = unsigned(lanes >> g) & 0xffu;
        if (!bits) continue;
        const __m256i live =
            _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(bits)), bitOf), bitOf);
        Cover c;
        c.mask = load(s.mask + g);
        const __m256i negative = _mm256_cmpgt_epi32(zero, c.mask);
        general |= std::uint64_t(unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(negative))) & bits)
                   << g;
        c.colMin = load(s.colMin + g), c.area = load(s.area + g);
        for (int i = 0; i < 3; ++i) {
            c.e[i] = load(s.e[i] + g), c.sx[i] = load(s.sx[i] + g), c.sy[i] = load(s.sy[i] + g);
            c.bias[i] = load(s.bias[i] + g);
        }
        shadeGroup(f, c, _mm256_andnot_si256(negative, _mm256_and_si256(c.mask, live)), slot + g,
                   depth, color);
    }
    return general;
}

/// drawSheared's setup and fragments of the m packed views (OneRow: ys.rowMax == ys.rowMin, as
/// for most triangles of a dense mesh within a band). Their x: xs.x, or with `deriveX` derived
/// here from their shears ps[0, m) (then stored only for the views left to the general walk).
template <bool OneRow>
int drawPacked(const YSetup& ys, int m, int width, int height, const FragmentTri& tri, bool flat,
               float* const* depth, std::uint32_t* const* color, std::int32_t blockStride,
               ViewsX& xs, const ShearX* deriveX = nullptr, const float* ps = nullptr) {
    const __m256i zero = _mm256_setzero_si256();
    const __m256i Y[3] = {_mm256_set1_epi32(ys.y[0]), _mm256_set1_epi32(ys.y[1]),
                          _mm256_set1_epi32(ys.y[2])};
    const __m256i rowMin = _mm256_set1_epi32(ys.rowMin), rowMax = _mm256_set1_epi32(ys.rowMax);
    LaneFragment f;  // broadcast when a first lane has a covered center
    bool haveFragment = false;
    int general = 0;
    for (int i = 0; i < m; i += 8) {
        const __m256i live = liveLanes(m, i);
        __m256i X[3];
        if (deriveX) {
            (*deriveX)(_mm256_maskload_ps(ps + i, live), X);
        } else {
            for (int j = 0; j < 3; ++j) X[j] = loadLanes(xs.x[j] + i, live);
        }
        const Cover c = cover<OneRow>(X[0], X[1], X[2], Y, rowMin, rowMax, width);
        const __m256i negative = _mm256_and_si256(_mm256_cmpgt_epi32(zero, c.mask), live);
        const __m256i rem = _mm256_andnot_si256(negative, _mm256_and_si256(c.mask, live));
        if (!_mm256_testz_si256(rem, rem)) {
            if (!haveFragment) f = laneFragment(tri, flat, ys.rowMin, width, height);
            haveFragment = true;
            if (blockStride > 0) {
                shadeGroup<OneRow, true>(f, c, rem, xs.view + i, depth, color, blockStride);
            } else {
                shadeGroup<OneRow, false>(f, c, rem, xs.view + i, depth, color);
            }
        }
        // General lanes to the front (general <= i + k: positions already read).
        const unsigned g0 = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(negative)));
        if (!g0) continue;
        alignas(32) std::int32_t xg[3][8];
        for (int j = 0; j < 3; ++j) store(xg[j], X[j]);
        for (unsigned g = g0; g; g &= g - 1) {
            const int k = __builtin_ctz(g);
            for (int j = 0; j < 3; ++j) xs.x[j][general] = xg[j][k];
            xs.view[general++] = xs.view[i + k];
        }
    }
    return general;
}

/// The views of a one-row triangle (ys.rowMin == ys.rowMax) that may cover a pixel center of
/// that row, found from the epipolar-plane image (Halle's multiple-viewpoint rendering): on the
/// row's center line the triangle's span has endpoints that move linearly with the shear, so for
/// every view its span [lo(s), hi(s)] is two multiply-adds away, without deriving and snapping
/// the view's x. The estimate is widened by a bound on what snapping and float rounding can move
/// a vertex (a few 1/256 px), so a view is left out only when no center of the row can be
/// covered in it: the images do not change, only views that would draw nothing are skipped.
/// The others that are not in `culled` are packed in view order: their shears into ps, their
/// positions into xs.view. Returns how many (0 when the triangle misses the row's center line).
template <bool Culled>  // false: culled is nullptr
inline int packOnRow(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                     const std::uint64_t* culled, int width, float* ps, ViewsX& xs) {
    RowSpan r;
    if (!rowSpan(ys, t, width, r)) return 0;
    const __m256 slack0 = _mm256_set1_ps(r.slack0), slack1 = _mm256_set1_ps(r.slack1);
    const __m256 A[3] = {_mm256_set1_ps(lane<0>(r.pa)), _mm256_set1_ps(lane<1>(r.pa)),
                         _mm256_set1_ps(lane<2>(r.pa))};
    const __m256 B[3] = {_mm256_set1_ps(lane<0>(r.pb)), _mm256_set1_ps(lane<1>(r.pb)),
                         _mm256_set1_ps(lane<2>(r.pb))};
    const __m256 absMask = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps(),
                 lastCol = _mm256_set1_ps(float(width - 1));
    int m = 0;
    auto group = [&](int k, unsigned live) {
        const __m256 s = _mm256_loadu_ps(shears + k);  // readable to n rounded up to 8
        const __m256 e0 = _mm256_fmadd_ps(s, B[0], A[0]), e1 = _mm256_fmadd_ps(s, B[1], A[1]),
                     e2 = _mm256_fmadd_ps(s, B[2], A[2]);
        const __m256 slack = _mm256_fmadd_ps(_mm256_andnot_ps(absMask, s), slack1, slack0);
        // A column center c in [lo, hi] within the image [0, width - 1]: the last one at or
        // below hi, c = min(floor(hi), width - 1), is one when c >= max(lo, 0).
        const __m256 lo =
            _mm256_max_ps(zero, _mm256_sub_ps(_mm256_min_ps(e0, _mm256_min_ps(e1, e2)), slack));
        const __m256 c = _mm256_min_ps(
            lastCol, _mm256_round_ps(_mm256_add_ps(_mm256_max_ps(e0, _mm256_max_ps(e1, e2)), slack),
                                     _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
        unsigned keep = unsigned(_mm256_movemask_ps(_mm256_cmp_ps(lo, c, _CMP_LE_OQ))) & live;
        if constexpr (Culled) keep &= ~unsigned(culled[k >> 6] >> (k & 63));
        // No branch on an empty group (whether a group keeps a view follows no pattern: a
        // mispredicted branch cost more than the stores; this kernel on a Sapphire Rapids
        // host, single thread, 100 views 200.4 -> 182.4 ms): nothing is kept, m does not
        // move, the next group overwrites the stores.
        _mm256_storeu_ps(ps + m, _mm256_permutevar8x32_ps(s, packPermutation(keep)));
        packViews(keep, k, xs.view + m);
        m += __builtin_popcount(keep);
    };
    int k = 0;
    for (; k + 8 <= n; k += 8) group(k, 0xffu);
    if (k < n) group(k, (1u << (n - k)) - 1u);
    return m;
}

/// drawSheared: packSheared, then per 8 packed views cover() and shadeGroup in registers; the
/// views left to the general walk are moved to the front of `xs`. A one-row triangle packs only
/// the views that may cover a center of its row (packOnRow), and derives their x as it draws.
int drawSheared(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                const std::uint64_t* culled, int width, int height, const FragmentTri& tri,
                bool flat, float* const* depth, std::uint32_t* const* color,
                std::int32_t blockStride, ViewsX& xs) {
    if (ys.rowMax == ys.rowMin) {
        alignas(32) float ps[kMaxViews + 8];  // + room for a whole register's store
        const int m = culled ? packOnRow<true>(ys, t, shears, n, culled, width, ps, xs)
                             : packOnRow<false>(ys, t, shears, n, nullptr, width, ps, xs);
        if (m == 0) return 0;
        const ShearX deriveX(t, width);
        return drawPacked<true>(ys, m, width, height, tri, flat, depth, color, blockStride, xs,
                                &deriveX, ps);
    }
    const int m = packSheared(t, shears, n, culled, width, xs);
    return m == 0
               ? 0
               : drawPacked<false>(ys, m, width, height, tri, flat, depth, color, blockStride, xs);
}

/// setupLanes: two passes of 8 lanes.
std::uint32_t setupLanes(TriangleLanes& l, int n, int width) {
    std::uint64_t lanes = 0;
    for (int k = 0; k < n; k += 8) {
        const __m256i live = liveLanes(n, k);
        const __m256i Y[3] = {loadLanes(l.y[0] + k, live), loadLanes(l.y[1] + k, live),
                              loadLanes(l.y[2] + k, live)};
        lanes |= setupCore(loadLanes(l.x[0] + k, live), loadLanes(l.x[1] + k, live),
                           loadLanes(l.x[2] + k, live), Y, loadLanes(l.rowMin + k, live),
                           loadLanes(l.rowMax + k, live), live, width, l.out, k);
    }
    return std::uint32_t(lanes);
}

/// glm's scalar semantics, lane by lane: max(x, y) = x < y ? y : x; min(x, y) = y < x ? y : x.
inline __m256 glmMax(__m256 x, __m256 y) {
    return _mm256_blendv_ps(x, y, _mm256_cmp_ps(x, y, _CMP_LT_OQ));
}
inline __m256 glmMin(__m256 x, __m256 y) {
    return _mm256_blendv_ps(x, y, _mm256_cmp_ps(y, x, _CMP_LT_OQ));
}
inline __m256 dot3(__m256 ax, __m256 ay, __m256 az, __m256 bx, __m256 by, __m256 bz) {
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(ax, bx), _mm256_mul_ps(ay, by)),
                         _mm256_mul_ps(az, bz));
}
/// glm::normalize: v * (1 / sqrt(dot(v, v))).
inline void normalize3(__m256& x, __m256& y, __m256& z) {
    const __m256 s = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(dot3(x, y, z, x, y, z)));
    x = _mm256_mul_ps(x, s), y = _mm256_mul_ps(y, s), z = _mm256_mul_ps(z, s);
}

/// lighting.h's specularPow, 8 lanes: the same float / integer operations in the same order.
inline __m256 specularPow8(__m256 x, float s) {
    using namespace pow_detail;
    const __m256 tiny = _mm256_cmp_ps(x, _mm256_set1_ps(0x1p-126f), _CMP_LT_OQ);
    const __m256 xs = _mm256_blendv_ps(x, _mm256_mul_ps(x, _mm256_set1_ps(0x1p23f)), tiny);
    const __m256i t = _mm256_sub_epi32(_mm256_castps_si256(xs), _mm256_set1_epi32(kSqrtHalfBits));
    const __m256i e =
        _mm256_sub_epi32(_mm256_srai_epi32(t, 23),
                         _mm256_and_si256(_mm256_castps_si256(tiny), _mm256_set1_epi32(23)));
    const __m256 f = _mm256_sub_ps(
        _mm256_castsi256_ps(_mm256_add_epi32(_mm256_and_si256(t, _mm256_set1_epi32(0x007fffff)),
                                             _mm256_set1_epi32(kSqrtHalfBits))),
        _mm256_set1_ps(1.0f));
    __m256 p = _mm256_set1_ps(kLog2[8]);
    for (int k = 7; k >= 0; --k) p = _mm256_add_ps(_mm256_mul_ps(p, f), _mm256_set1_ps(kLog2[k]));
    const __m256 l = _mm256_add_ps(_mm256_cvtepi32_ps(e), _mm256_mul_ps(f, p));
    __m256 y = _mm256_mul_ps(_mm256_set1_ps(s), l);
    y = _mm256_max_ps(y, _mm256_set1_ps(-kYMax));  // y > −Y ? y : −Y (NaN → −Y), as the scalar code
    y = _mm256_min_ps(y, _mm256_set1_ps(kYMax));  // y < Y ? y : Y
    const __m256 rnd = _mm256_set1_ps(kRound);
    const __m256 nf = _mm256_sub_ps(_mm256_add_ps(y, rnd), rnd);
    const __m256 r = _mm256_sub_ps(y, nf);
    __m256 q = _mm256_set1_ps(kExp2[5]);
    for (int k = 4; k >= 0; --k) q = _mm256_add_ps(_mm256_mul_ps(q, r), _mm256_set1_ps(kExp2[k]));
    const __m256 m = _mm256_add_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(r, q));
    const __m256i n = _mm256_cvttps_epi32(nf);  // nf is an integer: exact
    const __m256i a = _mm256_srai_epi32(n, 1), b = _mm256_sub_epi32(n, a);
    const __m256i bias = _mm256_set1_epi32(127);
    __m256 res = _mm256_mul_ps(
        _mm256_mul_ps(m, _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(a, bias), 23))),
        _mm256_castsi256_ps(_mm256_slli_epi32(_mm256_add_epi32(b, bias), 23)));
    res = _mm256_blendv_ps(res, _mm256_set1_ps(powOfZero(s)),
                           _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_EQ_OQ));
    return _mm256_add_ps(res, _mm256_sub_ps(x, x));
}

/// shadeVerticesTail with 8 vertices per register (the AVX-512 kernel's operations on 8 lanes).
void shadeVertices(const glm::vec3* positions, const glm::vec3* normals, std::size_t n,
                   const glm::mat4& W, const glm::mat3& N, const ShadingContext& ctx,
                   const Material& m, float* color) {
    const __m256i idx3 = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const glm::vec3 ambient = ctx.ambient * m.albedo;
    const __m256 specular = _mm256_set1_ps(m.specular);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const float* p = &positions[i].x;
        const float* q = &normals[i].x;
        const __m256 px = _mm256_i32gather_ps(p, idx3, 4), py = _mm256_i32gather_ps(p + 1, idx3, 4),
                     pz = _mm256_i32gather_ps(p + 2, idx3, 4);
        __m256 nx = _mm256_i32gather_ps(q, idx3, 4), ny = _mm256_i32gather_ps(q + 1, idx3, 4),
               nz = _mm256_i32gather_ps(q + 2, idx3, 4);
        __m256 wp[3], nn[3];
        for (int r = 0; r < 3; ++r) {
            wp[r] = _mm256_add_ps(
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(W[0][r]), px),
                                            _mm256_mul_ps(_mm256_set1_ps(W[1][r]), py)),
                              _mm256_mul_ps(_mm256_set1_ps(W[2][r]), pz)),
                _mm256_set1_ps(W[3][r]));
            nn[r] = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(N[0][r]), nx),
                                                _mm256_mul_ps(_mm256_set1_ps(N[1][r]), ny)),
                                  _mm256_mul_ps(_mm256_set1_ps(N[2][r]), nz));
        }
        nx = nn[0], ny = nn[1], nz = nn[2];
        normalize3(nx, ny, nz);
        __m256 vx = _mm256_sub_ps(_mm256_set1_ps(ctx.centerEye.x), wp[0]);
        __m256 vy = _mm256_sub_ps(_mm256_set1_ps(ctx.centerEye.y), wp[1]);
        __m256 vz = _mm256_sub_ps(_mm256_set1_ps(ctx.centerEye.z), wp[2]);
        normalize3(vx, vy, vz);
        __m256 cr = _mm256_set1_ps(ambient.x), cg = _mm256_set1_ps(ambient.y),
               cb = _mm256_set1_ps(ambient.z);
        for (const DirectionalLight& l : ctx.lights) {
            const __m256 lx = _mm256_set1_ps(l.towardLight.x), ly = _mm256_set1_ps(l.towardLight.y),
                         lz = _mm256_set1_ps(l.towardLight.z);
            const __m256 nl = dot3(nx, ny, nz, lx, ly, lz);
            const __m256 lit = _mm256_cmp_ps(nl, zero, _CMP_GT_OQ);
            if (_mm256_movemask_ps(lit) == 0) continue;
            __m256 hx = _mm256_add_ps(lx, vx), hy = _mm256_add_ps(ly, vy),
                   hz = _mm256_add_ps(lz, vz);
            normalize3(hx, hy, hz);
            const __m256 nh = dot3(nx, ny, nz, hx, hy, hz);
            const __m256 base = _mm256_blendv_ps(nh, zero, _mm256_cmp_ps(nh, zero, _CMP_LT_OQ));
            const __m256 spec = _mm256_mul_ps(specular, specularPow8(base, m.shininess));
            const __m256 ar =
                _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(nl, _mm256_set1_ps(m.albedo.x)), spec),
                              _mm256_set1_ps(l.color.x));
            const __m256 ag =
                _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(nl, _mm256_set1_ps(m.albedo.y)), spec),
                              _mm256_set1_ps(l.color.y));
            const __m256 ab =
                _mm256_mul_ps(_mm256_add_ps(_mm256_mul_ps(nl, _mm256_set1_ps(m.albedo.z)), spec),
                              _mm256_set1_ps(l.color.z));
            cr = _mm256_blendv_ps(cr, _mm256_add_ps(cr, ar), lit);
            cg = _mm256_blendv_ps(cg, _mm256_add_ps(cg, ag), lit);
            cb = _mm256_blendv_ps(cb, _mm256_add_ps(cb, ab), lit);
        }
        cr = glmMin(glmMax(cr, zero), one);
        cg = glmMin(glmMax(cg, zero), one);
        cb = glmMin(glmMax(cb, zero), one);
        alignas(32) float t[3][8];
        _mm256_store_ps(t[0], cr), _mm256_store_ps(t[1], cg), _mm256_store_ps(t[2], cb);
        float* o = color + 3 * i;
        for (int k = 0; k < 8; ++k)
            o[3 * k] = t[0][k], o[3 * k + 1] = t[1][k], o[3 * k + 2] = t[2][k];
    }
    // The tail through the scalar table: lighting.h's shadeBlinnPhong is an inline function with
    // external linkage; an out-of-line copy compiled here, with this file's target flags, is
    // one the linker may keep for every caller (tests/raster/simd_objects.cmake).
    scalarKernels().shadeVertices(positions + i, normals + i, n - i, W, N, ctx, m, color + 3 * i);
}

/// transformPointsTail with 8 vertices per register.
void transformPoints(const glm::vec3* positions, std::size_t n, const glm::mat4& M, float* x,
                     float* y, float* z, float* w) {
    const __m256i idx3 = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    float* out[4] = {x, y, z, w};
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        const float* p = &positions[i].x;
        const __m256 px = _mm256_i32gather_ps(p, idx3, 4), py = _mm256_i32gather_ps(p + 1, idx3, 4),
                     pz = _mm256_i32gather_ps(p + 2, idx3, 4);
        for (int r = 0; r < 4; ++r) {
            const __m256 v = _mm256_add_ps(
                _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(M[0][r]), px),
                                            _mm256_mul_ps(_mm256_set1_ps(M[1][r]), py)),
                              _mm256_mul_ps(_mm256_set1_ps(M[2][r]), pz)),
                _mm256_set1_ps(M[3][r]));
            _mm256_storeu_ps(out[r] + i, v);
        }
    }
    transformPointsTail(positions + i, n - i, M, x + i, y + i, z + i, w + i);
}

void specularPowN(const float* x, std::size_t n, float s, float* out) {
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) _mm256_storeu_ps(out + i, specularPow8(_mm256_loadu_ps(x + i), s));
    specularPowTail(x + i, n - i, s, out + i);
}

}  // namespace

const Kernels* avx2Kernels() {
    static const Kernels k{&projectYZW,      &projectX,     &setupViews, &shadeVertices,
                           &transformPoints, &specularPowN, &setupLanes, &setupSheared,
                           &shadeLanes,      &drawSheared,  &rowClipX,   nullptr,
                           &rowSnapX};
    return &k;
}

}  // namespace mvr::raster::detail
