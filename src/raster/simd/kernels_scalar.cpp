// The scalar kernels: the reference every SIMD path must equal bit for bit.
#include "../cpu.h"
#include "../pipeline.h"
#include "kernels_tail.h"

namespace mvr::raster::detail {

const Kernels& scalarKernels() {
    static const Kernels k{&projectYZWTail, &projectXTail};
    return k;
}

#if !defined(MVR_HAVE_AVX2_KERNELS)
const Kernels* avx2Kernels() { return nullptr; }
#endif
#if !defined(MVR_HAVE_AVX512_KERNELS)
const Kernels* avx512Kernels() { return nullptr; }
#endif

}  // namespace mvr::raster::detail
