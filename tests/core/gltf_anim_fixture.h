// tests/core/gltf_anim_fixture.h — a small animated glTF 2.0 file for the animation tests:
// "mover" (a red cube, translation LINEAR) with a child "arm" (rotation STEP, no mesh) whose
// child "tip" (a green cube one unit up) swings with it, and "cam" (a camera, translation
// LINEAR) as a second root. Written as .gltf with a data-URI buffer or as .glb. The keys are
// public (GltfAnimTruth) so tests interpolate them by hand, independently of the loader.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "gltf_fixture.h"
#include "test_files.h"

namespace mvr::test {

struct GltfAnimTruth {
    // mover.translation, LINEAR, keys at 0 and 1 s.
    static constexpr float kMoverFrom[3] = {-1.0f, 0.0f, 0.0f}, kMoverTo[3] = {1.0f, 0.0f, 0.0f};
    // arm.rotation, STEP, keys at 0 s (identity) and 0.5 s (90° about +Z).
    static constexpr float kStepTime = 0.5f;
    // tip: rest translation (0, 1, 0) under arm.
    // cam.translation, LINEAR, keys at 0 and 1 s; the camera looks down −Z (no rotation).
    static constexpr float kCamFrom[3] = {0.5f, 0.0f, 8.0f}, kCamTo[3] = {-0.5f, 0.3f, 6.0f};
    static constexpr float kYfov = 0.8f, kCubeHalf = 0.2f;

