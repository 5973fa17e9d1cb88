// tests/core/gltf_maps_fixture.h — a glTF 2.0 file with every texture map (issue 39), laid out as
// Blender's exporter writes one, and the variants real files show: one image as colour and as
// data, a map under another KHR_texture_transform, set 1 only, a missing emission texture,
// TEXCOORD_1 naming TEXCOORD_0's accessor (three.js) or not. For the scene loader's tests and
// the CLI's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "test_files.h"

namespace mvr::test {

/// The "Full" mesh's TANGENT, vertex by vertex.
inline constexpr float kMapsTangents[4][4] = {
    {0, 1, 0, -1}, {0.6f, 0.8f, 0, -1}, {0.8f, 0.6f, 0, -1}, {1, 0, 0, -1}};

/// A quad with TEXCOORD_0 and TEXCOORD_1, as Blender's exporter writes a material with every
/// map (one image file per map, the metallic-roughness map packed, the occlusion map with its
/// strength, the emission texture under emissiveFactor [1, 1, 1]); the same image as base colour
/// and occlusion in "Shared"; "Moved" has an occlusion map under another KHR_texture_transform
/// than its base colour; "Second" reads set 1 only, from its metallic-roughness map on;
/// "Lost" names an emission texture whose file is not there; "Alike" has its occlusion map on
/// TEXCOORD_1 where its mesh names TEXCOORD_0's accessor twice (as three.js's exporter writes
/// the DamagedHelmet) and a normal map (scale 0.5) on a mesh without TANGENT, "Apart" the
/// occlusion map on a mesh whose two sets differ. The "Full" mesh has TANGENT: in-plane
/// directions of handedness −1 (kMapsTangents).
inline std::filesystem::path writeMapsGltf(const std::filesystem::path& dir) {
    std::string bin;
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const float uv0[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    const float uv1[8] = {0, 0.5f, 0.5f, 0.5f, 0.5f, 0, 0, 0};
    const std::uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    // Not all alike: assimp's aiProcess_FindInvalidData drops a stream whose values are.
    const auto& tangent = kMapsTangents;
    const float normal[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    bin.append(reinterpret_cast<const char*>(pos), sizeof pos);
    bin.append(reinterpret_cast<const char*>(uv0), sizeof uv0);
    bin.append(reinterpret_cast<const char*>(uv1), sizeof uv1);
    bin.append(reinterpret_cast<const char*>(idx), sizeof idx);
    bin.append(reinterpret_cast<const char*>(tangent), sizeof tangent);
    bin.append(reinterpret_cast<const char*>(normal), sizeof normal);
    const std::string json = fmt::format(
        R"({{"asset":{{"version":"2.0","generator":"Khronos glTF Blender I/O v3.6.27"}},
"extensionsUsed":["KHR_texture_transform"],
"scene":0,"scenes":[{{"name":"Scene","nodes":[0,1,2,3,4,5,6]}}],
"nodes":[{{"mesh":0,"name":"Full"}},{{"mesh":1,"name":"Shared"}},{{"mesh":2,"name":"Moved"}},
 {{"mesh":3,"name":"Second"}},{{"mesh":4,"name":"Lost"}},{{"mesh":5,"name":"Alike"}},{{"mesh":6,"name":"Apart"}}],
"materials":[
 {{"name":"Full","emissiveFactor":[1,1,1],"emissiveTexture":{{"index":3}},
   "normalTexture":{{"index":4}},"occlusionTexture":{{"index":2,"strength":0.6}},
   "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"metallicRoughnessTexture":{{"index":1}}}}}},
 {{"name":"Shared","occlusionTexture":{{"index":0}},
   "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"metallicFactor":0}}}},
 {{"name":"Moved","occlusionTexture":{{"index":2,"extensions":{{"KHR_texture_transform":{{"scale":[2,2]}}}}}},
   "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"metallicFactor":0}}}},
 {{"name":"Second","pbrMetallicRoughness":{{"metallicRoughnessTexture":{{"index":1,"texCoord":1}}}},
   "emissiveFactor":[0.5,0.5,0.5],"emissiveTexture":{{"index":3,"texCoord":1}}}},
 {{"name":"Lost","emissiveFactor":[1,1,1],"emissiveTexture":{{"index":5}},
   "pbrMetallicRoughness":{{"metallicFactor":0}}}},
 {{"name":"Alike","occlusionTexture":{{"index":2,"texCoord":1}},"normalTexture":{{"index":4,"scale":0.5}},
   "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}},
 {{"name":"Apart","occlusionTexture":{{"index":2,"texCoord":1}},
   "pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
"textures":[{{"source":0}},{{"source":1}},{{"source":2}},{{"source":3}},{{"source":4}},{{"source":5}}],
"images":[{{"uri":"base.png"}},{{"uri":"mr.png"}},{{"uri":"occ.png"}},{{"uri":"emit.png"}},
 {{"uri":"normal.png"}},{{"uri":"gone.png"}}],
"meshes":[{}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
 {{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
 {{"bufferView":2,"componentType":5126,"count":4,"type":"VEC2"}},
 {{"bufferView":3,"componentType":5123,"count":6,"type":"SCALAR"}},
 {{"bufferView":4,"componentType":5126,"count":4,"type":"VEC4"}},
 {{"bufferView":5,"componentType":5126,"count":4,"type":"VEC3"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":32}},
 {{"buffer":0,"byteOffset":80,"byteLength":32}},{{"buffer":0,"byteOffset":112,"byteLength":12}},
 {{"buffer":0,"byteOffset":124,"byteLength":64}},{{"buffer":0,"byteOffset":188,"byteLength":48}}],
"buffers":[{{"byteLength":236,"uri":"data:application/octet-stream;base64,{}"}}]}})",
        [] {
            std::string meshes;
            for (int m = 0; m < 7; ++m) {
                meshes += fmt::format(
                    R"({}{{"name":"M{}","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":5,"TEXCOORD_0":1,"TEXCOORD_1":{}{}}},"indices":3,"material":{}}}]}})",
                    m ? "," : "", m, m == 5 ? 1 : 2, m == 0 ? R"(,"TANGENT":4)" : "", m);
            }
            return meshes;
        }(),
        base64(bin));
    EXPECT_TRUE(writePng(dir / "base.png", Image(4, 4, Rgba8{200, 150, 100, 255})));
    EXPECT_TRUE(writePng(dir / "mr.png", Image(4, 4, Rgba8{0, 128, 255, 255})));
    EXPECT_TRUE(writePng(dir / "occ.png", Image(4, 4, Rgba8{90, 90, 90, 255})));
    EXPECT_TRUE(writePng(dir / "emit.png", Image(4, 4, Rgba8{255, 60, 0, 255})));
    EXPECT_TRUE(writePng(dir / "normal.png", Image(4, 4, Rgba8{128, 128, 255, 255})));
    const auto path = dir / "maps.gltf";
    std::ofstream(path) << json;
    return path;
}

}  // namespace mvr::test
