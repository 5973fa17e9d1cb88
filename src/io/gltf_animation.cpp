// gltf_animation.cpp — see gltf_animation.h.
#include "gltf_animation.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "model_guard.h"
#include "mvr/core/input_file.h"

namespace mvr::detail {
namespace {

using json = nlohmann::json;
constexpr std::uintmax_t kMaxFile = std::uintmax_t(1) << 30;

Result<std::vector<std::uint8_t>> readBytes(const std::filesystem::path& file,
                                            const std::string& what) {
    if (Status s = checkRegularFile(file, what); !s) return s;  // no FIFO, device, directory
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec) return inputError(fmt::format("{}: cannot be read", what));
    if (size > kMaxFile) return inputError(fmt::format("{}: is larger than 1 GiB", what));
    std::ifstream in(file, std::ios::binary);
    std::vector<std::uint8_t> bytes(size);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
    if (!in) return inputError(fmt::format("{}: cannot be read", what));
    return bytes;
}

std::optional<std::vector<std::uint8_t>> base64(const std::string& text) {
    std::vector<std::uint8_t> out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (char ch : text) {
        int v;
        if (ch >= 'A' && ch <= 'Z')
            v = ch - 'A';
        else if (ch >= 'a' && ch <= 'z')
            v = ch - 'a' + 26;
        else if (ch >= '0' && ch <= '9')
            v = ch - '0' + 52;
        else if (ch == '+' || ch == '-')
            v = 62;
        else if (ch == '/' || ch == '_')
            v = 63;
        else if (ch == '=')
            break;
        else
            return std::nullopt;
        acc = (acc << 6) | std::uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(std::uint8_t((acc >> bits) & 0xFF));
        }
    }
    return out;
}

std::uint32_t u32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

struct Reader {
    std::filesystem::path path;
    std::string what;
    json doc;
    std::vector<std::uint8_t> glbBin;
    bool hasGlbBin = false;
    std::vector<std::optional<std::vector<std::uint8_t>>> buffers;

    Result<const std::vector<std::uint8_t>*> buffer(std::size_t index) {
        const json& list = doc.at("buffers");
        if (index >= list.size()) return inputError(fmt::format("no buffer {}", index));
        if (buffers.size() != list.size()) buffers.resize(list.size());
        if (!buffers[index]) {
            const json& b = list.at(index);
            if (!b.contains("uri")) {
                if (index != 0 || !hasGlbBin) {
                    return inputError(fmt::format("buffer {} has no uri", index));
                }
                buffers[index] = glbBin;
            } else {
                const std::string uri = b.at("uri").get<std::string>();
                if (uri.rfind("data:", 0) == 0) {
                    const auto comma = uri.find(";base64,");
                    if (comma == std::string::npos) {
                        return inputError(
                            fmt::format("buffer {}: a data URI not in base64", index));
                    }
                    auto bytes = base64(uri.substr(comma + 8));
                    if (!bytes) return inputError(fmt::format("buffer {}: bad base64", index));
                    buffers[index] = std::move(*bytes);
                } else {
                    auto bytes = readBytes(path.parent_path() / uriDecode(uri),
                                           fmt::format("buffer {} ('{}')", index, uri));
                    if (!bytes) return bytes.status();
                    buffers[index] = std::move(bytes).value();
                }
            }
            if (b.contains("byteLength") &&
                b.at("byteLength").get<std::uint64_t>() > buffers[index]->size()) {
                return inputError(fmt::format("buffer {} is shorter than its byteLength", index));
            }
        }
        return &*buffers[index];
    }

