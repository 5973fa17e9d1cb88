#include "model_guard.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
#include <string_view>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "mvr/core/input_file.h"

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

namespace {

/// Bytes of one element of an accessor (its type's components × its component type's size);
/// 0 for what glTF does not define (assimp refuses those itself).
std::uint64_t elementBytes(const nlohmann::json& accessor) {
    static const std::pair<const char*, int> kComponents[] = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
    const auto type = accessor.find("type");
    const auto component = accessor.find("componentType");
    if (type == accessor.end() || !type->is_string() || component == accessor.end() ||
        !component->is_number_integer()) {
        return 0;
    }
    int components = 0;
    for (const auto& [name, n] : kComponents) components = *type == name ? n : components;
    const std::int64_t c = component->get<std::int64_t>();
    const int size = c == 5120 || c == 5121 ? 1 : c == 5122 || c == 5123 ? 2 : c == 5125 || c == 5126 ? 4 : 0;
    return std::uint64_t(components) * std::uint64_t(size);
}

/// The most bytes of zeros one accessor without a bufferView may stand for: 256 MiB is 22
/// million VEC3 floats, more than any mesh mvr draws at interactive rates.
constexpr std::uint64_t kMaxZeroFilledBytes = std::uint64_t(256) << 20;

std::uint64_t number(const nlohmann::json& object, const char* key, std::uint64_t fallback = 0) {
    const auto it = object.find(key);
    return it != object.end() && it->is_number_unsigned() ? it->get<std::uint64_t>()
           : it != object.end() && it->is_number_integer() && it->get<std::int64_t>() >= 0
               ? std::uint64_t(it->get<std::int64_t>())
               : fallback;
}

/// Bytes a data URI's base64 payload decodes to (padding excluded); nullopt when not base64.
std::optional<std::uint64_t> dataUriBytes(const std::string& uri) {
    const auto comma = uri.find(',');
    if (uri.rfind("data:", 0) != 0 || comma == std::string::npos ||
        uri.substr(0, comma).find(";base64") == std::string::npos) {
        return std::nullopt;
    }
    std::uint64_t chars = 0;
    for (std::size_t i = comma + 1; i < uri.size(); ++i) chars += uri[i] != '=';
    return chars * 3 / 4;
}

}  // namespace

std::string uriDecode(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '%' && i + 2 < s.size() && std::isxdigit((unsigned char)s[i + 1]) &&
            std::isxdigit((unsigned char)s[i + 2])) {
            out.push_back(char(std::stoi(s.substr(i + 1, 2), nullptr, 16)));
            i += 2;
        } else {
            out.push_back(s[i]);
        }
    }
    return out;
}

