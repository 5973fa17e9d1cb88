// checkGltfValues() (model_guard.h): the numbers of a glTF 2.0 document that mvr draws with —
// node transforms, cameras, KHR_lights_punctual lights, materials and samplers — checked for
// type, length and range before assimp reads them. assimp takes ["abc",0,0] or [0,0] for a
// translation without a word (a zero, or the array cut short) and the scene is drawn otherwise
// than the file says; a number beyond a float's range becomes infinite.
#include "model_guard.h"

#include <cfloat>
#include <cstdint>
#include <cmath>
#include <initializer_list>
#include <numbers>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

namespace mvr::detail {
namespace {

using Json = nlohmann::json;

/// A value as the message quotes it: its JSON, cut at 60 characters.
std::string quote(const Json& v) {
    std::string text = v.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

/// The checks of one document; the first failure is kept (`failed`).
struct Checker {
    const std::string& what;
    Status status;

    bool failed() const { return !status.isOk(); }
    void fail(const std::string& where, const std::string& why) {
        if (!failed()) status = inputError(fmt::format("{}: {}: {}", what, where, why));
    }
    /// A JSON number that is a float (finite, at most FLT_MAX in magnitude).
    static bool isFloat(const Json& v) {
        if (!v.is_number()) return false;
        const double d = v.get<double>();
        return std::isfinite(d) && std::abs(d) <= double(FLT_MAX);
    }
    /// key of `object`, when present: an array of `n` floats, each in lo..hi.
    void floats(const Json& object, const char* key, const std::string& where, std::size_t n,
                double lo = -double(FLT_MAX), double hi = double(FLT_MAX)) {
        const auto it = object.find(key);
        if (it == object.end() || failed()) return;
        const std::string place = fmt::format("{}.{}", where, key);
        bool ok = it->is_array() && it->size() == n;
        for (std::size_t i = 0; ok && i < n; ++i) ok = isFloat((*it)[i]);
        if (!ok) return fail(place, fmt::format("expected {} numbers, got {}", n, quote(*it)));
        for (std::size_t i = 0; i < n; ++i) {
            const double d = (*it)[i].get<double>();
            if (d < lo || d > hi)
                return fail(place, fmt::format("element {} = {:g} is out of range (must be "
                                               "{:g}..{:g})",
                                               i, d, lo, hi));
        }
    }
    /// key of `object`, when present: one float in lo..hi (loOpen: lo excluded).
    void number(const Json& object, const char* key, const std::string& where,
                double lo = -double(FLT_MAX), double hi = double(FLT_MAX), bool loOpen = false) {
        const auto it = object.find(key);
        if (it == object.end() || failed()) return;
        const std::string place = fmt::format("{}.{}", where, key);
        if (!isFloat(*it)) return fail(place, fmt::format("expected a number, got {}", quote(*it)));
        const double d = it->get<double>();
        if (d < lo || d > hi || (loOpen && d == lo))
            fail(place, fmt::format("{:g} is out of range (must be {} {:g} and at most {:g})", d,
                                    loOpen ? ">" : ">=", lo, hi));
    }
    /// key of `object`, when present: a whole number >= 0 (an index), or one of `allowed`.
    void whole(const Json& object, const char* key, const std::string& where,
               std::initializer_list<int> allowed = {}) {
        const auto it = object.find(key);
        if (it == object.end() || failed()) return;
        const std::string place = fmt::format("{}.{}", where, key);
        if (!it->is_number_integer() || it->get<std::int64_t>() < 0 ||
            it->get<std::int64_t>() > INT32_MAX)
            return fail(place, fmt::format("expected a whole number >= 0, got {}", quote(*it)));
        if (allowed.size() == 0) return;
        for (int a : allowed)
            if (it->get<std::int64_t>() == a) return;
        std::string list;
        for (int a : allowed) list += (list.empty() ? "" : ", ") + std::to_string(a);
        fail(place, fmt::format("{} is not one of glTF's values ({})", quote(*it), list));
    }
    /// A textureInfo (index, texCoord, and scale / strength where given).
    void textureInfo(const Json& material, const char* key, const std::string& where) {
        const auto it = material.find(key);
        if (it == material.end() || failed()) return;
        const std::string place = fmt::format("{}.{}", where, key);
        if (!it->is_object()) return fail(place, fmt::format("expected an object, got {}", quote(*it)));
        whole(*it, "index", place);
        whole(*it, "texCoord", place);
        number(*it, "scale", place);
        number(*it, "strength", place, 0.0, 1.0);
    }
    /// A textureInfo's texture coordinate set (textureInfo's texCoord, and its
    /// KHR_texture_transform's, which overrides it) is one mvr reads, 0 or 1; the transform's
    /// offset and scale are 2 floats, its rotation one. assimp 5.2.5 reads offset[0], offset[1],
    /// scale[0] and scale[1] without checking that the arrays hold two numbers (when the file's
    /// extensionsUsed lists the extension). `place` names the material and the slot; call it
    /// after textureInfo(), which refuses a texCoord that is no whole number.
    void textureCoords(const Json& parent, const char* key, const std::string& place) {
        const auto it = parent.find(key);
        if (it == parent.end() || failed() || !it->is_object()) return;
        auto set = [&](const Json& o, const std::string& at) {
            const auto t = o.find("texCoord");
            if (t == o.end() || failed() || !t->is_number_integer()) return;
            if (t->get<std::int64_t>() > 1)
                fail(at + ".texCoord",
                     fmt::format("{} is not a texture coordinate set mvr reads (0 or 1)",
                                 quote(*t)));
        };
        set(*it, place);
        const auto ext = it->find("extensions");
        if (ext == it->end() || !ext->is_object() || failed()) return;
        const auto k = ext->find("KHR_texture_transform");
        if (k == ext->end()) return;
        const std::string at = place + ".extensions.KHR_texture_transform";
        if (!k->is_object()) return fail(at, fmt::format("expected an object, got {}", quote(*k)));
        for (const char* pair : {"offset", "scale"}) {
            const auto v = k->find(pair);
            if (v == k->end()) continue;
            if (!v->is_array() || v->size() != 2 || !isFloat((*v)[0]) || !isFloat((*v)[1]))
                return fail(fmt::format("{}.{}", at, pair),
                            fmt::format("expected 2 finite numbers, got {}", quote(*v)));
        }
        if (const auto r = k->find("rotation"); r != k->end() && !isFloat(*r))
            return fail(at + ".rotation",
                        fmt::format("expected a finite number (radians), got {}", quote(*r)));
        whole(*k, "texCoord", at);
        set(*k, at);
    }
};

/// doc[key] when it is an array, else an empty one (a wrong type is refused in `check`).
const Json& arrayAt(const Json& doc, const char* key, Checker& c, const std::string& where) {
    static const Json kEmpty = Json::array();
    const auto it = doc.find(key);
    if (it == doc.end()) return kEmpty;
    if (!it->is_array()) {
        c.fail(where.empty() ? key : where + "." + key,
               fmt::format("expected an array, got {}", quote(*it)));
        return kEmpty;
    }
    return *it;
}

}  // namespace

Status checkGltfValues(const nlohmann::json& doc, const std::string& what) {
    Checker c{what, {}};
    constexpr double kHalfPi = std::numbers::pi / 2.0;
    const Json& nodes = arrayAt(doc, "nodes", c, "");
    for (std::size_t i = 0; i < nodes.size() && !c.failed(); ++i) {
        const std::string where = fmt::format("nodes[{}]", i);
        if (!nodes[i].is_object()) {
            c.fail(where, fmt::format("expected an object, got {}", quote(nodes[i])));
            break;
        }
        c.floats(nodes[i], "translation", where, 3);
        c.floats(nodes[i], "rotation", where, 4);
        c.floats(nodes[i], "scale", where, 3);
        c.floats(nodes[i], "matrix", where, 16);
        c.whole(nodes[i], "mesh", where);
        c.whole(nodes[i], "camera", where);
        const Json& children = arrayAt(nodes[i], "children", c, where);
        for (std::size_t k = 0; k < children.size() && !c.failed(); ++k) {
            if (!children[k].is_number_integer() || children[k].get<std::int64_t>() < 0 ||
                children[k].get<std::int64_t>() >= std::int64_t(nodes.size()))
                c.fail(fmt::format("{}.children[{}]", where, k),
                       fmt::format("expected a node index 0..{}, got {}", nodes.size() - 1,
                                   quote(children[k])));
        }
    }
    const Json& cameras = arrayAt(doc, "cameras", c, "");
    for (std::size_t i = 0; i < cameras.size() && !c.failed(); ++i) {
        const std::string where = fmt::format("cameras[{}]", i);
        if (!cameras[i].is_object()) {
            c.fail(where, fmt::format("expected an object, got {}", quote(cameras[i])));
            break;
        }
        if (const auto p = cameras[i].find("perspective"); p != cameras[i].end()) {
            const std::string place = where + ".perspective";
            if (!p->is_object()) {
                c.fail(place, fmt::format("expected an object, got {}", quote(*p)));
                break;
            }
            c.number(*p, "yfov", place, 0.0, std::numbers::pi, true);
            c.number(*p, "znear", place, 0.0, double(FLT_MAX), true);
            c.number(*p, "zfar", place, 0.0, double(FLT_MAX), true);
            c.number(*p, "aspectRatio", place, 0.0, double(FLT_MAX), true);
        }
        if (const auto o = cameras[i].find("orthographic"); o != cameras[i].end()) {
            const std::string place = where + ".orthographic";
            if (!o->is_object()) {
                c.fail(place, fmt::format("expected an object, got {}", quote(*o)));
                break;
            }
            for (const char* key : {"xmag", "ymag", "znear", "zfar"}) c.number(*o, key, place);
        }
    }
    const auto ext = doc.find("extensions");
    if (ext != doc.end() && ext->is_object() && !c.failed()) {
        const auto khr = ext->find("KHR_lights_punctual");
        if (khr != ext->end() && khr->is_object()) {
            const std::string base = "extensions.KHR_lights_punctual";
            const Json& lights = arrayAt(*khr, "lights", c, base);
            for (std::size_t i = 0; i < lights.size() && !c.failed(); ++i) {
                const std::string where = fmt::format("{}.lights[{}]", base, i);
                if (!lights[i].is_object()) {
                    c.fail(where, fmt::format("expected an object, got {}", quote(lights[i])));
                    break;
                }
                c.floats(lights[i], "color", where, 3, 0.0, double(FLT_MAX));
                c.number(lights[i], "intensity", where, 0.0);
                c.number(lights[i], "range", where, 0.0, double(FLT_MAX), true);
                if (const auto spot = lights[i].find("spot"); spot != lights[i].end()) {
                    if (!spot->is_object()) {
                        c.fail(where + ".spot", fmt::format("expected an object, got {}", quote(*spot)));
                        break;
                    }
                    c.number(*spot, "innerConeAngle", where + ".spot", 0.0, kHalfPi);
                    c.number(*spot, "outerConeAngle", where + ".spot", 0.0, kHalfPi);
                }
            }
        }
    }
    const Json& materials = arrayAt(doc, "materials", c, "");
    for (std::size_t i = 0; i < materials.size() && !c.failed(); ++i) {
        const std::string where = fmt::format("materials[{}]", i);
        const Json& m = materials[i];
        if (!m.is_object()) {
            c.fail(where, fmt::format("expected an object, got {}", quote(m)));
            break;
        }
        // The texture coordinate checks name the material ("material 'Wood' (materials[2]):
        // pbrMetallicRoughness.baseColorTexture.texCoord: ...").
        const auto name = m.find("name");
        const std::string named =
            name != m.end() && name->is_string()
                ? fmt::format("material '{}' ({}): ", name->get<std::string>(), where)
                : where + ": ";
        if (const auto pbr = m.find("pbrMetallicRoughness"); pbr != m.end()) {
            const std::string place = where + ".pbrMetallicRoughness";
            if (!pbr->is_object()) {
                c.fail(place, fmt::format("expected an object, got {}", quote(*pbr)));
                break;
            }
            c.floats(*pbr, "baseColorFactor", place, 4, 0.0, double(FLT_MAX));
            c.number(*pbr, "metallicFactor", place, 0.0, 1.0);
            c.number(*pbr, "roughnessFactor", place, 0.0, 1.0);
            c.textureInfo(*pbr, "baseColorTexture", place);
            c.textureInfo(*pbr, "metallicRoughnessTexture", place);
            for (const char* slot : {"baseColorTexture", "metallicRoughnessTexture"})
                c.textureCoords(*pbr, slot, fmt::format("{}pbrMetallicRoughness.{}", named, slot));
        }
        c.floats(m, "emissiveFactor", where, 3, 0.0, double(FLT_MAX));
        c.number(m, "alphaCutoff", where, 0.0);
        for (const char* slot : {"normalTexture", "occlusionTexture", "emissiveTexture"}) {
            c.textureInfo(m, slot, where);
            c.textureCoords(m, slot, named + slot);
        }
        if (const auto mode = m.find("alphaMode"); mode != m.end() && !c.failed()) {
            if (!mode->is_string() || (*mode != "OPAQUE" && *mode != "MASK" && *mode != "BLEND"))
                c.fail(where + ".alphaMode",
                       fmt::format("expected OPAQUE, MASK or BLEND, got {}", quote(*mode)));
        }
        if (const auto e = m.find("extensions"); e != m.end() && e->is_object()) {
            if (const auto s = e->find("KHR_materials_emissive_strength");
                s != e->end() && s->is_object())
                c.number(*s, "emissiveStrength", where + ".extensions.KHR_materials_emissive_strength",
                         0.0);
        }
    }
    const Json& samplers = arrayAt(doc, "samplers", c, "");
    for (std::size_t i = 0; i < samplers.size() && !c.failed(); ++i) {
        const std::string where = fmt::format("samplers[{}]", i);
        if (!samplers[i].is_object()) {
            c.fail(where, fmt::format("expected an object, got {}", quote(samplers[i])));
            break;
        }
        c.whole(samplers[i], "magFilter", where, {9728, 9729});
        c.whole(samplers[i], "minFilter", where, {9728, 9729, 9984, 9985, 9986, 9987});
        c.whole(samplers[i], "wrapS", where, {33071, 33648, 10497});
        c.whole(samplers[i], "wrapT", where, {33071, 33648, 10497});
    }
    return c.status;
}

}  // namespace mvr::detail
