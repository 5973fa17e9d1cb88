// mvr/core/output_file.h — the one message of a file that could not be written, with the
// system's reason: "cannot write 'out/view-3.png': No space left on device" (ErrorCode::Output).
#pragma once

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string_view>

#include <fmt/core.h>

#include "mvr/core/status.h"

namespace mvr {

/// The error of a failed open, write or close of `path`: errno's text when the C library set it
/// (a full disk, a file over `ulimit -f`, no such folder), else `detail` (the codec's own).
/// Clear errno before the writing it describes.
inline Status writeError(const std::filesystem::path& path, std::string_view detail) {
    const int err = errno;
    return outputError(fmt::format("cannot write '{}': {}", path.string(),
                                   err != 0 ? std::string_view(std::strerror(err)) : detail));
}

}  // namespace mvr
