// The scalar kernels: the reference every SIMD path must equal bit for bit.
#include "../cpu.h"
#include "../pipeline.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

const Kernels& scalarKernels() {
    static const Kernels k{&projectYZWTail,
                           &projectXTail,
                           [](const YSetup& ys, const std::int32_t* x0, const std::int32_t* x1,
                              const std::int32_t* x2, int n, int width, ViewsSetup& out) {
                               return setupViewsTail(ys, x0, x1, x2, 0, n, width, out);
                           },
                           &shadeVerticesTail,
                           &transformPointsTail,
                           &specularPowTail,
                           &setupLanesTail,
                           [](const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                              int width, ViewsSetup& out, ViewsX& x) {
                               return setupShearedTail(ys, t, shears, n, width, out, x);
                           },
                           &shadeLanesTail,
                           &drawShearedTail,
                           &rowClipXTail,
                           nullptr,
                           &rowSnapXTail};
    return k;
}

#if !defined(MVR_HAVE_AVX2_KERNELS)
const Kernels* avx2Kernels() { return nullptr; }
#endif
#if !defined(MVR_HAVE_AVX512_KERNELS)
const Kernels* avx512Kernels() { return nullptr; }
#endif

}  // namespace mvr::raster::detail
