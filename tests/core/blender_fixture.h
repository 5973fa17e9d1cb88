// tests/core/blender_fixture.h — a small glTF in the layout Blender's exporter (Khronos glTF
// Blender I/O) writes, and its hand-written equivalent, for the loader's tests (issue 14).
//
// What the exporter writes, from its sources (github.com/KhronosGroup/glTF-Blender-IO,
// addons/io_scene_gltf2/):
// - blender/exp/lights.py, __gather_intensity(): with the default Lighting Mode "Standard"
//   (SPEC, __init__.py), a sun's strength S (W/m²) becomes S × PBR_WATTS_TO_LUMENS lux; a point
//   or spot lamp's power P (W) becomes P / (4π) × PBR_WATTS_TO_LUMENS candela;
//   PBR_WATTS_TO_LUMENS = 683 (blender/com/conversion.py). __gather_range(): `range` is the
//   lamp's custom cutoff distance, written only when set.
// - blender/exp/light_spots.py: outerConeAngle = spot_size / 2, innerConeAngle = outer − outer ×
//   spot_blend.
// - blender/com/conversion.py, yvof_blender_to_gltf(): yfov = 2 atan(tan(angle / 2) / aspect)
//   for a landscape frame with sensor fit AUTO; the camera's node carries the rotation (the
//   axis correction baked into its quaternion), as do the lights' nodes.
// - nodes as translation / rotation (x, y, z, w) / scale, parents listing "children"; samplers
//   {"magFilter": 9729, "minFilter": 9987} without wrap modes (REPEAT); images as external
//   files with "mimeType"; the buffer as an external .bin; "extras" from custom properties;
//   KHR_materials_specular and KHR_materials_ior on a Principled BSDF's material
//   (blender/exp/material/extensions/specular.py, ior.py) — which mvr does not use.
// The numbers are made small (lamps of a few hundredths of a watt) so that the lights, read
// in the extension's units, light the scene without saturating it.
#pragma once

#include <numbers>
#include <string>

#include <fmt/core.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gltf_fixture.h"
#include "mvr/io/png.h"

namespace mvr::test {

enum class BlenderLayout { Exporter, HandWritten };

/// The Blender scene's values and what the exporter turns them into, computed here.
struct BlenderTruth {
    static constexpr float kWattsToLumens = 683.0f;  // PBR_WATTS_TO_LUMENS
    static constexpr float kPi = std::numbers::pi_v<float>;
    static constexpr float kSunStrength = 0.003f;  // W/m²
    static constexpr float kPointWatts = 0.06f, kSpotWatts = 0.1f;
    static constexpr float kPointRange = 6.0f;  // the lamp's custom distance
    static constexpr float kSpotSize = 60.0f * kPi / 180.0f, kSpotBlend = 0.25f;
    static constexpr float kLensAngle = 0.69111489f;  // 2 atan(18 / 50): 50 mm lens, 36 mm sensor
    static constexpr float kAspect = 16.0f / 9.0f;

    static float sunLux() { return kSunStrength * kWattsToLumens; }
    static float candela(float watts) { return watts / (4.0f * kPi) * kWattsToLumens; }
    static float outerCone() { return kSpotSize * 0.5f; }
    static float innerCone() { return outerCone() - outerCone() * kSpotBlend; }
    static float yfov() { return 2.0f * std::atan(std::tan(kLensAngle * 0.5f) / kAspect); }

