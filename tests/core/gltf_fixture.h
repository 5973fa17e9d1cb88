// tests/core/gltf_fixture.h — a small glTF 2.0 scene in the layout Blender's exporter writes,
// for the scene loader's tests (and the fuzzers' seeds): a parent node with TRS and two
// children that instance one mesh of two primitives (a textured cube and a small red cube
// above it), a camera node, a KHR_lights_punctual sun and a point light; a material with a
// baseColorTexture and a sampler. Written as .gltf + external .bin + PNG, as .gltf with data
// URIs, or as .glb (buffer and image in the BIN chunk).
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "mvr/core/image.h"
#include "mvr/io/png.h"
#include "test_files.h"

namespace mvr::test {

enum class GltfLayout { External, DataUri, Glb };

/// The fixture's node transforms, as the test computes them independently of any loader.
struct GltfFixtureTruth {
    static glm::mat4 parent() {
        const glm::quat q = glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 1, 0));
        return glm::translate(glm::mat4(1), glm::vec3(0, 0, -1)) * glm::mat4_cast(q);
    }
    static glm::mat4 childA() { return glm::translate(glm::mat4(1), glm::vec3(-1.5f, 0, 0)); }
    static glm::mat4 childB() {
        return glm::translate(glm::mat4(1), glm::vec3(1.5f, 0, 0)) *
               glm::scale(glm::mat4(1), glm::vec3(0.5f));
    }
    static glm::vec3 cameraPosition() { return {0.0f, 0.5f, 8.0f}; }
    static constexpr float kYfov = 0.6f, kAspect = 1.5f, kZnear = 0.1f, kZfar = 100.0f;
};

/// The 4x4 texture: row 0 (top) red, green, blue, white; the other rows yellow.
inline Image fixtureTexture() {
    Image img(4, 4, Rgba8{255, 255, 0, 255});
    img.set(0, 0, {255, 0, 0, 255});
    img.set(1, 0, {0, 255, 0, 255});
    img.set(2, 0, {0, 0, 255, 255});
    img.set(3, 0, {255, 255, 255, 255});
    return img;
}

inline std::string readBytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

namespace detail_fixture {

inline void appendFloats(std::string& bin, const std::vector<float>& v) {
    bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
}

/// A box [c - h, c + h] with 24 vertices (4 per face: outward normals, uv per face).
inline void box(std::string& bin, glm::vec3 c, float h, std::size_t& posOff, std::size_t& nrmOff,
                std::size_t& uvOff, std::size_t& idxOff) {
    std::vector<float> pos, nrm, uv;
    std::vector<std::uint16_t> idx;
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        for (int s = -1; s <= 1; s += 2) {
            const glm::vec3 n = axes[a] * float(s);
            const glm::vec3 u = axes[(a + 1) % 3], w = axes[(a + 2) % 3];
            // Counter-clockwise seen from outside: (u, w) ordered so u x w points along n.
            const glm::vec3 uu = s > 0 ? u : w, ww = s > 0 ? w : u;
            const auto base = std::uint16_t(pos.size() / 3);
            const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (const glm::vec2& k : corners) {
                const glm::vec3 p = c + h * (n + k.x * uu + k.y * ww);
                pos.insert(pos.end(), {p.x, p.y, p.z});
                nrm.insert(nrm.end(), {n.x, n.y, n.z});
                uv.insert(uv.end(), {(k.x + 1) * 0.5f, (1 - k.y) * 0.5f});
            }
            idx.insert(idx.end(), {base, std::uint16_t(base + 1), std::uint16_t(base + 2), base,
                                   std::uint16_t(base + 2), std::uint16_t(base + 3)});
        }
    }
    posOff = bin.size();
    appendFloats(bin, pos);
    nrmOff = bin.size();
    appendFloats(bin, nrm);
    uvOff = bin.size();
    appendFloats(bin, uv);
    idxOff = bin.size();
    bin.append(reinterpret_cast<const char*>(idx.data()), idx.size() * 2);
    while (bin.size() % 4) bin.push_back('\0');
}

}  // namespace detail_fixture

