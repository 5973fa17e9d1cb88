// scene_io.cpp — model files as scenes (see scene_io.h).
//
// assimp (Debian libassimp 5.2.5, already mvr's model loader) reads the files: it exposes the
// node hierarchy, one aiMesh per glTF primitive, the glTF material keys (base color, alpha
// mode and cutoff, double-sided, texture samplers), embedded images (GLB, data URIs),
// cameras and KHR_lights_punctual lights, so no second glTF parser is needed for the scene
// (cgltf is not packaged in Debian 12). What assimp 5.2.5 drops is read from the glTF JSON
// itself: a light's range (khrLights below), the animations' interpolation
// (gltf_animation.cpp) and the texture slots' coordinate sets and KHR_texture_transform
// (materialTextureCoords below). The file first goes through loadMesh()'s checks (preflightModel,
// model_guard.h), which keep assimp's known faults from being reached and whose messages name
// the problem, and is then imported once (plain files through loadMesh() itself); OBJ
// materials come from mvr's own MTL reader (mtl.h), never assimp's.
#include "mvr/io/scene_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <span>

#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "gltf_animation.h"
#include "radiance.h"
#include "model_guard.h"
#include "mvr/core/input_file.h"
#include "mvr/core/lighting.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/core/texture_sampling.h"
#include "mvr/io/jpeg.h"
#include "mvr/io/mesh_io.h"
#include "mvr/io/mtl.h"
#include "mvr/io/png.h"

namespace mvr {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

glm::mat4 toGlm(const aiMatrix4x4& m) {
    // assimp is row-major (a1..a4 is the first row); glm is column-major.
    return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4,
                     m.b4, m.c4, m.d4);
}

void collectWorld(const aiNode& node, const glm::mat4& parent,
                  std::map<std::string, glm::mat4>& byName,
                  std::vector<std::pair<const aiNode*, glm::mat4>>& order) {
    const glm::mat4 world = parent * toGlm(node.mTransformation);
    byName.emplace(node.mName.C_Str(), world);
    order.emplace_back(&node, world);
    for (unsigned c = 0; c < node.mNumChildren; ++c)
        collectWorld(*node.mChildren[c], world, byName, order);
}

bool isJpegBytes(std::span<const std::uint8_t> d) {
    return d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF;
}

Result<Image> decodeImageBytes(std::span<const std::uint8_t> data, const std::string& what) {
    if (isJpegBytes(data)) return decodeJpeg(data, what);
    return decodePng(data, what);
}

/// A regular file's bytes (no FIFO, device or directory), at most `limitMiB` MiB. Errors
/// (Input) name `what`: "cannot be read", "is larger than N MiB", checkRegularFile's.
Result<std::vector<std::uint8_t>> readFileBytes(const std::filesystem::path& path,
                                                const std::string& what, int limitMiB) {
    if (Status s = checkRegularFile(path, what); !s) return s;
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return inputError(fmt::format("{}: cannot be read", what));
    if (size > (std::uintmax_t(limitMiB) << 20))
        return inputError(fmt::format("{}: is larger than {} MiB", what, limitMiB));
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> bytes(size);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size));
    if (!in) return inputError(fmt::format("{}: cannot be read", what));
    return bytes;
}

Result<Image> readImageFile(const std::filesystem::path& path, const std::string& what) {
    auto bytes = readFileBytes(path, what, 256);
    if (!bytes) return bytes.status();
    return decodeImageBytes(*bytes, what);
}

TextureWrap wrapFrom(int mode) {
    switch (mode) {
        case aiTextureMapMode_Clamp: return TextureWrap::ClampToEdge;
        case aiTextureMapMode_Mirror: return TextureWrap::MirroredRepeat;
        default: return TextureWrap::Repeat;
    }
}

/// The JSON of a .gltf, or the JSON chunk of a .glb; null when it cannot be had (assimp has
/// read the file already, so this only adds what assimp drops: see khrLights()).
nlohmann::json gltfDocument(const std::filesystem::path& path, bool glb) {
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec || size > (std::uintmax_t(1) << 30)) return nullptr;
    std::ifstream in(path, std::ios::binary);
    std::string bytes;
    if (!glb) {
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } else {
        // Header (magic, version, length), then the first chunk: length, type "JSON", data.
        char head[20] = {};
        if (!in.read(head, sizeof head) || std::string_view(head + 16, 4) != "JSON") return nullptr;
        std::uint32_t length = 0;
        std::memcpy(&length, head + 12, 4);  // little endian, as every platform mvr builds on
        if (length > size - 20) return nullptr;
        bytes.resize(length);
        if (!in.read(bytes.data(), std::streamsize(length))) return nullptr;
    }
    nlohmann::json doc = nlohmann::json::parse(bytes, nullptr, /*allow_exceptions=*/false);
    return doc.is_object() ? doc : nlohmann::json(nullptr);
}

/// One KHR_lights_punctual light as the file states it (the extension's defaults otherwise).
struct KhrLight {
    glm::vec3 color{1.0f};
    float intensity = 1.0f;
    float range = 0.0f;  ///< 0 = not given (infinite)
    float innerConeAngle = 0.0f;
    float outerConeAngle = std::numbers::pi_v<float> / 4.0f;
};

/// The file's lights array, index for index as assimp's aiLights (glTF2Importer creates
/// mLights[i] from lights[i] and names it after the node that uses it). assimp 5.2.5 drops
/// `range` (and folds intensity into the color), so range and the cone angles come from here.
/// Empty when the file has no such array or one of its entries is malformed.
std::vector<KhrLight> khrLights(const nlohmann::json& doc) {
    std::vector<KhrLight> out;
    if (!doc.is_object()) return out;
    auto ext = doc.find("extensions");
    if (ext == doc.end() || !ext->is_object()) return out;
    auto khr = ext->find("KHR_lights_punctual");
    if (khr == ext->end() || !khr->is_object()) return out;
    auto lights = khr->find("lights");
    if (lights == khr->end() || !lights->is_array()) return out;
    auto number = [](const nlohmann::json& o, const char* key, float& value) {
        auto it = o.find(key);
        if (it == o.end()) return true;
        if (!it->is_number()) return false;
        value = it->get<float>();
        return std::isfinite(value);
    };
    for (const nlohmann::json& l : *lights) {
        if (!l.is_object()) return {};
        KhrLight k;
        if (!number(l, "intensity", k.intensity) || !number(l, "range", k.range)) return {};
        if (auto c = l.find("color"); c != l.end()) {
            if (!c->is_array() || c->size() != 3) return {};
            for (int i = 0; i < 3; ++i) {
                if (!(*c)[i].is_number()) return {};
                k.color[i] = (*c)[i].get<float>();
            }
        }
        if (auto spot = l.find("spot"); spot != l.end() && spot->is_object()) {
            if (!number(*spot, "innerConeAngle", k.innerConeAngle) ||
                !number(*spot, "outerConeAngle", k.outerConeAngle))
                return {};
        }
        out.push_back(k);
    }
    return out;
}

