// mvr/vk/vk_backend.h — the Vulkan backend ("vk"): Vulkan 1.2, headless (no surface, no window
// system), built when libvulkan and glslc are found (MVR_WITH_VULKAN). src/vk/README.md has the
// details.
//
// Conventions: those of the gl backend (gl_backend.h) — mvr's clip space is OpenGL's; the vertex
// shader maps it to Vulkan's (y down, depth z in [0, w]) so that the window depth is
// ndc.z / 2 + 1/2 (D32_SFLOAT, cleared to 1, test LESS) and row 0 is the top, with no flip.
//
// Device: the first one that has what the backend needs (Vulkan 1.2, multiview), a discrete
// GPU before an integrated one before a virtual one before a CPU (lavapipe); MVR_VK_DEVICE=N
// picks the N-th device of vkEnumeratePhysicalDevices instead. Created lazily on the first
// call that needs it (supports(), render(), info()), never in makeVkBackend().
//
// Validation: MVR_VK_VALIDATION=1 enables VK_LAYER_KHRONOS_validation with a debug messenger;
// any message it reports makes the render (or the call) that caused it fail with an Internal
// error quoting the message, and one reported while the backend is destroyed aborts. The tests
// set it (tests/vk); a missing layer is then an error, not a silent run without it.
//
// Methods:
//   multipass        one render pass per view into its own layer. The reference.
//   multiview        VK_KHR_multiview (Vulkan 1.1 core): one render pass with a view mask over
//                    a batch of at most maxMultiviewViewCount views (gl_ViewIndex; lavapipe:
//                    one, as it loses clipped triangles past a pass's first view).
//   instanced-layer  one render pass over a layered framebuffer; N instances, the vertex shader
//                    writes gl_Layer (Vulkan 1.2 shaderOutputLayer).
//   auto             measures the others for the request (views, size, shading) on its first
//                    frame, uses the fastest; cached.
// Views are drawn in batches (kalaiah2007 §3); each batch's colour (and depth) is copied into
// one staging buffer with one command, fenced, and copied out while the next batch is drawn.
// Base colour textures, vertex colours and shadow maps are drawn as the gl backend draws them
// (src/vk/README.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mvr/core/render.h"

namespace mvr::vk {

/// Creates the vk backend (name "vk"). Makes no Vulkan call: safe without a device.
std::unique_ptr<mvr::Backend> makeVkBackend();

/// Every method name of the vk backend ("multipass" first, "auto" last).
const std::vector<std::string>& vkMethodNames();

}  // namespace mvr::vk