/// Writes the fixture into `dir` as NAME.gltf (+ NAME.bin + NAME.png) or NAME.glb; returns the
/// model's path. `png` replaces the texture file's bytes (for bad-texture tests).
inline std::filesystem::path writeGltfFixture(const std::filesystem::path& dir,
                                              const std::string& name, GltfLayout layout,
                                              const std::string* png = nullptr) {
    std::string bin;
    std::size_t p0, n0, u0, i0, p1, n1, u1, i1;
    detail_fixture::box(bin, glm::vec3(0), 0.5f, p0, n0, u0, i0);
    detail_fixture::box(bin, glm::vec3(0, 1, 0), 0.25f, p1, n1, u1, i1);
    const std::filesystem::path pngPath = dir / (name + ".png");
    std::string pngBytes;
    if (png) {
        pngBytes = *png;
    } else {
        (void)writePng(pngPath, fixtureTexture());
        pngBytes = readBytes(pngPath);
        std::filesystem::remove(pngPath);
    }
    const std::size_t imageOff = bin.size();
    if (layout == GltfLayout::Glb) {
        bin += pngBytes;
        while (bin.size() % 4) bin.push_back('\0');
    }
    const std::size_t vbytes = 24 * 12, tbytes = 24 * 8, ibytes = 36 * 2;
    std::string views, accessors;
    int nv = 0;
    auto view = [&](std::size_t off, std::size_t len, int target) {
        views +=
            fmt::format("{}{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}{}}}", nv ? "," : "",
                        off, len, target ? fmt::format(",\"target\":{}", target) : "");
        return nv++;
    };
    int na = 0;
    auto accessor = [&](int v, int comp, int count, const char* type, const std::string& extra) {
        accessors += fmt::format(
            "{}{{\"bufferView\":{},\"componentType\":{},\"count\":{},\"type\":\"{}\"{}}}",
            na ? "," : "", v, comp, count, type, extra);
        return na++;
    };
    auto prim = [&](std::size_t p, std::size_t n, std::size_t u, std::size_t i, glm::vec3 lo,
                    glm::vec3 hi, int material) {
        const int ap = accessor(view(p, vbytes, 34962), 5126, 24, "VEC3",
                                fmt::format(",\"min\":[{},{},{}],\"max\":[{},{},{}]", lo.x, lo.y,
                                            lo.z, hi.x, hi.y, hi.z));
        const int an = accessor(view(n, vbytes, 34962), 5126, 24, "VEC3", "");
        const int au = accessor(view(u, tbytes, 34962), 5126, 24, "VEC2", "");
        const int ai = accessor(view(i, ibytes, 34963), 5123, 36, "SCALAR", "");
        return fmt::format(
            "{{\"attributes\":{{\"POSITION\":{},\"NORMAL\":{},\"TEXCOORD_0\":{}}},"
            "\"indices\":{},\"material\":{}}}",
            ap, an, au, ai, material);
    };
    const std::string prim0 = prim(p0, n0, u0, i0, glm::vec3(-0.5f), glm::vec3(0.5f), 0);
    const std::string prim1 =
        prim(p1, n1, u1, i1, glm::vec3(-0.25f, 0.75f, -0.25f), glm::vec3(0.25f, 1.25f, 0.25f), 1);
    std::string image;
    if (layout == GltfLayout::Glb) {
        const int iv = view(imageOff, pngBytes.size(), 0);
        image = fmt::format("{{\"bufferView\":{},\"mimeType\":\"image/png\",\"name\":\"checker\"}}",
                            iv);
    } else if (layout == GltfLayout::DataUri) {
        image = fmt::format("{{\"uri\":\"data:image/png;base64,{}\"}}", base64(pngBytes));
    } else {
        image = fmt::format("{{\"uri\":\"{}.png\"}}", name);
        std::ofstream(pngPath, std::ios::binary) << pngBytes;
    }
    std::string buffer;
    if (layout == GltfLayout::Glb) {
        buffer = fmt::format("{{\"byteLength\":{}}}", bin.size());
    } else if (layout == GltfLayout::DataUri) {
        buffer =
            fmt::format("{{\"byteLength\":{},\"uri\":\"data:application/octet-stream;base64,{}\"}}",
                        bin.size(), base64(bin));
    } else {
        buffer = fmt::format("{{\"byteLength\":{},\"uri\":\"{}.bin\"}}", bin.size(), name);
        std::ofstream(dir / (name + ".bin"), std::ios::binary) << bin;
    }
    const glm::quat q = glm::angleAxis(glm::radians(30.0f), glm::vec3(0, 1, 0));
    // The sun points down and toward -Z: rotation of -60 degrees about X.
    const glm::quat sun = glm::angleAxis(glm::radians(-60.0f), glm::vec3(1, 0, 0));
    const std::string json = fmt::format(
        R"({{"asset":{{"generator":"Khronos glTF Blender I/O v3.6.27","version":"2.0"}},)"
        R"("extensionsUsed":["KHR_lights_punctual"],)"
        R"("extensions":{{"KHR_lights_punctual":{{"lights":[)"
        R"({{"color":[1,0.9,0.8],"intensity":2,"type":"directional","name":"Sun"}},)"
        R"({{"color":[0.5,0.5,1],"intensity":3,"type":"point","range":20,"name":"Lamp"}}]}}}},)"
        R"("scene":0,"scenes":[{{"name":"Scene","nodes":[0,3,4,5]}}],)"
        R"("nodes":[)"
        R"({{"name":"Parent","children":[1,2],"translation":[0,0,-1],"rotation":[{},{},{},{}]}},)"
        R"({{"name":"A","mesh":0,"translation":[-1.5,0,0]}},)"
        R"({{"name":"B","mesh":0,"translation":[1.5,0,0],"scale":[0.5,0.5,0.5]}},)"
        R"({{"name":"Camera","camera":0,"translation":[0,0.5,8]}},)"
        R"({{"name":"Sun","rotation":[{},{},{},{}],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}},)"
        R"({{"name":"Lamp","translation":[0,3,2],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}}],)"
        R"("cameras":[{{"name":"Camera","type":"perspective","perspective":)"
        R"({{"yfov":0.6,"aspectRatio":1.5,"znear":0.1,"zfar":100}}}}],)"
        R"("meshes":[{{"name":"Boxes","primitives":[{},{}]}}],)"
        R"("materials":[)"
        R"({{"name":"Checker","doubleSided":true,"alphaMode":"MASK","alphaCutoff":0.3,)"
        R"("pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"metallicFactor":0}}}},)"
        R"({{"name":"Red","alphaMode":"BLEND","pbrMetallicRoughness":)"
        R"({{"baseColorFactor":[1,0,0,0.5],"metallicFactor":0}}}}],)"
        R"("textures":[{{"sampler":0,"source":0}}],)"
        R"("samplers":[{{"magFilter":9728,"minFilter":9987,"wrapS":33071,"wrapT":33648}}],)"
        R"("images":[{}],"accessors":[{}],"bufferViews":[{}],"buffers":[{}]}})",
        q.x, q.y, q.z, q.w, sun.x, sun.y, sun.z, sun.w, prim0, prim1, image, accessors, views,
        buffer);
    if (layout != GltfLayout::Glb) {
        const auto path = dir / (name + ".gltf");
        std::ofstream(path, std::ios::binary) << json;
        return path;
    }
    std::string js = json;
    while (js.size() % 4) js.push_back(' ');
    auto u32 = [](std::string& s, std::uint32_t v) {
        for (int k = 0; k < 4; ++k) s.push_back(char((v >> (8 * k)) & 255));
    };
    std::string glb = "glTF";
    u32(glb, 2);
    u32(glb, std::uint32_t(12 + 8 + js.size() + 8 + bin.size()));
    u32(glb, std::uint32_t(js.size()));
    glb += "JSON";
    glb += js;
    u32(glb, std::uint32_t(bin.size()));
    glb.append("BIN\0", 4);
    glb += bin;
    const auto path = dir / (name + ".glb");
    std::ofstream(path, std::ios::binary) << glb;
    return path;
}

}  // namespace mvr::test