/// One glTF material's texture slots as its JSON states them: the texture coordinate set each
/// reads and its KHR_texture_transform. assimp 5.2.5 does not apply the extension: it records
/// it as AI_MATKEY_UVTRANSFORM (rotation negated and the offset moved for its own v-up space,
/// about the image's centre) for aiProcess_TransformUVCoords to bake, a step mvr does not run
/// (it transforms assimp's v-up coordinates before FlipUVs, one transform per UV channel
/// whatever the slot), only when extensionsUsed lists the extension, and it ignores the
/// extension's texCoord override (AI_MATKEY_UVWSRC is the textureInfo's texCoord). So the sets
/// and transforms come from here and are applied in glTF's own uv space (convertMesh).
struct GltfMaterialUv {
    bool baseColorTexture = false;  ///< pbrMetallicRoughness.baseColorTexture is given
    int baseColorTexCoord = 0;      ///< its set, the transform's texCoord having won
    std::optional<TextureTransform> baseColor, metallicRoughness, normal, occlusion, emissive;
    // The metallic-roughness model's factors (issue 39 item 1), read here beside the slots
    // (assimp 5.2.5 does not import KHR_materials_emissive_strength).
    float metallic = 1.0f, roughness = 1.0f;
    glm::vec3 emissiveColor{0.0f};  ///< emissiveFactor × emissive_strength
    bool unlit = false;
    // The other slots (issue 39): given or not, and their sets. Exporters write neutral factors
    // beside a texture (Blender: emissiveFactor [1, 1, 1] under an emission texture; metallic
    // and roughness 1 under a packed metallic-roughness map), which alone would be a white glow
    // or a rough metal: material() drops those factors when the texture is not drawn.
    bool metallicRoughnessTexture = false, emissiveTexture = false, occlusionTexture = false;
    bool normalTexture = false;
    int metallicRoughnessTexCoord = 0, occlusionTexCoord = 0, emissiveTexCoord = 0;
    int normalTexCoord = 0;
    float normalScale = 1.0f;  ///< normalTexture.scale
    bool specularGlossiness = false;  ///< KHR_materials_pbrSpecularGlossiness without MR

    /// The texture coordinates a mesh of this material holds (Mesh::texcoords, one array for
    /// every slot): the set and transform of its first slot given, in the order base colour,
    /// metallic-roughness, occlusion, emissive, normal; set 0 untransformed when it has none.
    struct Coords {
        int set = 0;
        std::optional<TextureTransform> transform;
    };
    Coords coords() const {
        if (baseColorTexture) return {baseColorTexCoord, baseColor};
        if (metallicRoughnessTexture) return {metallicRoughnessTexCoord, metallicRoughness};
        if (occlusionTexture) return {occlusionTexCoord, occlusion};
        if (emissiveTexture) return {emissiveTexCoord, emissive};
        if (normalTexture) return {normalTexCoord, normal};
        return {};
    }
    /// Whether a slot reading set `set` through `transform` reads coords() (an absent transform
    /// is the identity). `setsAlike`: the material's meshes hold the same values in sets 0 and
    /// 1 (exporters that put the occlusion map on TEXCOORD_1, three.js's among them, often
    /// name one accessor twice), so either set reads the same coordinates.
    bool readsCoords(int set, const std::optional<TextureTransform>& transform,
                     bool setsAlike) const {
        const Coords c = coords();
        const TextureTransform a = transform.value_or(TextureTransform{});
        const TextureTransform b = c.transform.value_or(TextureTransform{});
        return (set == c.set || setsAlike) && a.offset == b.offset && a.rotation == b.rotation &&
               a.scale == b.scale;
    }
};

/// The file's materials[i] as GltfMaterialUv, index for index as assimp's mMaterials[i]
/// (glTF2Importer::ImportMaterials imports materials[i] as mMaterials[i] and appends its default
/// material). checkGltfValues() has checked the values (floats; sets 0 or 1): what has another
/// type here is skipped. Empty when the document has no materials array.
std::vector<GltfMaterialUv> materialTextureCoords(const nlohmann::json& doc) {
    std::vector<GltfMaterialUv> out;
    if (!doc.is_object()) return out;
    const auto materials = doc.find("materials");
    if (materials == doc.end() || !materials->is_array()) return out;
    auto slot = [](const nlohmann::json& parent, const char* key, bool* present, int& texCoord,
                   std::optional<TextureTransform>& transform) {
        const auto info = parent.find(key);
        if (info == parent.end() || !info->is_object()) return;
        if (present) *present = true;
        if (auto t = info->find("texCoord"); t != info->end() && t->is_number_integer())
            texCoord = t->get<int>();
        const auto ext = info->find("extensions");
        if (ext == info->end() || !ext->is_object()) return;
        const auto k = ext->find("KHR_texture_transform");
        if (k == ext->end() || !k->is_object()) return;
        TextureTransform x;
        auto pair = [&](const char* name, glm::vec2& v) {
            const auto a = k->find(name);
            if (a != k->end() && a->is_array() && a->size() == 2 && (*a)[0].is_number() &&
                (*a)[1].is_number())
                v = {(*a)[0].get<float>(), (*a)[1].get<float>()};
        };
        pair("offset", x.offset);
        pair("scale", x.scale);
        if (auto r = k->find("rotation"); r != k->end() && r->is_number())
            x.rotation = r->get<float>();
        if (auto t = k->find("texCoord"); t != k->end() && t->is_number_integer()) {
            x.texCoord = t->get<int>();
            texCoord = *x.texCoord;
        }
        transform = x;
    };
    for (const nlohmann::json& m : *materials) {
        GltfMaterialUv uv;
        if (m.is_object()) {
            if (const auto pbr = m.find("pbrMetallicRoughness");
                pbr != m.end() && pbr->is_object()) {
                slot(*pbr, "baseColorTexture", &uv.baseColorTexture, uv.baseColorTexCoord,
                     uv.baseColor);
                slot(*pbr, "metallicRoughnessTexture", &uv.metallicRoughnessTexture,
                     uv.metallicRoughnessTexCoord, uv.metallicRoughness);
                if (auto f = pbr->find("metallicFactor"); f != pbr->end() && f->is_number())
                    uv.metallic = std::clamp(f->get<float>(), 0.0f, 1.0f);
                if (auto f = pbr->find("roughnessFactor"); f != pbr->end() && f->is_number())
                    uv.roughness = std::clamp(f->get<float>(), 0.0f, 1.0f);
            }
            if (auto e = m.find("emissiveFactor");
                e != m.end() && e->is_array() && e->size() == 3 &&
                std::all_of(e->begin(), e->end(), [](const auto& x) { return x.is_number(); }))
                uv.emissiveColor = glm::clamp(glm::vec3((*e)[0].get<float>(),
                                                        (*e)[1].get<float>(), (*e)[2].get<float>()),
                                              0.0f, 1e6f);
            if (const auto ext = m.find("extensions"); ext != m.end() && ext->is_object()) {
                if (const auto k = ext->find("KHR_materials_emissive_strength");
                    k != ext->end() && k->is_object()) {
                    const auto st = k->find("emissiveStrength");
                    const float strength =
                        st != k->end() && st->is_number() ? st->get<float>() : 1.0f;
                    if (std::isfinite(strength) && strength >= 0.0f)  // kept finite:
                        uv.emissiveColor = glm::min(uv.emissiveColor * strength, glm::vec3(1e6f));
                }
                uv.unlit = ext->contains("KHR_materials_unlit");
                uv.specularGlossiness = ext->contains("KHR_materials_pbrSpecularGlossiness") &&
                                        !m.contains("pbrMetallicRoughness");
            }
            slot(m, "normalTexture", &uv.normalTexture, uv.normalTexCoord, uv.normal);
            if (const auto n = m.find("normalTexture"); n != m.end() && n->is_object()) {
                if (auto k = n->find("scale"); k != n->end() && k->is_number() &&
                                               std::isfinite(k->get<float>()))
                    uv.normalScale = k->get<float>();
            }
            slot(m, "occlusionTexture", &uv.occlusionTexture, uv.occlusionTexCoord, uv.occlusion);
            slot(m, "emissiveTexture", &uv.emissiveTexture, uv.emissiveTexCoord, uv.emissive);
        }
        out.push_back(uv);
    }
    return out;
}

struct Loader {
    std::filesystem::path path;
    std::string what;
    const aiScene* ai = nullptr;
    Scene scene;
    std::map<std::string, int> textureByKey;  ///< one Texture per image, however many users
    std::vector<MtlMaterial> mtl;             ///< OBJ only
    bool isObj = false;
    SceneLoadInfo* info = nullptr;  ///< strict in, warnings out