    /// An accessor's values as floats (normalized integers mapped as glTF says), `comps` each.
    Result<std::vector<float>> accessor(std::size_t index, int comps) {
        const json& list = doc.at("accessors");
        if (index >= list.size()) return inputError(fmt::format("no accessor {}", index));
        const json& a = list.at(index);
        const std::string where = fmt::format("accessor {}", index);
        if (a.contains("sparse")) return unsupportedError(where + ": sparse accessors");
        const std::string type = a.at("type").get<std::string>();
        const int want = type == "SCALAR" ? 1
                         : type == "VEC2" ? 2
                         : type == "VEC3" ? 3
                         : type == "VEC4" ? 4
                                          : 0;
        if (want != comps) {
            return inputError(
                fmt::format("{}: type {} (expected {} components)", where, type, comps));
        }
        const int ct = a.at("componentType").get<int>();
        const bool normalized = a.value("normalized", false);
        int size = 0;
        switch (ct) {
            case 5126: size = 4; break;
            case 5120:
            case 5121: size = 1; break;
            case 5122:
            case 5123: size = 2; break;
            default: return inputError(fmt::format("{}: componentType {}", where, ct));
        }
        if (ct != 5126 && !normalized) {
            return inputError(fmt::format("{}: integer values that are not normalized", where));
        }
        const std::uint64_t count = a.at("count").get<std::uint64_t>();
        if (count == 0 || count > (1u << 24)) {
            return inputError(fmt::format("{}: count {} out of range", where, count));
        }
        std::vector<float> out(count * std::uint64_t(comps), 0.0f);
        if (!a.contains("bufferView")) return out;  // all zeros (glTF)
        const std::size_t viewIndex = a.at("bufferView").get<std::size_t>();
        const json& views = doc.at("bufferViews");
        if (viewIndex >= views.size()) return inputError(fmt::format("{}: no bufferView", where));
        const json& view = views.at(viewIndex);
        auto buf = buffer(view.at("buffer").get<std::size_t>());
        if (!buf) return Status(buf.status().code(), where + ": " + buf.status().message());
        const std::uint64_t viewOffset = view.value("byteOffset", std::uint64_t(0));
        const std::uint64_t viewLength = view.at("byteLength").get<std::uint64_t>();
        const std::uint64_t element = std::uint64_t(size) * std::uint64_t(comps);
        const std::uint64_t stride = view.value("byteStride", std::uint64_t(0));
        const std::uint64_t step = stride ? stride : element;
        const std::uint64_t offset = a.value("byteOffset", std::uint64_t(0));
        // glTF: byteStride 4..252; offsets within the 1 GiB a file may have (no overflow below).
        if (stride > 252 || viewOffset > kMaxFile || viewLength > kMaxFile || offset > kMaxFile ||
            viewOffset + viewLength > (*buf)->size() ||
            offset + (count - 1) * step + element > viewLength) {
            return inputError(fmt::format("{}: reads past its bufferView or buffer", where));
        }
        const std::uint8_t* base = (*buf)->data() + viewOffset + offset;
        for (std::uint64_t i = 0; i < count; ++i) {
            const std::uint8_t* e = base + i * step;
            for (int c = 0; c < comps; ++c) {
                const std::uint8_t* p = e + std::uint64_t(c) * std::uint64_t(size);
                float v = 0.0f;
                switch (ct) {
                    case 5126: std::memcpy(&v, p, 4); break;
                    case 5120: v = std::max(float(std::int8_t(*p)) / 127.0f, -1.0f); break;
                    case 5121: v = float(*p) / 255.0f; break;
                    case 5122: {
                        std::int16_t s;
                        std::memcpy(&s, p, 2);
                        v = std::max(float(s) / 32767.0f, -1.0f);
                        break;
                    }
                    default: {
                        std::uint16_t s;
                        std::memcpy(&s, p, 2);
                        v = float(s) / 65535.0f;
                    }
                }
                out[i * std::uint64_t(comps) + std::uint64_t(c)] = v;
            }
        }
        return out;
    }
};

std::optional<glm::vec3> vec3(const json& node, const char* key) {
    if (!node.contains(key)) return std::nullopt;
    const json& v = node.at(key);
    return glm::vec3(v.at(0).get<float>(), v.at(1).get<float>(), v.at(2).get<float>());
}

