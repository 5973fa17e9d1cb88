// src/vk/spirv.h — the SPIR-V of shaders/, compiled by glslc at build time (CMakeLists.txt).
#pragma once

#include <cstdint>
#include <span>

#include "mvr/core/lighting.h"

namespace mvr::vk::detail {

/// Where the vertex shader takes its view index from.
enum class ViewSource { Pass, Multiview, Layer };

std::span<const std::uint32_t> sceneVertexSpirv(Shading shading, ViewSource views);
std::span<const std::uint32_t> sceneFragmentSpirv(Shading shading);

}  // namespace mvr::vk::detail