    /// The Texture of image `key` (a file beside the model, or assimp's "*N" embedded image),
    /// as colour or, `linear`, as data (scene.h Texture::linear: one Texture each); -1 when the
    /// file is missing (a warning saying `fallback`, what is drawn instead).
    Result<int> texture(const std::string& key, const std::string& materialName,
                        bool linear = false,
                        const char* fallback = "the material's base colour is used") {
        const std::string cacheKey = linear ? key + "\n(linear)" : key;
        if (auto it = textureByKey.find(cacheKey); it != textureByKey.end()) return it->second;
        const std::string where =
            fmt::format("{}: material '{}': texture '{}'", what, materialName, key);
        Result<Image> image = inputError("unset");
        std::string name;
        const aiTexture* embedded = ai ? ai->GetEmbeddedTexture(key.c_str()) : nullptr;
        if (embedded) {
            name = fmt::format("{}: image {}", path.filename().string(), key);
            if (embedded->mHeight == 0) {
                image = decodeImageBytes(
                    std::span(reinterpret_cast<const std::uint8_t*>(embedded->pcData),
                              embedded->mWidth),
                    where);
            } else {  // raw BGRA texels
                Image img(int(embedded->mWidth), int(embedded->mHeight));
                for (unsigned y = 0; y < embedded->mHeight; ++y)
                    for (unsigned x = 0; x < embedded->mWidth; ++x) {
                        const aiTexel& t = embedded->pcData[y * embedded->mWidth + x];
                        img.set(int(x), int(y), {t.r, t.g, t.b, t.a});
                    }
                image = std::move(img);
            }
        } else if (!key.empty() && key[0] == '*') {
            return inputError(fmt::format("{}: no such embedded image", where));
        } else {
            std::filesystem::path file = path.parent_path() / detail::uriDecode(key);
            std::error_code ec;
            if (!std::filesystem::exists(file, ec) && key.find('\\') != std::string::npos) {
                std::string slashed = detail::uriDecode(key);  // ".\\tex.jpg" (LightWave's MTL)
                std::replace(slashed.begin(), slashed.end(), '\\', '/');
                file = path.parent_path() / slashed;
            }
            if (!std::filesystem::exists(file, ec) && !(info && info->strict)) {
                if (info) {
                    info->warnings.push_back(fmt::format(
                        "{}: file not found: {} (--strict: an error)", where, fallback));
                }
                textureByKey.emplace(cacheKey, -1);
                return -1;
            }
            name = file.string();
            image = readImageFile(file, where);
        }
        if (!image) return image.status();
        const int index = int(scene.textures.size());
        scene.textures.push_back({name, std::move(*image), linear});
        textureByKey.emplace(cacheKey, index);
        return index;
    }

    /// `uv`: the glTF material's texture slots (null for OBJ, and for assimp's default
    /// material).
    /// `setsAlike`: GltfMaterialUv::readsCoords.
    Result<Material> material(const aiMaterial& m, const GltfMaterialUv* uv,
                              bool setsAlike = false) {
        Material out;
        aiString name;
        if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out.name = name.C_Str();
        aiColor4D base(0.8f, 0.8f, 0.8f, 1.0f);
        if (m.Get(AI_MATKEY_BASE_COLOR, base) == AI_SUCCESS ||
            m.Get(AI_MATKEY_COLOR_DIFFUSE, base) == AI_SUCCESS) {
            out.albedo = glm::clamp(glm::vec3(base.r, base.g, base.b), 0.0f, 1.0f);
            out.alpha = std::clamp(base.a, 0.0f, 1.0f);
        }
        if (isObj) {
            // assimp never sees the MTL (model_guard.h): usemtl names its material.
            const MtlMaterial* mm = findMtl(mtl, out.name);
            out.albedo = mm ? mm->diffuse : glm::vec3(0.8f);
            out.alpha = mm ? mm->dissolve : 1.0f;
            if (out.alpha < 1.0f) out.alphaMode = AlphaMode::Blend;
            if (mm && !mm->diffuseMap.empty()) {
                auto t = texture(mm->diffuseMap, out.name);
                if (!t) return t.status();
                out.baseColorTexture = *t;
            }
            return out;
        }
        aiString mode;
        if (m.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS) {
            const std::string s = mode.C_Str();
            out.alphaMode = s == "MASK"    ? AlphaMode::Mask
                            : s == "BLEND" ? AlphaMode::Blend
                                           : AlphaMode::Opaque;
        }
        float cutoff = 0.5f;
        if (m.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS && std::isfinite(cutoff))
            out.alphaCutoff = cutoff;
        int twoSided = 0;
        if (m.Get(AI_MATKEY_TWOSIDED, twoSided) == AI_SUCCESS) out.doubleSided = twoSided != 0;
        if (uv) {
            out.baseColorTexCoord = uv->baseColorTexCoord;
            out.baseColorTransform = uv->baseColor;
            out.metallicRoughnessTransform = uv->metallicRoughness;
            out.normalTransform = uv->normal;
            out.occlusionTransform = uv->occlusion;
            out.emissiveTransform = uv->emissive;
            out.model = uv->unlit                ? MaterialModel::Unlit
                        : uv->specularGlossiness ? MaterialModel::BlinnPhong
                                                 : MaterialModel::MetallicRoughness;
            out.metallic = uv->metallic;
            out.roughness = uv->roughness;
            out.emissive = uv->emissiveColor;
        }
        bool samplerRead = false;  // the first slot drawn gives the material's one sampler
        auto readSampler = [&](aiTextureType type, const aiTextureMapMode modes[2]) {
            if (samplerRead) return;
            samplerRead = true;
            int wrapU = modes[0], wrapV = modes[1];
            m.Get(AI_MATKEY_MAPPINGMODE_U(type, 0), wrapU);
            m.Get(AI_MATKEY_MAPPINGMODE_V(type, 0), wrapV);
            out.sampler.wrapS = wrapFrom(wrapU);
            out.sampler.wrapT = wrapFrom(wrapV);
            int mag = 0, min = 0;
            if (m.Get(AI_MATKEY_GLTF_MAPPINGFILTER_MAG(type, 0), mag) == AI_SUCCESS)
                out.sampler.magFilter =
                    mag == 9728 ? TextureFilter::Nearest : TextureFilter::Linear;
            if (m.Get(AI_MATKEY_GLTF_MAPPINGFILTER_MIN(type, 0), min) == AI_SUCCESS) {
                // 9728 NEAREST, 9729 LINEAR, 9984..9987 {NEAREST,LINEAR}_MIPMAP_{NEAREST,LINEAR}
                out.sampler.minFilter = (min == 9728 || min == 9984 || min == 9986)
                                            ? TextureFilter::Nearest
                                            : TextureFilter::Linear;
                out.sampler.mipmaps = min >= 9984 && min <= 9987;
            }
        };
        for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
            if (m.GetTextureCount(type) == 0) continue;
            aiString file;
            unsigned uvIndex = 0;
            aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
            if (m.GetTexture(type, 0, &file, nullptr, &uvIndex, nullptr, nullptr, modes) !=
                AI_SUCCESS)
                continue;
            // The set: baseColorTexture's (0 or 1, baked into Mesh::texcoords by convertMesh);
            // otherwise (KHR_materials_pbrSpecularGlossiness' diffuse) set 0 only.
            if (uvIndex != 0 && !(uv && uv->baseColorTexture)) break;
            auto t = texture(file.C_Str(), out.name);
            if (!t) return t.status();
            out.baseColorTexture = *t;
            readSampler(type, modes);
            break;
        }
        if (!uv) return out;
        // glTF's other slots (issue 39; assimp 5.2.5 lists the metallic-roughness texture as
        // aiTextureType_METALNESS, the occlusion as LIGHTMAP with its strength, the emissive as
        // EMISSIVE). Each reads Mesh::texcoords, which hold one set through one transform
        // (GltfMaterialUv::coords): a slot reading others is not drawn, with a warning.
        struct MapSlot {
            const char* name;
            aiTextureType type;
            bool given;
            int set;
            const std::optional<TextureTransform>* transform;
            bool linear;
            int* index;
        };
        const MapSlot slots[] = {
            {"metallic-roughness", aiTextureType_METALNESS, uv->metallicRoughnessTexture,
             uv->metallicRoughnessTexCoord, &uv->metallicRoughness, true,
             &out.metallicRoughnessTexture},
            {"occlusion", aiTextureType_LIGHTMAP, uv->occlusionTexture, uv->occlusionTexCoord,
             &uv->occlusion, true, &out.occlusionTexture},
            {"emissive", aiTextureType_EMISSIVE, uv->emissiveTexture, uv->emissiveTexCoord,
             &uv->emissive, false, &out.emissiveTexture},
            {"normal", aiTextureType_NORMALS, uv->normalTexture, uv->normalTexCoord, &uv->normal,
             true, &out.normalTexture},
        };
        for (const MapSlot& slot : slots) {
            if (!slot.given) continue;
            aiString file;
            aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
            if (m.GetTextureCount(slot.type) == 0 ||
                m.GetTexture(slot.type, 0, &file, nullptr, nullptr, nullptr, nullptr, modes) !=
                    AI_SUCCESS)
                continue;
            if (!uv->readsCoords(slot.set, *slot.transform, setsAlike)) {
                if (info) {
                    info->warnings.push_back(fmt::format(
                        "{}: material '{}': its {} texture reads other texture coordinates "
                        "(set {} or KHR_texture_transform) than its first texture: not drawn",
                        what, out.name, slot.name, slot.set));
                }
                continue;
            }
            auto t = texture(file.C_Str(), out.name, slot.linear,
                             slot.index == &out.metallicRoughnessTexture
                                 ? "the map is not drawn (the material keeps Blinn-Phong)"
                                 : "the map is not drawn");
            if (!t) return t.status();
            *slot.index = *t;
            if (*t >= 0) readSampler(slot.type, modes);
        }
        out.normalScale = uv->normalScale;
        if (uv->occlusionTexture) {
            float strength = 1.0f;
            if (m.Get(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), strength) ==
                    AI_SUCCESS &&
                std::isfinite(strength))
                out.occlusionStrength = std::clamp(strength, 0.0f, 1.0f);
        }
        withoutNeutralFactors(out, *uv);
        return out;
    }

    /// The neutral factors exporters write beside a texture (GltfMaterialUv) are not drawn
    /// without it: an emissive map not drawn takes its emissive with it, a metallic-roughness
    /// map not drawn leaves Blinn-Phong (its factors 1 and 1 alone are a rough metal).
    static void withoutNeutralFactors(Material& m, const GltfMaterialUv& uv) {
        if (uv.emissiveTexture && m.emissiveTexture < 0) m.emissive = glm::vec3(0.0f);
        if (uv.metallicRoughnessTexture && m.metallicRoughnessTexture < 0 &&
            m.model == MaterialModel::MetallicRoughness)
            m.model = MaterialModel::BlinnPhong;
    }
};