Status checkGltfBounds(const std::filesystem::path& path, const std::string& what) {
    std::error_code ec;
    const std::uintmax_t fileSize = std::filesystem::file_size(path, ec);
    if (ec || fileSize > (std::uintmax_t(1) << 31)) return Status();
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string_view json = bytes;
    std::optional<std::uint64_t> binChunk;  // a GLB's BIN chunk length
    const bool glb = bytes.size() >= 20 && bytes.compare(0, 4, "glTF") == 0;
    if (glb) {
        const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
        if (le32(b + 4) == 1)
            return inputError(fmt::format(
                "{}: binary glTF 1.0 is not supported (mvr reads glTF 2.0)", what));
        if (le32(b + 4) != 2 || le32(b + 16) != 0x4E4F534Au) return Status();  // checkGlbHeader's
        const std::uint64_t jsonLength = std::min<std::uint64_t>(le32(b + 12), bytes.size() - 20);
        json = json.substr(20, jsonLength);
        const std::uint64_t next = 20 + jsonLength;
        if (next + 8 <= bytes.size() && le32(b + next + 4) == 0x004E4942u)
            binChunk = std::min<std::uint64_t>(le32(b + next), bytes.size() - next - 8);
    }
    const auto bad = [&](const std::string& why) {
        return inputError(fmt::format("{}: malformed glTF: {}", what, why));
    };
    // assimp reads the JSON up to its first NUL byte (rapidjson, in place); so does this check,
    // so that both see one document. What assimp reads, this must read the same way: JSON that
    // is not UTF-8 or not well formed, and an object naming a key twice (rapidjson takes the
    // first, nlohmann the last), are refused rather than left to assimp unchecked.
    json = json.substr(0, json.find('\0'));
    std::vector<std::vector<std::string>> keys;  // the keys of each open object
    std::string duplicate;
    const auto noteKey = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start) keys.emplace_back();
        if (event == Event::object_end && !keys.empty()) keys.pop_back();
        if (event == Event::key && !keys.empty()) {
            const std::string& key = parsed.get_ref<const std::string&>();
            if (duplicate.empty() &&
                std::find(keys.back().begin(), keys.back().end(), key) != keys.back().end()) {
                duplicate = key;
            }
            keys.back().push_back(key);
        }
        return true;
    };
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(json, noteKey);
    } catch (const nlohmann::json::exception& e) {
        std::string why = e.what();  // "[json.exception.parse_error.101] parse error at ..."
        if (const auto close = why.find("] "); why.rfind("[json.", 0) == 0 && close != why.npos)
            why.erase(0, close + 2);
        // nlohmann quotes the bytes it last read: raw, perhaps not UTF-8, not for a terminal.
        if (const auto last = why.find("; last read:"); last != why.npos) why.erase(last);
        return bad(fmt::format("its JSON{}: {}", glb ? " chunk" : "", why));
    }
    if (!duplicate.empty())
        return bad(fmt::format("an object names the key \"{}\" twice", duplicate));
    if (!doc.is_object()) return bad("its JSON is not an object");
    // glTF 1.0 (Khronos retired it in 2017) goes to a different, older reader in assimp, which
    // checks far less; mvr reads glTF 2.0 only.
    const auto asset = doc.find("asset");
    const nlohmann::json* version = nullptr;
    if (asset != doc.end() && asset->is_object()) {
        if (const auto v = asset->find("version"); v != asset->end() && v->is_string()) version = &*v;
    }
    if (!version) return bad("no asset.version (glTF 2.0 requires one)");
    if (const std::string& v = version->get_ref<const std::string&>(); v.rfind("2.", 0) != 0)
        return bad(fmt::format("glTF {} is not supported (mvr reads glTF 2.0)", v));
    if (Status s = checkGltfValues(doc, what); !s) return s;
    auto arrayOf = [&](const char* key) {
        const auto it = doc.find(key);
        return it != doc.end() && it->is_array() ? *it : nlohmann::json::array();
    };
    const nlohmann::json buffers = arrayOf("buffers"), views = arrayOf("bufferViews"),
                         accessors = arrayOf("accessors");
    // assimp's data URI parser keeps the offsets of the URI's parts in signed chars: a header
    // (up to the comma) past 126 bytes sends them negative, and the data is read from before
    // the string. And it takes an embedded image's file extension from after the '/' of its
    // MIME type without checking that there is one (a NULL + 1 pointer: SIGSEGV).
    auto dataUriHeaderBad = [](const std::string& uri) -> std::optional<std::string> {
        if (uri.rfind("data:", 0) != 0) return std::nullopt;
        const std::size_t comma = std::min(uri.find(','), uri.size());
        if (comma > 100) return fmt::format("a data URI header of {} bytes (at most 100)", comma);
        const std::string type = uri.substr(5, std::min(uri.find(';'), comma) - 5);
        if (!type.empty() && type.find('/') == std::string::npos)
            return fmt::format("a data URI of media type \"{}\" (not type/subtype)", type);
        return std::nullopt;
    };
    const nlohmann::json images = arrayOf("images");
    for (std::size_t i = 0; i < images.size(); ++i) {
        const nlohmann::json& image = images[i];
        if (!image.is_object()) return bad(fmt::format("image {} is not an object", i));
        const auto uri = image.find("uri");
        if (uri != image.end() && uri->is_string()) {
            if (auto why = dataUriHeaderBad(uri->get<std::string>()))
                return bad(fmt::format("image {} has {}", i, *why));
        } else if (const auto mime = image.find("mimeType");
                   mime != image.end() && mime->is_string() &&
                   mime->get_ref<const std::string&>().find('/') == std::string::npos) {
            return bad(fmt::format("image {}'s mimeType \"{}\" is not type/subtype", i,
                                   mime->get<std::string>()));
        }
    }
    std::vector<std::uint64_t> bufferBytes;
    for (std::size_t i = 0; i < buffers.size(); ++i) {
        const nlohmann::json& buf = buffers[i];
        if (!buf.is_object()) return bad(fmt::format("buffer {} is not an object", i));
        const std::uint64_t length = number(buf, "byteLength");
        std::optional<std::uint64_t> have;
        const auto uri = buf.find("uri");
        if (uri == buf.end()) {
            have = i == 0 ? binChunk : std::nullopt;
        } else if (uri->is_string()) {
            const std::string u = uri->get<std::string>();
            if (auto why = dataUriHeaderBad(u)) return bad(fmt::format("buffer {} has {}", i, *why));
            have = dataUriBytes(u);
            if (!have && u.rfind("data:", 0) != 0) {
                // An external .bin: a regular file only (assimp would block on a FIFO and
                // read a device such as /dev/zero forever). A missing one is assimp's to report.
                const std::filesystem::path file = path.parent_path() / uriDecode(u);
                if (std::filesystem::exists(file, ec)) {
                    if (Status s = checkRegularFile(
                            file, fmt::format("{}: buffer {} ({})", what, i, file.string()));
                        !s) {
                        return s;
                    }
                }
                const std::uintmax_t n = std::filesystem::file_size(file, ec);
                if (!ec) have = n;
            }
        }
        if (have && *have < length) {
            return bad(fmt::format("buffer {} claims {} bytes, its data holds {}", i, length, *have));
        }
        bufferBytes.push_back(length);
    }
    std::vector<std::uint64_t> viewBytes;
    for (std::size_t i = 0; i < views.size(); ++i) {
        const nlohmann::json& v = views[i];
        if (!v.is_object()) return bad(fmt::format("bufferView {} is not an object", i));
        const std::uint64_t buffer = number(v, "buffer", ~std::uint64_t(0));
        const std::uint64_t offset = number(v, "byteOffset"), length = number(v, "byteLength");
        if (buffer >= bufferBytes.size())
            return bad(fmt::format("bufferView {} names buffer {} of {}", i, buffer, bufferBytes.size()));
        if (offset > bufferBytes[buffer] || length > bufferBytes[buffer] - offset) {
            return bad(fmt::format("bufferView {} (byteOffset {}, byteLength {}) runs past "
                                   "buffer {}'s {} bytes",
                                   i, offset, length, buffer, bufferBytes[buffer]));
        }
        viewBytes.push_back(length);
    }
    // An array of `count` elements of `element` bytes, `stride` apart, from `offset` of a view.
    auto fits = [&](std::uint64_t view, std::uint64_t offset, std::uint64_t count,
                    std::uint64_t element, std::uint64_t stride) {
        if (view >= viewBytes.size()) return false;
        if (count == 0) return offset <= viewBytes[view];
        if (count > (std::uint64_t(1) << 32) || stride > (std::uint64_t(1) << 16)) return false;
        const std::uint64_t end = offset + (count - 1) * stride + element;
        return end <= viewBytes[view];
    };
    for (std::size_t i = 0; i < accessors.size(); ++i) {
        const nlohmann::json& a = accessors[i];
        if (!a.is_object()) return bad(fmt::format("accessor {} is not an object", i));
        const std::uint64_t element = elementBytes(a), count = number(a, "count");
        if (element == 0) continue;
        if (!a.contains("bufferView") && count > kMaxZeroFilledBytes / element) {
            // glTF's zero-filled accessor (usually sparse): assimp allocates all of it.
            return bad(fmt::format("accessor {} has no bufferView and {} elements of {} bytes: "
                                   "over {} MiB of zeros",
                                   i, count, element, kMaxZeroFilledBytes >> 20));
        }
        if (a.contains("bufferView")) {
            const std::uint64_t view = number(a, "bufferView", ~std::uint64_t(0));
            const std::uint64_t stride =
                view < views.size() ? number(views[view], "byteStride", element) : element;
            const std::uint64_t offset = number(a, "byteOffset");
            if (!fits(view, offset, count, element, std::max(stride, element))) {
                return bad(fmt::format(
                    "accessor {} ({} elements of {} bytes from byte {} of bufferView {}) runs "
                    "past its bufferView",
                    i, count, element, offset, view));
            }
        }
        const auto sparse = a.find("sparse");
        if (sparse != a.end() && sparse->is_object()) {
            const std::uint64_t n = number(*sparse, "count");
            for (const char* part : {"indices", "values"}) {
                const auto p = sparse->find(part);
                if (p == sparse->end() || !p->is_object()) continue;
                const std::uint64_t size =
                    std::string(part) == "values" ? element : elementBytes({{"type", "SCALAR"},
                                                                            {"componentType", number(*p, "componentType")}});
                if (size == 0) continue;
                if (!fits(number(*p, "bufferView", ~std::uint64_t(0)), number(*p, "byteOffset"), n,
                          size, size)) {
                    return bad(fmt::format("accessor {}'s sparse {} run past their bufferView", i,
                                           part));
                }
            }
        }
    }
    // assimp 5.2.5 builds a primitive's faces without checking the ends: an indexed LINE_LOOP
    // whose first segment it drops closes the loop through that segment's indices (a NULL
    // read); a strip or fan of fewer vertices than one face allocates 2^32 faces (count - 2 in
    // 32 bits). A primitive without POSITION has no vertices, so it is one of those or fails.
    const nlohmann::json meshes = arrayOf("meshes");
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const auto prims = meshes[m].is_object() ? meshes[m].find("primitives") : meshes[m].end();
        if (prims == meshes[m].end() || !prims->is_array()) continue;
        for (std::size_t p = 0; p < prims->size(); ++p) {
            const nlohmann::json& prim = (*prims)[p];
            if (!prim.is_object()) continue;
            const std::string where = fmt::format("mesh {} primitive {}", m, p);
            const auto attributes = prim.find("attributes");
            const std::uint64_t position =
                attributes != prim.end() && attributes->is_object()
                    ? number(*attributes, "POSITION", ~std::uint64_t(0))
                    : ~std::uint64_t(0);
            if (position >= accessors.size())
                return bad(where + " has no POSITION accessor (glTF draws no such primitive)");
            const std::uint64_t mode = number(prim, "mode", 4);
            if (mode == 2 && prim.contains("indices"))
                return bad(where + " is an indexed LINE_LOOP (mode 2), which assimp 5.2.5 can "
                                   "crash on; mvr draws triangles only");
            const std::uint64_t vertices = number(accessors[position], "count");
            const std::uint64_t least = mode == 3 ? 2 : mode == 5 || mode == 6 ? 3 : 0;
            if (!prim.contains("indices") && vertices < least)
                return bad(fmt::format("{} is a {} of {} vertices (one {} needs {})", where,
                                       mode == 3 ? "LINE_STRIP" : mode == 5 ? "TRIANGLE_STRIP"
                                                                            : "TRIANGLE_FAN",
                                       vertices, mode == 3 ? "line" : "triangle", least));
        }
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
    // Whatever else assimp opens (a buffer, an image, an included file): a regular file only,
    // never a FIFO (it blocks) or a device (/dev/zero never ends). checkGltfBounds() names a
    // glTF's buffers first; here assimp sees a file it cannot open.
    if (hidden(file) || (file && !checkRegularFile(file, file))) return nullptr;
    return Assimp::DefaultIOSystem::Open(file, mode);
}

}  // namespace mvr::detail
