// mvr/core/input_file.h — the one check every reader of an input file makes before opening it.
//
// Only regular files are read: a FIFO blocks its reader until something writes to it, and a
// device such as /dev/zero or /dev/urandom never ends, so reading one (directly or through a
// symbolic link) would hang mvr. Header only (std::filesystem's stat, no file is opened), so
// that every library, mvr::core's included, can use it.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

#include "mvr/core/status.h"

namespace mvr {

/// What a path that is there but not a regular file is ("a directory", "a FIFO", "a device",
/// "a socket"), following symbolic links; empty for a regular file or nothing at all.
inline std::string nonRegularKind(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    switch (st.type()) {
        case fs::file_type::directory: return "a directory";
        case fs::file_type::fifo: return "a FIFO";
        case fs::file_type::character:
        case fs::file_type::block: return "a device";
        case fs::file_type::socket: return "a socket";
        case fs::file_type::unknown: return "of an unknown kind";
        default: return {};
    }
}

/// OK when `path` (after symbolic links) is a regular file. Errors: ErrorCode::Input,
/// "WHAT: file not found" when nothing is there (or a link leads nowhere), "WHAT: not a regular
/// file (a FIFO)" for a directory, FIFO, device or socket.
inline Status checkRegularFile(const std::filesystem::path& path, const std::string& what) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (fs::is_regular_file(st)) return Status::ok();
    if (!fs::exists(st)) return inputError(what + ": file not found");
    return inputError(what + ": not a regular file (" + nonRegularKind(path) + ")");
}

}  // namespace mvr