/// One aiMesh as a Mesh: triangles only, smooth normals where the file has none.
/// `srgbColors`: vertex colours are sRGB-encoded (an OBJ's), not linear (glTF's COLOR_0).
/// Mesh::texcoords are the aiMesh's set `uvSet` (glTF's TEXCOORD_n is assimp's channel n, in
/// glTF's uv space after FlipUVs), each mapped by `transform` when given.
std::optional<Mesh> convertMesh(const aiMesh& in, const std::string& name, bool srgbColors,
                                unsigned uvSet = 0,
                                const std::optional<TextureTransform>& transform = {},
                                bool computedTangents = false) {
    if (!(in.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return std::nullopt;
    Mesh mesh;
    mesh.name = name;
    const bool hasUv = uvSet < AI_MAX_NUMBER_OF_TEXTURECOORDS && in.HasTextureCoords(uvSet);
    for (unsigned v = 0; v < in.mNumVertices; ++v) {
        mesh.positions.emplace_back(in.mVertices[v].x, in.mVertices[v].y, in.mVertices[v].z);
        if (in.HasNormals())
            mesh.normals.emplace_back(in.mNormals[v].x, in.mNormals[v].y, in.mNormals[v].z);
        if (hasUv) {
            const glm::vec2 uv(in.mTextureCoords[uvSet][v].x, in.mTextureCoords[uvSet][v].y);
            mesh.texcoords.push_back(transform ? transform->apply(uv) : uv);
        }
        if (in.HasVertexColors(0)) {
            const aiColor4D& c = in.mColors[0][v];
            const glm::vec4 rgba(c.r, c.g, c.b, c.a);
            mesh.colors.push_back(srgbColors ? decodeSrgbColor(rgba)
                                             : glm::clamp(rgba, glm::vec4(0.0f), glm::vec4(1.0f)));
        }
    }
    for (unsigned f = 0; f < in.mNumFaces; ++f) {
        const aiFace& face = in.mFaces[f];
        if (face.mNumIndices != 3) continue;
        for (int k = 0; k < 3; ++k) mesh.indices.push_back(face.mIndices[k]);
    }
    if (mesh.indices.empty()) return std::nullopt;
    bool normalsUsable = mesh.normals.size() == mesh.positions.size();
    for (glm::vec3& n : mesh.normals) {
        const float len = glm::length(n);
        normalsUsable = normalsUsable && std::isfinite(len) && len > 0.5f;
        if (normalsUsable) n /= len;
    }
    if (!normalsUsable) computeSmoothNormals(mesh);
    // Tangents (normal maps): the file's TANGENT (assimp keeps xyz and makes the bitangent
    // cross(n, t) · w) or assimp's aiProcess_CalcTangentSpace's (`computedTangents`: along +u
    // and +v of glTF's uv after FlipUVs, v down the image, where glTF's bitangent runs up it),
    // the handedness from the bitangent's side.
    if (in.HasTangentsAndBitangents() && !mesh.texcoords.empty()) {
        for (unsigned v = 0; v < in.mNumVertices; ++v) {
            const glm::vec3 t(in.mTangents[v].x, in.mTangents[v].y, in.mTangents[v].z);
            const glm::vec3 b(in.mBitangents[v].x, in.mBitangents[v].y, in.mBitangents[v].z);
            const float len = glm::length(t);
            const glm::vec3 unit = std::isfinite(len) && len > 0.0f ? t / len : glm::vec3(0.0f);
            const bool down = glm::dot(glm::cross(mesh.normals[v], unit), b) < 0.0f;
            const float w = down != computedTangents ? -1.0f : 1.0f;
            mesh.tangents.emplace_back(unit, w);
        }
    }
    // Morph targets (glTF `targets`): assimp holds each as the morphed mesh (base +
    // displacement) and the mesh's default weight; mvr keeps the displacements.
    std::vector<float> weights;
    for (unsigned t = 0; t < in.mNumAnimMeshes; ++t) {
        const aiAnimMesh* am = in.mAnimMeshes[t];
        if (!am || am->mNumVertices != in.mNumVertices) continue;
        MorphTarget target;
        target.positions.resize(in.mNumVertices, glm::vec3(0.0f));
        if (am->HasPositions())
            for (unsigned v = 0; v < in.mNumVertices; ++v) {
                const aiVector3D d = am->mVertices[v] - in.mVertices[v];
                target.positions[v] = glm::vec3(d.x, d.y, d.z);
            }
        if (am->HasNormals() && in.HasNormals()) {
            target.normals.resize(in.mNumVertices);
            for (unsigned v = 0; v < in.mNumVertices; ++v) {
                const aiVector3D d = am->mNormals[v] - in.mNormals[v];
                target.normals[v] = glm::vec3(d.x, d.y, d.z);
            }
        }
        mesh.morphTargets.push_back(std::move(target));
        weights.push_back(std::isfinite(am->mWeight) ? am->mWeight : 0.0f);
    }
    if (!mesh.morphTargets.empty()) {
        mesh.computedNormals = !normalsUsable;
        mesh.basePositions = mesh.positions;
        mesh.baseNormals = mesh.normals;
        applyMorphWeights(mesh, weights);  // the mesh's default weights
    }
    // Skins: assimp's bones (one per joint of the node's skin, mOffsetMatrix its inverse bind
    // matrix; the weights follow its own vertex processing); each vertex keeps its 8 largest
    // influences (JOINTS_0 / WEIGHTS_0 and JOINTS_1 / WEIGHTS_1: Mesh::joints1 / weights1,
    // only when a vertex has more than 4), renormalised; a ninth and beyond are dropped.
    if (in.HasBones() && in.mNumBones <= 65535u) {
        std::vector<std::vector<std::pair<float, unsigned>>> influences(in.mNumVertices);
        for (unsigned b = 0; b < in.mNumBones; ++b) {
            const aiBone& bone = *in.mBones[b];
            for (unsigned k = 0; k < bone.mNumWeights; ++k) {
                const aiVertexWeight& vw = bone.mWeights[k];
                if (vw.mVertexId < in.mNumVertices && vw.mWeight > 0.0f &&
                    std::isfinite(vw.mWeight))
                    influences[vw.mVertexId].emplace_back(vw.mWeight, b);
            }
        }
        mesh.joints.resize(in.mNumVertices, glm::u16vec4(0));
        mesh.weights.resize(in.mNumVertices, glm::vec4(0.0f));
        const bool eight = std::any_of(influences.begin(), influences.end(),
                                       [](const auto& list) { return list.size() > 4; });
        if (eight) {
            mesh.joints1.resize(in.mNumVertices, glm::u16vec4(0));
            mesh.weights1.resize(in.mNumVertices, glm::vec4(0.0f));
        }
        for (unsigned v = 0; v < in.mNumVertices; ++v) {
            auto& list = influences[v];
            std::sort(list.begin(), list.end(), [](const auto& a, const auto& b) {
                return a.first > b.first || (a.first == b.first && a.second < b.second);
            });
            float sum = 0.0f;
            for (std::size_t k = 0; k < list.size() && k < 8; ++k) sum += list[k].first;
            for (std::size_t k = 0; k < list.size() && k < 8; ++k) {
                auto& joints = k < 4 ? mesh.joints[v] : mesh.joints1[v];
                auto& weights = k < 4 ? mesh.weights[v] : mesh.weights1[v];
                joints[int(k % 4)] = std::uint16_t(list[k].second);
                weights[int(k % 4)] = list[k].first / sum;
            }
            // unweighted (all 0): poseSkin leaves the vertex where it is
        }
        if (mesh.basePositions.empty()) {
            mesh.basePositions = mesh.positions;
            mesh.baseNormals = mesh.normals;
        }
        mesh.baseTangents = mesh.tangents;
    }
    return mesh;
}

/// The skin of the node that instances `am` (assimp's bones), bound to `nodeOf`'s nodes:
/// joint j is bone j's node, its inverse bind matrix the bone's offset matrix.
struct BoundSkin {
    std::vector<const aiNode*> joints;
    std::vector<glm::mat4> inverseBind;
};
BoundSkin boundSkin(const aiScene& ai, const aiMesh& am) {
    BoundSkin s;
    for (unsigned b = 0; b < am.mNumBones; ++b) {
        const aiBone& bone = *am.mBones[b];
        s.joints.push_back(ai.mRootNode->FindNode(bone.mName));
        s.inverseBind.push_back(toGlm(bone.mOffsetMatrix));
    }
    return s;
}

/// Binds the glTF nodes (depth first from the scene's roots) to assimp's: the same hierarchy
/// walked in the same order (assimp adds one root above several scene roots). False when the
/// two differ (then the animation cannot be placed).
bool bindNodes(const aiNode& root, const detail::GltfAnimationFile& file,
               std::map<const aiNode*, int>& out) {
    std::function<bool(const aiNode&, int)> match = [&](const aiNode& ai, int node) {
        const std::vector<int>& kids = file.children[std::size_t(node)];
        const std::string& name = file.animation.nodes[std::size_t(node)].name;
        if (ai.mNumChildren != kids.size()) return false;
        if (!name.empty() && name != ai.mName.C_Str()) return false;
        out[&ai] = node;
        for (unsigned c = 0; c < ai.mNumChildren; ++c)
            if (!match(*ai.mChildren[c], kids[c])) return false;
        return true;
    };
    if (file.roots.size() == 1) return match(root, file.roots[0]);
    if (root.mNumChildren != file.roots.size()) return false;
    for (unsigned c = 0; c < root.mNumChildren; ++c)
        if (!match(*root.mChildren[c], file.roots[c])) return false;
    return true;
}

}  // namespace

glm::mat4 Placement::matrix() const {
    return glm::translate(glm::mat4(1.0f), position) *
           glm::rotate(glm::mat4(1.0f), glm::radians(yawDegrees), glm::vec3(0, 1, 0)) *
           glm::scale(glm::mat4(1.0f), glm::vec3(scale));
}

void transformScene(Scene& scene, const glm::mat4& worldFromScene) {
    for (Instance& inst : scene.instances)
        inst.worldFromModel = worldFromScene * inst.worldFromModel;
    const glm::mat3 linear(worldFromScene);
    for (Light& l : scene.lights) {
        const glm::vec3 d = linear * l.towardLight;
        if (glm::length(d) > 0.0f) l.towardLight = glm::normalize(d);
        l.position = glm::vec3(worldFromScene * glm::vec4(l.position, 1.0f));
    }
    if (scene.camera)
        scene.camera->worldFromCamera = worldFromScene * scene.camera->worldFromCamera;
    if (scene.viewpoint) {
        scene.viewpoint->position =
            glm::vec3(worldFromScene * glm::vec4(scene.viewpoint->position, 1));
        scene.viewpoint->target = glm::vec3(worldFromScene * glm::vec4(scene.viewpoint->target, 1));
    }
}

void appendScene(Scene& scene, Scene other) {
    const int meshBase = int(scene.meshes.size()), textureBase = int(scene.textures.size());
    for (Mesh& m : other.meshes) scene.meshes.push_back(std::move(m));
    for (Texture& t : other.textures) scene.textures.push_back(std::move(t));
    for (Instance inst : other.instances) {
        inst.mesh += meshBase;
        Material& m = inst.material;
        for (int* t : {&m.baseColorTexture, &m.metallicRoughnessTexture, &m.occlusionTexture,
                       &m.emissiveTexture, &m.normalTexture})
            if (*t >= 0) *t += textureBase;
        scene.instances.push_back(std::move(inst));
    }
    for (const Light& l : other.lights) scene.lights.push_back(l);
    if (!scene.camera) scene.camera = other.camera;
}

Result<Scene> loadScene(const std::filesystem::path& path, SceneLoadInfo* info) {
    SceneLoadInfo localInfo;
    SceneLoadInfo& out = info ? *info : localInfo;
    const std::string ext = lower(path.extension().string());
    Loader loader;
    loader.path = path;
    loader.what = fmt::format("mvr::loadScene(): {}", path.string());
    loader.isObj = ext == ".obj";
    loader.info = &out;
    // PLY, OBJ without materials, ...: loadMesh()'s merged mesh (one read), default material,
    // default lights.
    auto plain = [](Result<Mesh> merged) -> Result<Scene> {
        if (!merged) return merged.status();
        Scene s;
        s.meshes.push_back(std::move(merged).value());
        s.instances.push_back({0, glm::mat4(1.0f), Material{}});
        if (!s.meshes[0].colors.empty()) s.instances[0].material.albedo = glm::vec3(1.0f);
        s.lights = defaultLights();
        return s;
    };
    const bool gltf = ext == ".gltf" || ext == ".glb";
    if (!gltf && !loader.isObj) return plain(loadMesh(path, &out.warnings));
    if (loader.isObj) {
        auto mtl = loadObjMaterials(path);
        // An OBJ whose material library is missing or malformed still loads, as before
        // scenes (loadMesh() never read it): plain, with a warning.
        if (!mtl) {
            out.warnings.push_back(
                fmt::format("{}: materials not used: {}", loader.what, mtl.status().message()));
        } else {
            loader.mtl = std::move(mtl).value();
        }
        if (loader.mtl.empty()) return plain(loadMesh(path, &out.warnings));
    }
    // glTF and OBJ + MTL: loadMesh()'s checks (model_guard.h), then one import below.
    auto pre = detail::preflightModel(path, loader.what);
    if (!pre) return pre.status();
    if (pre->ply) return plain(loadMesh(path, &out.warnings));  // PLY content: mvr's reader, never assimp
    out.fromMaterials = true;

    Assimp::Importer importer;
    importer.SetIOHandler(new detail::ModelIOSystem(path));
    // FlipUVs: assimp hands out v up (OpenGL); Texture wants (0, 0) = top-left (glTF, image row 0).
    const aiScene* ai = importer.ReadFile(
        path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                           aiProcess_SortByPType | aiProcess_ValidateDataStructure |
                           aiProcess_FindInvalidData | aiProcess_FlipUVs);
    if (!ai || !ai->mRootNode) {
        if (pre->objAllZeroArea)
            return inputError(loader.what + ": is degenerate (every face has zero area)");
        std::string why = importer.GetErrorString();
        return inputError(fmt::format("{}: not a readable model (assimp: {})", loader.what,
                                      why.empty() ? "unknown error" : why));
    }
    loader.ai = ai;
    Scene& scene = loader.scene;

    // glTF: the file's JSON (parsed once more: assimp's own is out of reach) for what assimp
    // drops (the materials' texture coordinates, the lights' range).
    const nlohmann::json doc = gltf ? gltfDocument(path, ext == ".glb") : nlohmann::json(nullptr);
    std::vector<GltfMaterialUv> materialUv = materialTextureCoords(doc);
    if (materialUv.size() + 1 != ai->mNumMaterials) materialUv.clear();  // does not line up
    // Normal maps need tangents: a file's TANGENT as it is, else assimp's (on set 0), only when
    // some material has a normal map (the step costs a pass over every mesh).
    std::vector<char> fileTangents(ai->mNumMeshes);
    for (unsigned m = 0; m < ai->mNumMeshes; ++m)
        fileTangents[m] = ai->mMeshes[m]->HasTangentsAndBitangents();
    if (std::any_of(materialUv.begin(), materialUv.end(),
                    [](const GltfMaterialUv& m) { return m.normalTexture; })) {
        ai = importer.ApplyPostProcessing(aiProcess_CalcTangentSpace);
        if (!ai) {
            return inputError(fmt::format("{}: computing tangents failed (assimp: {})",
                                          loader.what, importer.GetErrorString()));
        }
        loader.ai = ai;
    }
    auto uvOf = [&](unsigned material) {
        return material < materialUv.size() ? &materialUv[material] : nullptr;
    };
    // Meshes: one per aiMesh (a glTF primitive); -1 for those with no triangles. A glTF mesh's
    // texture coordinates are its material's base colour set with the base colour transform
    // baked in (a primitive has one material, whichever nodes instance it); a set 1 it lacks
    // falls back to set 0 with a warning (an error with --strict, as a missing texture).
    std::vector<int> meshIndex(ai->mNumMeshes, -1);
    bool anyDegenerate = false;  // a mesh whose triangles all have zero area (skipped)
    for (unsigned m = 0; m < ai->mNumMeshes; ++m) {
        const aiMesh& am = *ai->mMeshes[m];
        std::string name = am.mName.length ? am.mName.C_Str() : fmt::format("mesh {}", m);
        const GltfMaterialUv* uv = uvOf(am.mMaterialIndex);
        const GltfMaterialUv::Coords coords = uv ? uv->coords() : GltfMaterialUv::Coords{};
        unsigned set = unsigned(coords.set);
        std::string missingSet;
        if (set != 0 && !am.HasTextureCoords(set) && am.HasTextureCoords(0)) {
            aiString materialName;
            ai->mMaterials[am.mMaterialIndex]->Get(AI_MATKEY_NAME, materialName);
            missingSet = fmt::format(
                "{}: material '{}': its {} texture reads texture coordinate set {} "
                "(TEXCOORD_{}), which mesh '{}' does not have",
                loader.what, materialName.C_Str(),
                uv->baseColorTexture ? "base colour" : "first", set, set, name);
            set = 0;
        }
        auto mesh = convertMesh(am, fmt::format("{}: {}", path.filename().string(), name), !gltf,
                                set, coords.transform, !fileTangents[m]);
        if (!mesh) continue;
        // assimp computes tangents on set 0 as the file holds it: they frame Mesh::texcoords
        // only when those are set 0 without a rotating or mirroring transform.
        const bool framed = !coords.transform || (coords.transform->rotation == 0.0f &&
                                                  coords.transform->scale.x > 0.0f &&
                                                  coords.transform->scale.y > 0.0f);
        if (!fileTangents[m] && !mesh->tangents.empty() && !(set == 0 && framed)) {
            mesh->tangents.clear();
            mesh->baseTangents.clear();
            if (uv && uv->normalTexture) {
                out.warnings.push_back(fmt::format(
                    "{}: mesh '{}': its normal map is not drawn (the file gives no TANGENT, and "
                    "tangents are computed for texture coordinate set 0 without a rotating or "
                    "mirroring KHR_texture_transform)",
                    loader.what, name));
            }
        }
        if (!missingSet.empty()) {
            if (out.strict) return inputError(missingSet);
            out.warnings.push_back(missingSet + ": set 0 is used (--strict: an error)");
        }
        if (Status s = validateMesh(*mesh, fmt::format("{}: mesh '{}'", loader.what, name)); !s) {
            if (s.message().find("degenerate") != std::string::npos) {
                anyDegenerate = true;
                continue;
            }
            return s;
        }
        optimizeMeshLocality(*mesh);
        meshIndex[m] = int(scene.meshes.size());
        scene.meshes.push_back(std::move(*mesh));
    }
    // Whether every mesh of material `mi` holds the same texture coordinates in sets 0 and 1.
    auto setsAlike = [&](unsigned mi) {
        bool any = false;
        for (unsigned k = 0; k < ai->mNumMeshes; ++k) {
            const aiMesh& am = *ai->mMeshes[k];
            if (am.mMaterialIndex != mi) continue;
            if (!am.HasTextureCoords(0) || !am.HasTextureCoords(1)) return false;
            for (unsigned v = 0; v < am.mNumVertices; ++v) {
                if (am.mTextureCoords[0][v].x != am.mTextureCoords[1][v].x ||
                    am.mTextureCoords[0][v].y != am.mTextureCoords[1][v].y)
                    return false;
            }
            any = true;
        }
        return any;
    };
    // Materials, decoded lazily: only those an instance uses.
    std::vector<std::optional<Material>> materials(ai->mNumMaterials);
    std::map<std::string, glm::mat4> worldByName;
    std::vector<std::pair<const aiNode*, glm::mat4>> nodes;
    collectWorld(*ai->mRootNode, glm::mat4(1.0f), worldByName, nodes);
    const std::map<const aiNode*, glm::mat4> worldOf(nodes.begin(), nodes.end());
    // glTF animations (gltf_animation.h): read from the file, bound to assimp's nodes.
    std::optional<detail::GltfAnimationFile> animation;
    std::map<const aiNode*, int> animNode;
    if (gltf) {
        auto read = detail::readGltfAnimation(path, loader.what);
        if (!read) return read.status();
        animation = std::move(read).value();
        if (animation) {
            for (const std::string& w : animation->warnings)
                out.warnings.push_back(fmt::format("{}: {}", loader.what, w));
            if (!bindNodes(*ai->mRootNode, *animation, animNode)) {
                out.warnings.push_back(fmt::format(
                    "{}: animation '{}' is not played (assimp's node hierarchy differs from the "
                    "file's)",
                    loader.what, animation->animation.name));
                animation.reset();
            }
        }
    }
    for (const auto& [node, world] : nodes) {
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            const unsigned m = node->mMeshes[k];
            if (m >= ai->mNumMeshes || meshIndex[m] < 0) continue;
            const unsigned mi = ai->mMeshes[m]->mMaterialIndex;
            Material mat;
            if (mi < ai->mNumMaterials) {
                if (!materials[mi]) {
                    auto made = loader.material(*ai->mMaterials[mi], uvOf(mi), setsAlike(mi));
                    if (!made) return made.status();
                    materials[mi] = std::move(*made);
                }
                mat = *materials[mi];
            }
            if (hasTexture(mat) && scene.meshes[meshIndex[m]].texcoords.empty()) {
                out.warnings.push_back(fmt::format(
                    "{}: material '{}': its texture is not drawn on mesh '{}' (no texture "
                    "coordinates)",
                    loader.what, mat.name, scene.meshes[meshIndex[m]].name));
                mat.baseColorTexture = mat.metallicRoughnessTexture = -1;
                mat.occlusionTexture = mat.emissiveTexture = mat.normalTexture = -1;
                if (const GltfMaterialUv* uv = uvOf(mi)) Loader::withoutNeutralFactors(mat, *uv);
            }
            // A skinned mesh (glTF skins): the node's own transform does not place it (the
            // specification's rule), its joints do, in the file's root space: posed by their
            // rest transforms here (a still shows the file's pose, not the bind pose moved by
            // the node), per frame by the animation (SceneAnimation::Skin). The instance stays
            // where the root is, so nodes sharing the mesh draw it alike.
            Mesh& drawn = scene.meshes[std::size_t(meshIndex[m])];
            const bool skinned = !drawn.joints.empty();
            if (skinned) {
                const BoundSkin skin = boundSkin(*ai, *ai->mMeshes[m]);
                std::vector<glm::mat4> matrices(skin.joints.size(), glm::mat4(1.0f));
                SceneAnimation::Skin played;
                played.instance = int(scene.instances.size());
                bool bound = bool(animation);
                for (std::size_t j = 0; j < skin.joints.size(); ++j) {
                    auto w = skin.joints[j] ? worldOf.find(skin.joints[j]) : worldOf.end();
                    if (w != worldOf.end()) {
                        matrices[j] = w->second * skin.inverseBind[j];
                    } else {
                        out.warnings.push_back(fmt::format(
                            "{}: mesh '{}': its skin's joint {} ('{}') is not a node of the "
                            "file: that joint does not move it",
                            loader.what, drawn.name, j, ai->mMeshes[m]->mBones[j]->mName.C_Str()));
                    }
                    auto a = skin.joints[j] ? animNode.find(skin.joints[j]) : animNode.end();
                    bound = bound && a != animNode.end();
                    if (bound) played.joints.push_back(a->second);
                }
                poseSkin(drawn, matrices);
                if (bound) {
                    played.inverseBind = skin.inverseBind;
                    animation->animation.skins.push_back(std::move(played));
                }
            } else if (animation) {
                if (auto it = animNode.find(node); it != animNode.end()) {
                    animation->animation.instances.push_back(
                        {int(scene.instances.size()), it->second, glm::mat4(1.0f)});
                }
            }
            scene.instances.push_back(
                {meshIndex[m], skinned ? glm::mat4(1.0f) : world, std::move(mat)});
        }
    }
    if (scene.instances.empty()) {
        return inputError(loader.what + (anyDegenerate
                                             ? ": is degenerate (every triangle has zero area)"
                                             : ": has no triangles"));
    }

    auto nodeWorld = [&](const aiString& name) {
        auto it = worldByName.find(name.C_Str());
        return it == worldByName.end() ? glm::mat4(1.0f) : it->second;
    };
    if (ai->mNumCameras > 0) {
        const aiCamera& c = *ai->mCameras[0];
        const glm::mat4 world = nodeWorld(c.mName);
        // glTF: the camera sits at its node's origin looking down the node's -Z, +Y up.
        // (assimp 5.2.5 also copies the node's translation into mPosition: not used.)
        SceneCamera cam;
        cam.worldFromCamera = world;
        cam.aspect = std::isfinite(c.mAspect) && c.mAspect > 0.0f ? c.mAspect : 0.0f;
        // assimp 5.2.5 stores mHorizontalFOV = yfov × (aspectRatio, or 1 when absent).
        if (std::isfinite(c.mHorizontalFOV) && c.mHorizontalFOV > 0.0f)
            cam.yfovRadians = c.mHorizontalFOV / (cam.aspect > 0.0f ? cam.aspect : 1.0f);
        if (std::isfinite(c.mClipPlaneNear) && c.mClipPlaneNear > 0.0f)
            cam.znear = c.mClipPlaneNear;
        if (std::isfinite(c.mClipPlaneFar) && c.mClipPlaneFar > cam.znear)
            cam.zfar = c.mClipPlaneFar;
        cam.name = c.mName.C_Str();
        if (std::isfinite(cam.yfovRadians) && cam.yfovRadians > 0.0f && cam.yfovRadians < 3.14f) {
            scene.camera = cam;
            if (animation) {
                const aiNode* node = ai->mRootNode->FindNode(c.mName);
                if (auto it = animNode.find(node); node && it != animNode.end())
                    animation->animation.cameraNode = it->second;
            }
        }
    }
    // The lights as the file states them (range, the cone angles), when its JSON can be read
    // and lines up with assimp's lights; assimp's values otherwise.
    const std::vector<KhrLight> fileLights =
        ai->mNumLights > 0 ? khrLights(doc) : std::vector<KhrLight>{};
    const bool useFileLights = gltf && fileLights.size() == ai->mNumLights;
    for (unsigned l = 0; l < ai->mNumLights; ++l) {
        const aiLight& al = *ai->mLights[l];
        if (al.mType != aiLightSource_DIRECTIONAL && al.mType != aiLightSource_POINT &&
            al.mType != aiLightSource_SPOT)
            continue;
        if (scene.lights.size() >= std::size_t(kMaxLights)) {
            out.warnings.push_back(fmt::format("{}: light '{}' dropped (at most {} lights)",
                                               loader.what, al.mName.C_Str(), kMaxLights));
            continue;
        }
        const glm::mat4 world = nodeWorld(al.mName);
        Light light;
        light.type = al.mType == aiLightSource_DIRECTIONAL ? LightType::Directional
                     : al.mType == aiLightSource_POINT     ? LightType::Point
                                                           : LightType::Spot;
        light.color = glm::max(
            glm::vec3(al.mColorDiffuse.r, al.mColorDiffuse.g, al.mColorDiffuse.b), glm::vec3(0.0f));
        const glm::vec3 dir =
            glm::mat3(world) * glm::vec3(al.mDirection.x, al.mDirection.y, al.mDirection.z);
        light.towardLight = glm::length(dir) > 0.0f ? -glm::normalize(dir) : glm::vec3(0, 0, 1);
        light.position =
            glm::vec3(world * glm::vec4(al.mPosition.x, al.mPosition.y, al.mPosition.z, 1.0f));
        if (light.type == LightType::Spot) {
            light.innerConeCos = std::cos(al.mAngleInnerCone);
            light.outerConeCos = std::cos(al.mAngleOuterCone);
        }
        if (useFileLights) {
            const KhrLight& k = fileLights[l];
            light.color = glm::max(k.color * k.intensity, glm::vec3(0.0f));
            if (light.type != LightType::Directional && k.range > 0.0f) light.range = k.range;
            if (light.type == LightType::Spot) {
                light.innerConeCos = std::cos(k.innerConeAngle);
                light.outerConeCos = std::cos(k.outerConeAngle);
            }
        }
        if (!std::isfinite(light.color.x + light.color.y + light.color.z + light.position.x +
                           light.position.y + light.position.z)) {
            return inputError(fmt::format("{}: light '{}' has a non-finite color or position",
                                          loader.what, al.mName.C_Str()));
        }
        scene.lights.push_back(light);
    }
    out.lightsFromFile = !scene.lights.empty();
    if (scene.lights.empty()) scene.lights = defaultLights();
    if (Status s = validateScene(scene); !s)
        return Status(s.code(), fmt::format("{}: {}", loader.what, s.message()));
    if (animation) {
        if (Status s = validateSceneAnimation(animation->animation); !s)
            return Status(s.code(), fmt::format("{}: {}", loader.what, s.message()));
        out.animation = std::move(animation->animation);
    }
    return std::move(scene);
}

