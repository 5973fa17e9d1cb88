// mvr/core/content_hash.h — a 64-bit hash of an image's size and pixels (FNV-style, 8 bytes a
// step, as contentHash(const Mesh&) in mesh.h; not cryptographic): the GPU backends' key for
// the textures they keep uploaded. Never 0 (a backend may use 0 for "no texture").
#pragma once

#include <cstdint>

#include "mvr/core/image.h"

namespace mvr {

std::uint64_t contentHash(const Image& image);

}  // namespace mvr
