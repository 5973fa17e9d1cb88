// src/raster/lanes.h — coverage setup of many (triangle, view) pairs side by side.
//
// setupViews (cpu.h) runs one triangle's views in SIMD lanes; for a stereo pair that fills 2 of
// 8 lanes and pays the kernel's whole latency for every triangle. Here a band's raster loop
// queues the (triangle, view) pairs of consecutive small triangles — for a stereo pair 8
// triangles × 2 views — and sets them all up in one pass: per lane the triangle's snapped x in
// that view and its y setup (computed ONCE per triangle and family, then copied into each of its
// views' lanes: adelson1991's shared y). The integers are those of setupViews lane for lane, so
// images do not change; each view still receives its triangles in submission order.
#pragma once

#include <cstdint>

#include "mvr/raster/soft_backend.h"
#include "pipeline.h"

namespace mvr::raster::detail {

inline constexpr int kLaneCount = 16;

struct TriangleLanes {
    alignas(64) std::int32_t x[3][kLaneCount];  ///< snapped window x of the lane's view
    alignas(64) std::int32_t y[3][kLaneCount];  ///< snapped window y (the triangle's, shared)
    alignas(64) std::int32_t rowMin[kLaneCount];  ///< YSetup rows, clamped to the band, not empty
    alignas(64) std::int32_t rowMax[kLaneCount];
    ViewsSetup out;  ///< lane k's results in column k, as setupViews writes view k's
};

/// Lanes [0, n) of `l` (n <= kLaneCount): fills l.out like setupViews fills a view (mask, colMin,
/// area, e, sx, sy, bias) and returns the lanes whose mask is not 0 (bit k: lane k).
using SetupLanesFn = std::uint32_t (*)(TriangleLanes& l, int n, int width);

/// The kernel of a SIMD path (scalar, AVX2, AVX-512; resolved like kernels()).
SetupLanesFn setupLanesKernel(SimdPath path);

std::uint32_t setupLanesScalar(TriangleLanes& l, int n, int width);
SetupLanesFn setupLanesAvx2();    ///< nullptr when not built
SetupLanesFn setupLanesAvx512();  ///< nullptr when not built

}  // namespace mvr::raster::detail
