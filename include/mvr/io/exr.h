// mvr/io/exr.h — depth as OpenEXR (library mvr::io, through Debian's OpenEXR 3): one FLOAT
// channel "Z" holding each pixel's linear eye-space distance in world units (the distance along
// the view direction, -z in the camera's frame, as cameras.json's matrices define it), +inf
// where nothing was drawn; ZIP-compressed scanlines. What compositing tools and RGB-D pipelines
// read as depth (`--depth-format exr`).
#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "mvr/core/status.h"

namespace mvr {

/// Writes `distance` (width × height values, row 0 at the top) to `path`.
/// Errors: ErrorCode::Usage for a size that does not match, ErrorCode::Output naming the path.
Status writeDepthExr(const std::filesystem::path& path, int width, int height,
                     std::span<const float> distance);

/// An EXR file's "Z" channel, read back (row 0 at the top).
struct ExrDepth {
    int width = 0;
    int height = 0;
    std::vector<float> distance;
};

/// Reads the "Z" channel of an OpenEXR file. Errors: ErrorCode::Input naming the path (missing,
/// not a regular file, not OpenEXR, no "Z" channel).
Result<ExrDepth> readDepthExr(const std::filesystem::path& path);

}  // namespace mvr