Result<std::optional<GltfAnimationFile>> read(Reader& r) {
    const json& doc = r.doc;
    if (!doc.contains("animations") || !doc.at("animations").is_array() ||
        doc.at("animations").empty() || !doc.contains("nodes")) {
        return std::optional<GltfAnimationFile>();
    }
    const json& nodes = doc.at("nodes");
    const std::size_t n = nodes.size();
    // The default scene's roots, then depth first (assimp's order).
    std::vector<std::size_t> roots;
    if (doc.contains("scenes") && !doc.at("scenes").empty()) {
        const std::size_t s = doc.value("scene", std::size_t(0));
        if (s >= doc.at("scenes").size()) return inputError(fmt::format("no scene {}", s));
        for (const json& i : doc.at("scenes").at(s).value("nodes", json::array()))
            roots.push_back(i.get<std::size_t>());
    }
    GltfAnimationFile out;
    SceneAnimation& anim = out.animation;
    std::vector<int> order(n, -1);  // glTF node -> index in anim.nodes
    std::function<Status(std::size_t, int, int)> visit = [&](std::size_t g, int parent,
                                                             int depth) -> Status {
        if (g >= n) return inputError(fmt::format("no node {}", g));
        if (order[g] >= 0) return inputError(fmt::format("node {} is reached twice (a cycle?)", g));
        if (depth > 256) return inputError(fmt::format("node {} is nested over 256 deep", g));
        const json& node = nodes.at(g);
        AnimatedNode a;
        a.name = node.value("name", std::string());
        a.parent = parent;
        NodeAnimation rest;
        if (node.contains("matrix")) {
            const json& m = node.at("matrix");
            float v[16];
            for (int i = 0; i < 16; ++i) v[i] = m.at(std::size_t(i)).get<float>();
            a.rest = glm::make_mat4(v);  // column-major, as glTF
        } else {
            if (auto t = vec3(node, "translation")) rest.restTranslation = *t;
            if (node.contains("rotation")) {
                const json& q = node.at("rotation");
                rest.restRotation = glm::quat(q.at(3).get<float>(), q.at(0).get<float>(),
                                              q.at(1).get<float>(), q.at(2).get<float>());
            }
            if (auto s = vec3(node, "scale")) rest.restScale = *s;
            a.rest = nodeMatrixAt(rest, 0.0);
        }
        const int self = int(anim.nodes.size());
        order[g] = self;
        anim.nodes.push_back(std::move(a));
        out.children.emplace_back();
        if (parent >= 0) out.children[std::size_t(parent)].push_back(self);
        // Kept for the channels: the rest T, R, S (identity for a matrix node).
        anim.nodes[std::size_t(self)].animation = rest;
        for (const json& c : node.value("children", json::array())) {
            if (Status s = visit(c.get<std::size_t>(), self, depth + 1); !s) return s;
        }
        return {};
    };
    for (std::size_t root : roots) {
        out.roots.push_back(int(anim.nodes.size()));
        if (Status s = visit(root, -1, 0); !s) return s;
    }
    std::vector<bool> animated(anim.nodes.size(), false);

    const json& a = doc.at("animations").at(0);
    anim.name = a.value("name", std::string("0"));
    const json& samplers = a.at("samplers");
    const json& channels = a.at("channels");
    for (std::size_t c = 0; c < channels.size(); ++c) {
        const json& ch = channels.at(c);
        const std::string where = fmt::format("channel {}", c);
        const json& target = ch.at("target");
        const std::string pathName = target.at("path").get<std::string>();
        if (!target.contains("node")) continue;  // glTF: ignore channels without a node
        const std::size_t g = target.at("node").get<std::size_t>();
        if (g >= n) return inputError(fmt::format("{}: no node {}", where, g));
        if (order[g] < 0) continue;  // a node outside the default scene
        const bool weights = pathName == "weights";
        if (pathName != "translation" && pathName != "rotation" && pathName != "scale" &&
            !weights) {
            out.warnings.push_back(fmt::format("animation '{}': {}: path '{}' is not played",
                                               anim.name, where, pathName));
            continue;
        }
        // Morph weights: one per target of the node's mesh (its first primitive's count; glTF
        // requires every primitive to have the same).
        int targets = 0;
        if (weights) {
            const std::size_t mi = nodes.at(g).value("mesh", std::size_t(-1));
            if (doc.contains("meshes") && mi < doc.at("meshes").size()) {
                const json& mesh = doc.at("meshes").at(mi);
                if (mesh.contains("primitives") && !mesh.at("primitives").empty()) {
                    const json& first = mesh.at("primitives").at(0);
                    if (first.contains("targets")) targets = int(first.at("targets").size());
                }
            }
            if (targets == 0) {
                out.warnings.push_back(fmt::format(
                    "animation '{}': {}: node {} animates morph weights but its mesh has no "
                    "morph targets: not played",
                    anim.name, where, g));
                continue;
            }
        } else if (nodes.at(g).contains("matrix")) {
            return inputError(
                fmt::format("{}: node {} has a matrix and cannot be animated", where, g));
        }
        const std::size_t si = ch.at("sampler").get<std::size_t>();
        if (si >= samplers.size()) return inputError(fmt::format("{}: no sampler {}", where, si));
        const json& js = samplers.at(si);
        Sampler s;
        const std::string interp = js.value("interpolation", std::string("LINEAR"));
        if (interp == "LINEAR")
            s.interpolation = Interpolation::Linear;
        else if (interp == "STEP")
            s.interpolation = Interpolation::Step;
        else if (interp == "CUBICSPLINE")
            s.interpolation = Interpolation::CubicSpline;
        else
            return inputError(fmt::format("{}: interpolation '{}'", where, interp));
        s.rotation = pathName == "rotation";
        s.components = weights ? targets : s.rotation ? 4 : 3;
        auto in = r.accessor(js.at("input").get<std::size_t>(), 1);
        // Weights are a SCALAR accessor of keys × targets values.
        auto values = in ? r.accessor(js.at("output").get<std::size_t>(),
                                      weights ? 1 : s.components)
                         : Result<std::vector<float>>(in.status());
        if (!values) {
            if (values.status().code() == ErrorCode::Unsupported) {
                out.warnings.push_back(fmt::format("animation '{}': {}: {}: not played", anim.name,
                                                   where, values.status().message()));
                continue;
            }
            return Status(values.status().code(), where + ": " + values.status().message());
        }
        s.input = std::move(in).value();
        s.output = std::move(values).value();
        if (Status st = validateSampler(s); !st) {
            return inputError(fmt::format("{}: {}", where, st.message()));
        }
        anim.duration = std::max(anim.duration, double(s.input.back()));
        NodeAnimation& na = *anim.nodes[std::size_t(order[g])].animation;
        (weights      ? na.weights
         : s.rotation ? na.rotation
         : pathName == "scale" ? na.scale
                               : na.translation) = std::move(s);
        animated[std::size_t(order[g])] = true;
    }
    for (std::size_t i = 0; i < anim.nodes.size(); ++i)
        if (!animated[i]) anim.nodes[i].animation.reset();
    if (std::find(animated.begin(), animated.end(), true) == animated.end()) {
        return std::optional<GltfAnimationFile>();
    }
    return std::optional<GltfAnimationFile>(std::move(out));
}

}  // namespace