    static float clamp01(double t) { return float(std::clamp(t, 0.0, 1.0)); }
    static glm::vec3 mix3(const float* a, const float* b, float s) {
        return {a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s, a[2] + (b[2] - a[2]) * s};
    }
    static glm::vec3 mover(double t) { return mix3(kMoverFrom, kMoverTo, clamp01(t)); }
    /// tip's centre: mover + Rz(0° or 90°) · (0, 1, 0), written out by hand.
    static glm::vec3 tip(double t) {
        const glm::vec3 arm = t >= kStepTime ? glm::vec3(-1, 0, 0) : glm::vec3(0, 1, 0);
        return mover(t) + arm;
    }
    static glm::vec3 camera(double t) { return mix3(kCamFrom, kCamTo, clamp01(t)); }
};

/// Writes the file into `dir` as NAME.gltf (data URI) or NAME.glb; returns its path.
inline std::filesystem::path writeAnimatedGltf(const std::filesystem::path& dir,
                                               const std::string& name, bool glb) {
    using T = GltfAnimTruth;
    std::string bin;
    std::size_t p0, n0, u0, i0;
    detail_fixture::box(bin, glm::vec3(0), T::kCubeHalf, p0, n0, u0, i0);
    const float s45 = std::sqrt(0.5f);
    const std::size_t times = bin.size();
    detail_fixture::appendFloats(bin, {0.0f, 1.0f});
    const std::size_t stepTimes = bin.size();
    detail_fixture::appendFloats(bin, {0.0f, T::kStepTime});
    const std::size_t moverKeys = bin.size();
    detail_fixture::appendFloats(bin, {T::kMoverFrom[0], T::kMoverFrom[1], T::kMoverFrom[2],
                                       T::kMoverTo[0], T::kMoverTo[1], T::kMoverTo[2]});
    const std::size_t armKeys = bin.size();
    detail_fixture::appendFloats(bin, {0, 0, 0, 1, 0, 0, s45, s45});
    const std::size_t camKeys = bin.size();
    detail_fixture::appendFloats(bin, {T::kCamFrom[0], T::kCamFrom[1], T::kCamFrom[2], T::kCamTo[0],
                                       T::kCamTo[1], T::kCamTo[2]});
    const std::string views = fmt::format(
        "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":288}},"
        "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":288}},"
        "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":192}},"
        "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":72}},"
        "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{}}}",
        p0, n0, u0, i0, times, bin.size() - times);
    auto at = [&](std::size_t off) { return off - times; };
    const float h = T::kCubeHalf;
    const std::string accessors = fmt::format(
        "{{\"bufferView\":0,\"componentType\":5126,\"count\":24,\"type\":\"VEC3\","
        "\"min\":[{},{},{}],\"max\":[{},{},{}]}},"
        "{{\"bufferView\":1,\"componentType\":5126,\"count\":24,\"type\":\"VEC3\"}},"
        "{{\"bufferView\":2,\"componentType\":5126,\"count\":24,\"type\":\"VEC2\"}},"
        "{{\"bufferView\":3,\"componentType\":5123,\"count\":36,\"type\":\"SCALAR\"}},"
        "{{\"bufferView\":4,\"byteOffset\":{},\"componentType\":5126,\"count\":2,"
        "\"type\":\"SCALAR\",\"min\":[0],\"max\":[1]}},"
        "{{\"bufferView\":4,\"byteOffset\":{},\"componentType\":5126,\"count\":2,"
        "\"type\":\"SCALAR\",\"min\":[0],\"max\":[{}]}},"
        "{{\"bufferView\":4,\"byteOffset\":{},\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}},"
        "{{\"bufferView\":4,\"byteOffset\":{},\"componentType\":5126,\"count\":2,\"type\":\"VEC4\"}},"
        "{{\"bufferView\":4,\"byteOffset\":{},\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}}",
        -h, -h, -h, h, h, h, at(times), at(stepTimes), T::kStepTime, at(moverKeys), at(armKeys),
        at(camKeys));
    const std::string buffer =
        glb ? fmt::format("{{\"byteLength\":{}}}", bin.size())
            : fmt::format(
                  "{{\"byteLength\":{},\"uri\":\"data:application/octet-stream;base64,{}\"}}",
                  bin.size(), base64(bin));
    const std::string json = fmt::format(
        R"({{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,3]}}],)"
        R"("nodes":[{{"name":"mover","mesh":0,"translation":[{},{},{}],"children":[1]}},)"
        R"({{"name":"arm","children":[2]}},{{"name":"tip","mesh":1,"translation":[0,1,0]}},)"
        R"({{"name":"cam","camera":0,"translation":[{},{},{}]}}],)"
        R"("cameras":[{{"type":"perspective","perspective":{{"yfov":{},"aspectRatio":1.0,)"
        R"("znear":0.1,"zfar":100}}}}],)"
        R"("meshes":[{{"name":"red","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,)"
        R"("TEXCOORD_0":2}},"indices":3,"material":0}}]}},{{"name":"green","primitives":[{{)"
        R"("attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3,"material":1}}]}}],)"
        R"("materials":[{{"name":"red","pbrMetallicRoughness":{{"baseColorFactor":[1,0,0,1]}}}},)"
        R"({{"name":"green","pbrMetallicRoughness":{{"baseColorFactor":[0,1,0,1]}}}}],)"
        R"("animations":[{{"name":"swing","samplers":[)"
        R"({{"input":4,"output":6,"interpolation":"LINEAR"}},)"
        R"({{"input":5,"output":7,"interpolation":"STEP"}},)"
        R"({{"input":4,"output":8}}],"channels":[)"
        R"({{"sampler":0,"target":{{"node":0,"path":"translation"}}}},)"
        R"({{"sampler":1,"target":{{"node":1,"path":"rotation"}}}},)"
        R"({{"sampler":2,"target":{{"node":3,"path":"translation"}}}}]}}],)"
        R"("buffers":[{}],"bufferViews":[{}],"accessors":[{}]}})",
        T::kMoverFrom[0], T::kMoverFrom[1], T::kMoverFrom[2], T::kCamFrom[0], T::kCamFrom[1],
        T::kCamFrom[2], T::kYfov, buffer, views, accessors);
    const std::filesystem::path path = dir / (name + (glb ? ".glb" : ".gltf"));
    std::ofstream out(path, std::ios::binary);
    if (!glb) {
        out << json;
        return path;
    }
    std::string j = json;
    while (j.size() % 4) j.push_back(' ');
    while (bin.size() % 4) bin.push_back('\0');
    auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    out.write("glTF", 4);
    u32(2);
    u32(std::uint32_t(12 + 8 + j.size() + 8 + bin.size()));
    u32(std::uint32_t(j.size()));
    u32(0x4E4F534Au);
    out << j;
    u32(std::uint32_t(bin.size()));
    u32(0x004E4942u);
    out << bin;
    return path;
}

}  // namespace mvr::test