    struct Trs {
        glm::vec3 t{0.0f};
        glm::quat r{1, 0, 0, 0};
        glm::vec3 s{1.0f};
        glm::mat4 matrix() const {
            return glm::translate(glm::mat4(1), t) * glm::mat4_cast(r) *
                   glm::scale(glm::mat4(1), s);
        }
    };
    static glm::quat about(float degrees, glm::vec3 axis) {
        return glm::angleAxis(glm::radians(degrees), axis);
    }
    static Trs parent() { return {{0, 0, -1}, about(30, {0, 1, 0}), glm::vec3(1)}; }
    static Trs childA() { return {{-1.2f, 0, 0}, glm::quat(1, 0, 0, 0), glm::vec3(1)}; }
    static Trs childB() { return {{1.2f, 0.3f, 0}, about(20, {0, 0, 1}), glm::vec3(0.6f)}; }
    static Trs camera() { return {{0, 1.5f, 7}, about(-12, {1, 0, 0}), glm::vec3(1)}; }
    static Trs sun() {
        return {{0, 4, 0}, about(20, {0, 1, 0}) * about(-50, {1, 0, 0}), glm::vec3(1)};
    }
    static Trs point() { return {{0.5f, 2, 1}, glm::quat(1, 0, 0, 0), glm::vec3(1)}; }
    static Trs spot() { return {{-1, 2.5f, 2}, about(-60, {1, 0, 0}), glm::vec3(1)}; }
};

namespace detail_fixture {

inline std::string trsJson(const BlenderTruth::Trs& n, BlenderLayout layout) {
    if (layout == BlenderLayout::HandWritten) {
        const glm::mat4 m = n.matrix();
        std::string out = "\"matrix\":[";
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) out += fmt::format("{}{:.9g}", c || r ? "," : "", m[c][r]);
        return out + "]";
    }
    std::string out;
    auto add = [&](const std::string& s) { out += (out.empty() ? "" : ",") + s; };
    if (n.t != glm::vec3(0))
        add(fmt::format("\"translation\":[{:.9g},{:.9g},{:.9g}]", n.t.x, n.t.y, n.t.z));
    if (n.r != glm::quat(1, 0, 0, 0))
        add(fmt::format("\"rotation\":[{:.9g},{:.9g},{:.9g},{:.9g}]", n.r.x, n.r.y, n.r.z, n.r.w));
    if (n.s != glm::vec3(1))
        add(fmt::format("\"scale\":[{:.9g},{:.9g},{:.9g}]", n.s.x, n.s.y, n.s.z));
    return out;
}

}  // namespace detail_fixture