Result<std::optional<GltfAnimationFile>> readGltfAnimation(const std::filesystem::path& path,
                                                           const std::string& what) {
    Reader r;
    r.path = path;
    r.what = what;
    auto bytes = readBytes(path, what);
    if (!bytes) return bytes.status();
    const std::vector<std::uint8_t>& b = *bytes;
    try {
        if (b.size() >= 12 && std::memcmp(b.data(), "glTF", 4) == 0) {
            // GLB: header, a JSON chunk, optionally a BIN chunk.
            if (b.size() < 20) return inputError(what + ": truncated GLB");
            const std::uint32_t jsonLength = u32(&b[12]);
            if (u32(&b[16]) != 0x4E4F534Au || std::uint64_t(jsonLength) + 20 > b.size()) {
                return inputError(what + ": GLB without a JSON chunk");
            }
            r.doc = json::parse(b.begin() + 20, b.begin() + 20 + jsonLength, nullptr, false);
            const std::uint64_t next = 20 + std::uint64_t(jsonLength);
            if (next + 8 <= b.size() && u32(&b[next + 4]) == 0x004E4942u) {
                const std::uint64_t binLength = u32(&b[next]);
                if (next + 8 + binLength > b.size()) return inputError(what + ": truncated GLB");
                r.glbBin.assign(b.begin() + long(next + 8), b.begin() + long(next + 8 + binLength));
                r.hasGlbBin = true;
            }
        } else {
            r.doc = json::parse(b.begin(), b.end(), nullptr, false);
        }
        if (r.doc.is_discarded() || !r.doc.is_object()) {
            return std::optional<GltfAnimationFile>();  // assimp read it; not JSON we know
        }
        auto out = read(r);
        if (!out) {
            return Status(out.status().code(),
                          fmt::format("{}: animation: {}", what, out.status().message()));
        }
        return out;
    } catch (const std::exception& e) {
        // nlohmann's type / range errors: a field of the wrong kind or an index out of range.
        return inputError(fmt::format("{}: animation: malformed glTF ({})", what, e.what()));
    }
}

}  // namespace mvr::detail
