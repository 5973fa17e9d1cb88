// tests/fuzz/fuzz_util.h — what the fuzz targets share: a scratch folder for the readers that
// take a path (mvr::loadMesh, mvr::readPng, composite::readViewFile), one per process, removed
// at exit. The readers pick the format by the file name's extension (assimp) or its signature,
// so a memfd (/proc/self/fd/N, no extension) would not reach them.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include "mvr/io/png.h"
#include "mvr/io/mesh_io.h"

namespace mvr::fuzz {

/// The scratch folder: $MVR_FUZZ_SCRATCH when set (scripts/fuzz.sh sets one fixed path per
/// target, so that a run's inputs, paths included, are the same on every machine), else a new
/// mvr-fuzz-XXXXXX in the temporary folder.
inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        if (const char* fixed = std::getenv("MVR_FUZZ_SCRATCH"); fixed && *fixed) {
            std::error_code ec;
            std::filesystem::create_directories(fixed, ec);
            if (ec) std::abort();
            return std::filesystem::path(fixed);
        }
        std::string tmpl = (std::filesystem::temp_directory_path() / "mvr-fuzz-XXXXXX").string();
        if (!::mkdtemp(tmpl.data())) std::abort();
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(scratchDir(), ec);
        });
        return std::filesystem::path(tmpl);
    }();
    return dir;
}

/// Writes `size` bytes to NAME in the scratch folder (replacing it) and returns its path.
inline std::filesystem::path writeScratch(const std::string& name, const std::uint8_t* data,
                                          std::size_t size) {
    const std::filesystem::path path = scratchDir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) std::abort();
    return path;
}

inline std::filesystem::path writeScratch(const std::string& name, const std::string& text) {
    return writeScratch(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

}  // namespace mvr::fuzz
