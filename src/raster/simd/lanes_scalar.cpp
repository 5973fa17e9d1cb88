// setupLanes, scalar: lane by lane through setupViewsTail — the reference of the SIMD paths.
#include "../cpu.h"
#include "../lanes.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

std::uint32_t setupLanesScalar(TriangleLanes& l, int n, int width) {
    std::uint32_t lanes = 0;
    for (int k = 0; k < n; ++k) {
        YSetup ys;
        setupY(ys, l.y[0][k], l.y[1][k], l.y[2][k], l.rowMin[k], l.rowMax[k]);
        ys.rowMin = l.rowMin[k], ys.rowMax = l.rowMax[k];
        lanes |= std::uint32_t(setupViewsTail(ys, l.x[0], l.x[1], l.x[2], k, k + 1, width, l.out));
    }
    return lanes;
}

#if !defined(MVR_HAVE_AVX2_KERNELS)
SetupLanesFn setupLanesAvx2() { return nullptr; }
#endif
#if !defined(MVR_HAVE_AVX512_KERNELS)
SetupLanesFn setupLanesAvx512() { return nullptr; }
#endif

SetupLanesFn setupLanesKernel(SimdPath path) {
    switch (resolveSimd(path)) {
        case SimdPath::Avx512: return setupLanesAvx512();
        case SimdPath::Avx2: return setupLanesAvx2();
        default: return &setupLanesScalar;
    }
}

}  // namespace mvr::raster::detail