// ---- sky maps (--sky FILE) ----------------------------------------------------------------------

Result<Sky> loadSky(const std::string& spec, float hdrScale, Tonemap tonemap, bool asRadiance) {
    Sky sky;
    if (spec == "gradient") return sky;
    // mvr's PNG and JPEG decoders, not stb_image: stb_image 2.27 (Debian 12) writes past a
    // Huffman table for a JPEG whose DHT counts exceed 256 (found by tests/fuzz/sky, input in
    // tests/fuzz/regressions/sky/), and its authors do not mean it for untrusted files.
    const std::string what = fmt::format("--sky '{}'", spec);
    std::error_code ec;
    if (!std::filesystem::exists(spec, ec))
        return inputError(fmt::format(
            "{}: file not found (a PNG, JPEG, .hdr or .exr map, 'gradient' or 'environment')",
            what));
    if (Status s = checkRegularFile(spec, what); !s) return s;  // no FIFO, device, directory
    std::uint8_t head[16] = {};
    std::ifstream(spec, std::ios::binary).read(reinterpret_cast<char*>(head), sizeof head);
    static const std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (asRadiance || detail::isRadianceBytes(head) || detail::isExrBytes(head)) {
        auto map = loadEnvironmentMap(spec, "--sky");
        if (!map) return map.status();
        sky.kind = Sky::Kind::Equirect;
        sky.image = Image(map->width, map->height, Rgba8{0, 0, 0, 255});
        ShadingContext shown;
        shown.tonemap = tonemap;
        for (std::size_t k = 0; k < map->texels.size(); ++k) {
            const glm::vec3 c = finishColor(
                shown, glm::min(map->texels[k] * hdrScale, glm::vec3(kMaxRadiance)));
            std::uint8_t* p = sky.image.rgba.data() + 4 * k;
            p[0] = quantizeUnorm8(c.x), p[1] = quantizeUnorm8(c.y), p[2] = quantizeUnorm8(c.z);
        }
        return sky;
    }
    if (!std::equal(head, head + 8, kPng) && !isJpegBytes(head))
        return inputError(fmt::format("{}: not a PNG, JPEG, Radiance or OpenEXR image", what));
    auto image = readImageFile(spec, what);
    if (!image) return image.status();
    const int w = image->width, h = image->height;
    if (w == 2 * h) {
        sky.kind = Sky::Kind::Equirect;
    } else if (w * 3 == h * 4 && w % 4 == 0) {
        sky.kind = Sky::Kind::CubeCross;
    } else {
        return usageError(fmt::format(
            "{}: {}x{} is neither an equirectangular map (width = 2 x height) nor a horizontal "
            "cube cross (4:3)",
            what, w, h));
    }
    sky.image = std::move(image).value();
    return sky;
}


