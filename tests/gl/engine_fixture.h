// tests/gl/engine_fixture.h — a .glb shaped like Khronos's 2CylinderEngine sample, written by
// the test: one node tree of `parts` nodes under a root, each instancing a mesh of its own (one
// primitive, a box of another size, UNSIGNED_SHORT indices as that file has) with a material of
// its own (baseColorFactor only, no textures). More meshes than the gl backend keeps on the GPU
// between renders: the sample failed on every gl method with GL_INVALID_OPERATION.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace mvr::gl::test {

inline std::filesystem::path writeEngineGlb(const std::filesystem::path& path, int parts = 40) {
    std::string bin, meshes, materials, nodes, accessors, views, children;
    auto pad = [](std::string& s, char c) {
        while (s.size() % 4) s.push_back(c);
    };
    auto addView = [&](const void* data, std::size_t bytes, int target) {
        const std::size_t offset = bin.size();
        bin.append(static_cast<const char*>(data), bytes);
        pad(bin, '\0');
        views += fmt::format("{}{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{},\"target\":{}}}",
                             views.empty() ? "" : ",", offset, bytes, target);
    };
    int viewCount = 0, accessorCount = 0;
    for (int i = 0; i < parts; ++i) {
        // A box of half-extents (a, b, c): 4 vertices a face with the face's normal.
        const float a = 0.3f + 0.02f * i, b = 0.2f + 0.01f * (i % 7), c = 0.25f;
        std::vector<float> pos, nrm;
        std::vector<std::uint16_t> idx;
        const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (int f = 0; f < 6; ++f) {
            // Two axes spanning the face, u × v = n (counter-clockwise seen from outside).
            const int ax = f / 2;
            const int ua = (ax + 1) % 3, va = (ax + 2) % 3;
            const float s = n[f][ax];
            const float ext[3] = {a, b, c};
            const auto base = static_cast<std::uint16_t>(pos.size() / 3);
            const float us[4] = {-1, 1, 1, -1}, vs[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; ++k) {
                float p[3];
                p[ax] = s * ext[ax];
                p[ua] = us[k] * ext[ua] * s;
                p[va] = vs[k] * ext[va];
                pos.insert(pos.end(), p, p + 3);
                nrm.insert(nrm.end(), n[f], n[f] + 3);
            }
            for (int k : {0, 1, 2, 0, 2, 3}) idx.push_back(static_cast<std::uint16_t>(base + k));
        }
        addView(pos.data(), pos.size() * 4, 34962);
        addView(nrm.data(), nrm.size() * 4, 34962);
        addView(idx.data(), idx.size() * 2, 34963);
        const int verts = static_cast<int>(pos.size() / 3);
        accessors += fmt::format(
            "{}{{\"bufferView\":{},\"componentType\":5126,\"count\":{},\"type\":\"VEC3\","
            "\"min\":[{},{},{}],\"max\":[{},{},{}]}},"
            "{{\"bufferView\":{},\"componentType\":5126,\"count\":{},\"type\":\"VEC3\"}},"
            "{{\"bufferView\":{},\"componentType\":5123,\"count\":{},\"type\":\"SCALAR\"}}",
            accessors.empty() ? "" : ",", viewCount, verts, -a, -b, -c, a, b, c, viewCount + 1,
            verts, viewCount + 2, idx.size());
        meshes += fmt::format(
            "{}{{\"name\":\"part{}\",\"primitives\":[{{\"attributes\":{{\"POSITION\":{},"
            "\"NORMAL\":{}}},\"indices\":{},\"material\":{}}}]}}",
            meshes.empty() ? "" : ",", i, accessorCount, accessorCount + 1, accessorCount + 2, i);
        materials += fmt::format(
            "{}{{\"name\":\"mat{}\",\"pbrMetallicRoughness\":{{\"baseColorFactor\":[{},{},{},1],"
            "\"metallicFactor\":0.5}}}}",
            materials.empty() ? "" : ",", i, 0.2 + 0.6 * (i % 5) / 4.0, 0.2 + 0.6 * (i % 7) / 6.0,
            0.2 + 0.6 * (i % 3) / 2.0);
        const int col = i % 8, row = i / 8;
        nodes += fmt::format(
            ",{{\"name\":\"node{}\",\"mesh\":{},\"translation\":[{},{},{}],"
            "\"rotation\":[0,{},0,{}]}}",
            i, i, 1.1 * (col - 3.5), 0.9 * (row - 2.0), -0.4 * (i % 3), std::sin(0.2 * i),
            std::cos(0.2 * i));
        children += fmt::format("{}{}", children.empty() ? "" : ",", i + 1);
        viewCount += 3;
        accessorCount += 3;
    }
    std::string json = fmt::format(
        "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"mvr engine fixture\"}},\"scene\":0,"
        "\"scenes\":[{{\"nodes\":[0]}}],\"nodes\":[{{\"name\":\"root\",\"children\":[{}],"
        "\"scale\":[1,1,1]}}{}],\"meshes\":[{}],\"materials\":[{}],\"accessors\":[{}],"
        "\"bufferViews\":[{}],\"buffers\":[{{\"byteLength\":{}}}]}}",
        children, nodes, meshes, materials, accessors, views, bin.size());
    pad(json, ' ');
    std::string glb;
    auto u32 = [&](std::uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67);  // "glTF"
    u32(2);
    u32(static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);  // "JSON"
    glb += json;
    u32(static_cast<std::uint32_t>(bin.size()));
    u32(0x004E4942);  // "BIN"
    glb += bin;
    std::ofstream(path, std::ios::binary)
        .write(glb.data(), static_cast<std::streamsize>(glb.size()));
    return path;
}

}  // namespace mvr::gl::test
