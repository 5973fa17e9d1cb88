#include "cpu.h"

#include <fstream>

namespace mvr::raster::detail {

SimdPath bestSupportedSimd() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    if (avx512Kernels() && __builtin_cpu_supports("avx512f") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512dq")) {
        return SimdPath::Avx512;
    }
    if (avx2Kernels() && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        return SimdPath::Avx2;
    }
#endif
    return SimdPath::Scalar;
}

SimdPath resolveSimd(SimdPath requested) {
    const SimdPath best = bestSupportedSimd();
    if (requested == SimdPath::Auto) return best;
    if (requested == SimdPath::Avx512 && best != SimdPath::Avx512) return best;
    if (requested == SimdPath::Avx2 && best == SimdPath::Scalar) return best;
    return requested;
}

const Kernels& kernels(SimdPath path) {
    switch (resolveSimd(path)) {
        case SimdPath::Avx512: return *avx512Kernels();
        case SimdPath::Avx2: return *avx2Kernels();
        default: return scalarKernels();
    }
}

}  // namespace mvr::raster::detail