/// Writes the scene as Blender's exporter lays it out (NAME.gltf + NAME.bin + checker.png) or
/// by hand (NAME.gltf alone: node matrices, data URIs, no extras, no material extensions, the
/// sampler's wrap modes spelled out); returns the .gltf's path. One textured cube mesh
/// instanced by two children of a rotated parent, a rotated camera, a sun, a point lamp with
/// a cutoff distance and a spot lamp.
inline std::filesystem::path writeBlenderGltf(const std::filesystem::path& dir,
                                              const std::string& name, BlenderLayout layout) {
    using T = BlenderTruth;
    const bool blender = layout == BlenderLayout::Exporter;
    std::string bin;
    std::size_t p0, n0, u0, i0;
    detail_fixture::box(bin, glm::vec3(0), 0.5f, p0, n0, u0, i0);
    const std::filesystem::path pngPath = dir / (blender ? "checker.png" : name + "-image.png");
    (void)writePng(pngPath, fixtureTexture());
    const std::string png = readBytes(pngPath);
    if (!blender) std::filesystem::remove(pngPath);
    const std::string views =
        fmt::format(R"({{"buffer":0,"byteLength":288,"byteOffset":{},"target":34962}},)"
                    R"({{"buffer":0,"byteLength":288,"byteOffset":{},"target":34962}},)"
                    R"({{"buffer":0,"byteLength":192,"byteOffset":{},"target":34962}},)"
                    R"({{"buffer":0,"byteLength":72,"byteOffset":{},"target":34963}})",
                    p0, n0, u0, i0);
    const std::string accessors =
        R"({"bufferView":0,"componentType":5126,"count":24,"max":[0.5,0.5,0.5],)"
        R"("min":[-0.5,-0.5,-0.5],"type":"VEC3"},)"
        R"({"bufferView":1,"componentType":5126,"count":24,"type":"VEC3"},)"
        R"({"bufferView":2,"componentType":5126,"count":24,"type":"VEC2"},)"
        R"({"bufferView":3,"componentType":5123,"count":36,"type":"SCALAR"})";
    std::string buffer, image;
    if (blender) {
        buffer = fmt::format(R"({{"byteLength":{},"uri":"{}.bin"}})", bin.size(), name);
        std::ofstream(dir / (name + ".bin"), std::ios::binary) << bin;
        image = R"({"mimeType":"image/png","name":"checker","uri":"checker.png"})";
    } else {
        buffer =
            fmt::format(R"({{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}})",
                        bin.size(), base64(bin));
        image = fmt::format(R"({{"uri":"data:image/png;base64,{}"}})", base64(png));
    }
    auto node = [&](const char* nodeName, const T::Trs& trs, const std::string& more,
                    const char* extras) {
        std::string fields = fmt::format("\"name\":\"{}\"", nodeName);
        const std::string t = detail_fixture::trsJson(trs, layout);
        if (!t.empty()) fields += "," + t;
        if (!more.empty()) fields += "," + more;
        if (blender && extras) fields += fmt::format(",\"extras\":{}", extras);
        return "{" + fields + "}";
    };
    auto lightRef = [](int i) {
        return fmt::format("\"extensions\":{{\"KHR_lights_punctual\":{{\"light\":{}}}}}", i);
    };
    const std::string nodes =
        node("Parent", T::parent(), "\"children\":[1,2]", R"({"prop":"parent","weight":2})") + "," +
        node("CubeA", T::childA(), "\"mesh\":0", nullptr) + "," +
        node("CubeB", T::childB(), "\"mesh\":0", R"({"tag":[1,2,3]})") + "," +
        node("Camera", T::camera(), "\"camera\":0", nullptr) + "," +
        node("Sun", T::sun(), lightRef(0), nullptr) + "," +
        node("Point", T::point(), lightRef(1), nullptr) + "," +
        node("Spot", T::spot(), lightRef(2), nullptr);
    const std::string lights = fmt::format(
        R"({{"color":[1,0.95,0.9],"intensity":{:.9g},"name":"Sun","type":"directional"}},)"
        R"({{"color":[1,1,1],"intensity":{:.9g},"name":"Point","range":{:.9g},"type":"point"}},)"
        R"({{"color":[0.9,0.9,1],"intensity":{:.9g},"name":"Spot","spot":)"
        R"({{"innerConeAngle":{:.9g},"outerConeAngle":{:.9g}}},"type":"spot"}})",
        T::sunLux(), T::candela(T::kPointWatts), T::kPointRange, T::candela(T::kSpotWatts),
        T::innerCone(), T::outerCone());
    const std::string material =
        blender ? R"({"doubleSided":true,"extensions":{"KHR_materials_specular":)"
                  R"({"specularColorFactor":[1,1,1],"specularFactor":0.5},)"
                  R"("KHR_materials_ior":{"ior":1.45}},"name":"Checker",)"
                  R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0},)"
                  R"("metallicFactor":0,"roughnessFactor":0.5}})"
                : R"({"doubleSided":true,"name":"Checker",)"
                  R"("pbrMetallicRoughness":{"baseColorTexture":{"index":0},)"
                  R"("metallicFactor":0,"roughnessFactor":0.5}})";
    const std::string sampler = blender ? R"({"magFilter":9729,"minFilter":9987})"
                                        : R"({"magFilter":9729,"minFilter":9987,"wrapS":10497,)"
                                          R"("wrapT":10497})";
    const std::string json = fmt::format(
        R"({{"asset":{{{}"version":"2.0"}},)"
        R"("extensionsUsed":["KHR_lights_punctual"{}],)"
        R"("extensions":{{"KHR_lights_punctual":{{"lights":[{}]}}}},)"
        R"("scene":0,"scenes":[{{"name":"Scene","nodes":[0,3,4,5,6]{}}}],)"
        R"("nodes":[{}],)"
        R"("cameras":[{{"name":"Camera","perspective":{{"aspectRatio":{:.9g},"yfov":{:.9g},)"
        R"("zfar":100,"znear":0.100000001}},"type":"perspective"}}],)"
        R"("materials":[{}],)"
        R"("meshes":[{{"name":"Cube","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,)"
        R"("TEXCOORD_0":2}},"indices":3,"material":0}}]}}],)"
        R"("textures":[{{"sampler":0,"source":0}}],"images":[{}],)"
        R"("accessors":[{}],"bufferViews":[{}],"samplers":[{}],"buffers":[{}]}})",
        blender ? R"("generator":"Khronos glTF Blender I/O v4.1.63",)" : "",
        blender ? R"(,"KHR_materials_specular","KHR_materials_ior")" : "", lights,
        blender ? R"(,"extras":{"render_engine":"BLENDER_EEVEE"})" : "", nodes, T::kAspect,
        T::yfov(), material, image, accessors, views, sampler, buffer);
    const auto path = dir / (name + ".gltf");
    std::ofstream(path, std::ios::binary) << json;
    return path;
}

}  // namespace mvr::test