namespace {
/// FNV-1a (64 bits) of a file's bytes: RadianceMap::contentHash.
std::uint64_t bytesHash(std::span<const std::uint8_t> bytes) {
    std::uint64_t hash = 14695981039346656037ull;
    for (const std::uint8_t b : bytes) hash = (hash ^ b) * 1099511628211ull;
    return hash;
}
}  // namespace

/// An environment map file holds at most this many MiB.
constexpr int kMaxEnvironmentMiB = 512;

std::uint64_t environmentFileHash(const std::string& path) {
    auto bytes = readFileBytes(path, path, kMaxEnvironmentMiB);
    return bytes ? bytesHash(*bytes) : 0;
}

Result<RadianceMap> loadEnvironmentMap(const std::string& path, const std::string& option) {
    const std::string what = fmt::format("{} '{}'", option, path);
    auto read = readFileBytes(path, what, kMaxEnvironmentMiB);
    if (!read) return read.status();
    const std::vector<std::uint8_t>& bytes = *read;
    static const std::uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    RadianceMap map;
    const std::uint64_t hash = bytesHash(bytes);
    if (detail::isExrBytes(bytes)) {
        auto exr = detail::readExrRadiance(path, what);
        if (!exr) return exr.status();
        map = std::move(*exr);
    } else if (detail::isRadianceBytes(bytes)) {
        auto hdr = detail::decodeRadiance(bytes, what);
        if (!hdr) return hdr.status();
        map = std::move(*hdr);
    } else if ((bytes.size() >= 8 && std::equal(kPng, kPng + 8, bytes.begin())) ||
               isJpegBytes(bytes)) {
        auto image = decodeImageBytes(bytes, what);
        if (!image) return image.status();
        map.width = image->width, map.height = image->height;
        map.texels.resize(std::size_t(map.width) * std::size_t(map.height));
        for (std::size_t k = 0; k < map.texels.size(); ++k) {
            const std::uint8_t* p = image->rgba.data() + 4 * k;
            map.texels[k] = glm::vec3(srgbToLinear(p[0]), srgbToLinear(p[1]), srgbToLinear(p[2]));
        }
    } else {
        return inputError(fmt::format(
            "{}: not a Radiance (.hdr), OpenEXR, PNG or JPEG image", what));
    }
    if (map.texels.size() > kMaxEnvironmentTexels) {
        return inputError(fmt::format("{}: {}x{} texels: out of range (at most {} texels)", what,
                                      map.width, map.height, kMaxEnvironmentTexels));
    }
    map.contentHash = hash;
    for (std::size_t k = 0; k < map.texels.size(); ++k) {
        const glm::vec3 c = map.texels[k];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
            return inputError(fmt::format("{}: texel ({}, {}) is not finite", what,
                                          k % std::size_t(map.width), k / std::size_t(map.width)));
        }
        // Light is never negative; kMaxRadiance keeps every sum of the build finite.
        map.texels[k] = glm::clamp(c, glm::vec3(0.0f), glm::vec3(kMaxRadiance));
    }
    const int w = map.width, h = map.height;
    if (w == 2 * h) {
        map.name = path;
        return map;
    }
    if (!(w * 3 == h * 4 && w % 4 == 0)) {
        return usageError(fmt::format(
            "{}: {}x{} is neither an equirectangular map (width = 2 x height) nor a horizontal "
            "cube cross (4:3)",
            what, w, h));
    }
    // A cube cross, resampled to an equirectangular map of 4s × 2s (bilinear in each face,
    // clamped at its edges, as the sky reads it).
    const int s = w / 4;
    RadianceMap eq;
    eq.width = 4 * s, eq.height = 2 * s, eq.name = path, eq.contentHash = hash;
    eq.texels.resize(std::size_t(eq.width) * std::size_t(eq.height));
    auto at = [&](int x, int y) { return map.texels[std::size_t(y) * std::size_t(w) + std::size_t(x)]; };
    for (int j = 0; j < eq.height; ++j) {
        for (int i = 0; i < eq.width; ++i) {
            const CubeCrossPoint c = cubeCrossPoint(equirectDirection(
                (float(i) + 0.5f) / float(eq.width), (float(j) + 0.5f) / float(eq.height)));
            const float x = (c.u + 1.0f) * 0.5f * float(s) - 0.5f;
            const float y = (c.v + 1.0f) * 0.5f * float(s) - 0.5f;
            const float fx = std::floor(x), fy = std::floor(y);
            const int x0 = std::clamp(int(fx), 0, s - 1), x1 = std::clamp(int(fx) + 1, 0, s - 1);
            const int y0 = std::clamp(int(fy), 0, s - 1), y1 = std::clamp(int(fy) + 1, 0, s - 1);
            const float ax = x - fx, ay = y - fy;
            const int ox = c.col * s, oy = c.row * s;
            const glm::vec3 top = at(ox + x0, oy + y0) * (1.0f - ax) + at(ox + x1, oy + y0) * ax;
            const glm::vec3 bot = at(ox + x0, oy + y1) * (1.0f - ax) + at(ox + x1, oy + y1) * ax;
            eq.texels[std::size_t(j) * std::size_t(eq.width) + std::size_t(i)] =
                top * (1.0f - ay) + bot * ay;
        }
    }
    return eq;
}

}  // namespace mvr
