#include "model_guard.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>

#include <fmt/core.h>

namespace mvr::detail {
namespace {

std::uint32_t le32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

}  // namespace

Status checkGlbHeader(const std::filesystem::path& path, const std::string& what) {
    std::error_code ec;
    const std::uintmax_t fileSize = std::filesystem::file_size(path, ec);
    if (ec) return Status();  // the loader reports an unreadable file itself
    std::ifstream in(path, std::ios::binary);
    std::array<unsigned char, 20> head{};
    in.read(reinterpret_cast<char*>(head.data()), head.size());
    const std::size_t got = static_cast<std::size_t>(in.gcount());
    if (got < 4 || std::memcmp(head.data(), "glTF", 4) != 0) return Status();
    const auto bad = [&](const std::string& why) {
        return inputError(fmt::format("{}: malformed GLB: {}", what, why));
    };
    if (got < 12) return bad("file ends inside the 12-byte header (truncated)");
    const std::uint32_t version = le32(&head[4]);
    const std::uint32_t length = le32(&head[8]);
    if (length > fileSize)
        return bad(
            fmt::format("header says {} bytes, the file has {} (truncated?)", length, fileSize));
    if (version == 1) {  // glTF 1.0 binary: {magic, version, length, contentLength, format}
        if (got < 20) return bad("file ends inside the glTF 1.0 header (truncated)");
        if (le32(&head[12]) > length - std::min<std::uint32_t>(length, 20))
            return bad(fmt::format("content of {} bytes does not fit in {} bytes", le32(&head[12]),
                                   length));
        return Status();
    }
    if (version != 2) return bad(fmt::format("version {} (expected 1 or 2)", version));
    // glTF 2.0: chunks {length, type, data} from byte 12 to `length`.
    std::uint64_t at = 12;
    for (int chunk = 0; at < length; ++chunk) {
        if (length - at < 8)
            return bad(
                fmt::format("chunk {} header runs past the {} bytes of the file", chunk, length));
        unsigned char ch[8];
        in.clear();
        in.seekg(static_cast<std::streamoff>(at));
        in.read(reinterpret_cast<char*>(ch), sizeof ch);
        if (in.gcount() != sizeof ch) return bad(fmt::format("chunk {} unreadable", chunk));
        const std::uint32_t chunkLength = le32(ch);
        if (chunkLength > length - at - 8)
            return bad(fmt::format("chunk {} claims {} bytes, {} are left in the file", chunk,
                                   chunkLength, length - at - 8));
        at += 8 + std::uint64_t(chunkLength);
    }
    return Status();
}

bool ModelIOSystem::hidden(const char* file) const {
    if (!file) return false;
    std::string ext = std::filesystem::path(file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".mtl" && std::filesystem::path(file) != mModel;
}

bool ModelIOSystem::Exists(const char* file) const {
    return !hidden(file) && Assimp::DefaultIOSystem::Exists(file);
}

Assimp::IOStream* ModelIOSystem::Open(const char* file, const char* mode) {
    return hidden(file) ? nullptr : Assimp::DefaultIOSystem::Open(file, mode);
}

}  // namespace mvr::detail
