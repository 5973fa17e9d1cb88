// tests/core/texture_transform_fixture.h — a glTF quad for KHR_texture_transform (issue 39
// item 4), in the layout Blender's glTF exporter writes it (extensionsUsed lists
// KHR_texture_transform; the extension object sits in the textureInfo, here baseColorTexture's;
// texCoord on the textureInfo only when not 0): a 3×3-vertex grid over x, y in -1..1 at z = 0.5
// (facing +z), TEXCOORD_0 = ((x + 1) / 2, (1 − y) / 2) so that uv (0, 0) is the top-left corner,
// optionally a TEXCOORD_1 of other values, and a 2×2 texture of four colours sampled NEAREST
// with REPEAT. One .gltf with data URIs. Used by tests/core and tests/raster.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "test_files.h"

namespace mvr::test {

/// The four texels: (0, 0) red, (1, 0) green, (0, 1) blue, (1, 1) white (x right, y down).
inline Image twoByTwoTexture() {
    Image img(2, 2);
    img.set(0, 0, {255, 0, 0, 255});
    img.set(1, 0, {0, 255, 0, 255});
    img.set(0, 1, {0, 0, 255, 255});
    img.set(1, 1, {255, 255, 255, 255});
    return img;
}

/// The grid's vertex k = 3 j + i (i, j in 0..2): position, TEXCOORD_0 and TEXCOORD_1.
struct QuadVertex {
    glm::vec3 position;
    glm::vec2 uv0, uv1;
};
inline std::vector<QuadVertex> transformQuadVertices() {
    std::vector<QuadVertex> out;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            out.push_back({{-1.0f + float(i), 1.0f - float(j), 0.5f},
                           {0.5f * float(i), 0.5f * float(j)},
                           {0.1f + 0.3f * float(i), 0.2f + 0.35f * float(j)}});
    return out;
}

struct TransformQuadOptions {
    /// JSON members added to baseColorTexture after "index":0, e.g.
    /// `,"extensions":{"KHR_texture_transform":{"offset":[0.5,0]}}`.
    std::string baseColorTextureExtra;
    /// JSON members added to the material, e.g. `,"normalTexture":{"index":0,...}`.
    std::string materialExtra;
    bool texcoord1 = true;  ///< the primitive has a TEXCOORD_1
    std::string materialName = "Checker";
};

/// Writes NAME.gltf into `dir` and returns its path.
inline std::filesystem::path writeTransformQuad(const std::filesystem::path& dir,
                                                const std::string& name,
                                                const TransformQuadOptions& o = {}) {
    const std::vector<QuadVertex> verts = transformQuadVertices();
    std::string bin;
    auto floats = [&](const std::vector<float>& v) {
        const std::size_t off = bin.size();
        bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
        return off;
    };
    std::vector<float> pos, nrm, uv0, uv1;
    for (const QuadVertex& v : verts) {
        pos.insert(pos.end(), {v.position.x, v.position.y, v.position.z});
        nrm.insert(nrm.end(), {0.0f, 0.0f, 1.0f});
        uv0.insert(uv0.end(), {v.uv0.x, v.uv0.y});
        uv1.insert(uv1.end(), {v.uv1.x, v.uv1.y});
    }
    const std::size_t pOff = floats(pos), nOff = floats(nrm), u0Off = floats(uv0),
                      u1Off = floats(uv1);
    std::vector<std::uint16_t> idx;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            const auto k = std::uint16_t(3 * j + i);
            // Counter-clockwise seen from +z (y up, j down).
            idx.insert(idx.end(), {k, std::uint16_t(k + 3), std::uint16_t(k + 4), k,
                                   std::uint16_t(k + 4), std::uint16_t(k + 1)});
        }
    }
    const std::size_t iOff = bin.size();
    bin.append(reinterpret_cast<const char*>(idx.data()), idx.size() * 2);
    while (bin.size() % 4) bin.push_back('\0');

    const std::filesystem::path pngPath = dir / (name + "-texture.png");
    (void)writePng(pngPath, twoByTwoTexture());
    std::ifstream in(pngPath, std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(pngPath);

    const std::string attributes = fmt::format(R"("POSITION":0,"NORMAL":1,"TEXCOORD_0":2{})",
                                               o.texcoord1 ? R"(,"TEXCOORD_1":3)" : "");
    const std::string json = fmt::format(
        R"({{"asset":{{"generator":"Khronos glTF Blender I/O v3.6.27","version":"2.0"}},)"
        R"("extensionsUsed":["KHR_texture_transform"],)"
        R"("scene":0,"scenes":[{{"name":"Scene","nodes":[0]}}],)"
        R"("nodes":[{{"mesh":0,"name":"Plane"}}],)"
        R"("materials":[{{"doubleSided":true,"name":"{}",)"
        R"("pbrMetallicRoughness":{{"baseColorTexture":{{"index":0{}}},)"
        R"("metallicFactor":0,"roughnessFactor":0.5}}{}}}],)"
        R"("meshes":[{{"name":"Plane","primitives":[{{"attributes":{{{}}},"indices":4,)"
        R"("material":0}}]}}],)"
        R"("textures":[{{"sampler":0,"source":0}}],)"
        R"("images":[{{"mimeType":"image/png","name":"checker",)"
        R"("uri":"data:image/png;base64,{}"}}],)"
        R"("samplers":[{{"magFilter":9728,"minFilter":9728}}],)"
        R"("accessors":[)"
        R"({{"bufferView":0,"componentType":5126,"count":9,"max":[1,1,0.5],"min":[-1,-1,0.5],)"
        R"("type":"VEC3"}},)"
        R"({{"bufferView":1,"componentType":5126,"count":9,"type":"VEC3"}},)"
        R"({{"bufferView":2,"componentType":5126,"count":9,"type":"VEC2"}},)"
        R"({{"bufferView":3,"componentType":5126,"count":9,"type":"VEC2"}},)"
        R"({{"bufferView":4,"componentType":5123,"count":24,"type":"SCALAR"}}],)"
        R"("bufferViews":[)"
        R"({{"buffer":0,"byteLength":108,"byteOffset":{},"target":34962}},)"
        R"({{"buffer":0,"byteLength":108,"byteOffset":{},"target":34962}},)"
        R"({{"buffer":0,"byteLength":72,"byteOffset":{},"target":34962}},)"
        R"({{"buffer":0,"byteLength":72,"byteOffset":{},"target":34962}},)"
        R"({{"buffer":0,"byteLength":48,"byteOffset":{},"target":34963}}],)"
        R"("buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]}})",
        o.materialName, o.baseColorTextureExtra, o.materialExtra, attributes, base64(png), pOff,
        nOff, u0Off, u1Off, iOff, bin.size(), base64(bin));
    const auto path = dir / (name + ".gltf");
    std::ofstream(path, std::ios::binary) << json;
    return path;
}

}  // namespace mvr::test
