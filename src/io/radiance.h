// Readers of high-dynamic-range images for environment maps (loadEnvironmentMap, scene_io.h):
// Radiance RGBE (.hdr) and OpenEXR (.exr). Internal to mvr::io.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "mvr/core/environment.h"
#include "mvr/core/status.h"

namespace mvr::detail {

/// True when the bytes begin as a Radiance file ("#?RADIANCE" or "#?RGBE").
bool isRadianceBytes(std::span<const std::uint8_t> head);
/// True when the bytes begin with OpenEXR's magic number.
bool isExrBytes(std::span<const std::uint8_t> head);

/// Decodes a Radiance RGBE file (FORMAT=32-bit_rle_rgbe, resolution "-Y H +X W", flat or
/// run-length-encoded scanlines): linear RGB, no texel in excess of the file's bytes read.
/// Errors (Input) name `what` and the place: the header, the size line, a scanline.
Result<RadianceMap> decodeRadiance(std::span<const std::uint8_t> bytes, const std::string& what);

/// Reads an OpenEXR file's R, G, B (half or float; a missing channel reads 0, a Y-only file is
/// grey) over its data window. Errors (Input) name `what` and OpenEXR's reason.
Result<RadianceMap> readExrRadiance(const std::filesystem::path& path, const std::string& what);

}  // namespace mvr::detail
