// src/raster/simd/kernels_avx512_vertex.h — the AVX-512 vertex-stage kernels of
// kernels_avx512_vertex.cpp, for avx512Kernels()'s table (kernels_avx512.cpp).
#pragma once

#include <cstddef>

#include "../cpu.h"

namespace mvr::raster::detail::avx512 {

/// Kernels::shadeVertices (ShadeVerticesFn), 16 vertices per register.
void shadeVertices(const glm::vec3* positions, const glm::vec3* normals, std::size_t n,
                   const glm::mat4& W, const glm::mat3& N, const ShadingContext& ctx,
                   const Material& m, float* color);
/// Kernels::transformPoints (TransformPointsFn), 16 vertices per register.
void transformPoints(const glm::vec3* positions, std::size_t n, const glm::mat4& M, float* x,
                     float* y, float* z, float* w);
/// Kernels::specularPow (SpecularPowFn), 16 values per register.
void specularPowN(const float* x, std::size_t n, float s, float* out);

}  // namespace mvr::raster::detail::avx512
