// bench/micro/micro.h — what the micro benchmarks share: the SIMD paths this build and CPU run,
// and deterministic inputs.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "cpu.h"

namespace mvr::bench {

/// One SIMD path of the soft backend's kernel table that this build compiled and this CPU runs.
struct KernelPath {
    raster::SimdPath path;
    const raster::detail::Kernels* kernels;
    std::string name;  ///< "scalar" | "avx2" | "avx512"
};

inline std::vector<KernelPath> kernelPaths() {
    std::vector<KernelPath> paths;
    for (raster::SimdPath p :
         {raster::SimdPath::Scalar, raster::SimdPath::Avx2, raster::SimdPath::Avx512}) {
        if (raster::detail::resolveSimd(p) != p) continue;  // not built, or not on this CPU
        paths.push_back({p, &raster::detail::kernels(p), raster::simdPathName(p)});
    }
    return paths;
}

/// The same inputs every run: a fixed seed.
inline std::mt19937 benchRng() { return std::mt19937(20261122); }

}  // namespace mvr::bench
