// glTF morph targets (issue 39 item 3; mesh.h applyMorphWeights, animation.h's weights
// channels): a box laid out as Blender's exporter writes shape keys (POSITION and NORMAL
// targets, the mesh's default `weights`, `extras.targetNames`, a LINEAR "weights" channel),
// read from .gltf; its vertices at the default weights and at animation times, against the
// displacements and weights interpolated by hand in the test.
#include <gtest/gtest.h>

#include "gltf_fixture.h"
#include "mvr/core/animation.h"
#include "mvr/io/scene_io.h"
#include "test_files.h"

namespace mvr {
namespace {

constexpr float kHalf = 0.5f;
// Target 0 ("Lift"): the box's top vertices (y = +h) 1 up; target 1 ("Shift"): every vertex
// 0.5 along +x. Default weights 0.5, 0; the animation goes from (0, 0) at t = 0 to (1, 1) at
// t = 1, LINEAR.
constexpr float kDefault[2] = {0.5f, 0.0f};

glm::vec3 morphed(const glm::vec3& base, float w0, float w1) {
    return base + w0 * (base.y > 0.0f ? glm::vec3(0, 1, 0) : glm::vec3(0)) +
           w1 * glm::vec3(0.5f, 0, 0);
}

std::filesystem::path writeMorphBox(const std::filesystem::path& dir, bool animated) {
    std::string bin;
    std::size_t p0, n0, u0, i0;
    test::detail_fixture::box(bin, glm::vec3(0), kHalf, p0, n0, u0, i0);
    // The box's 24 positions (its own layout: 4 a face), to build the targets from.
    std::vector<glm::vec3> pos(24);
    std::memcpy(pos.data(), bin.data() + p0, 24 * sizeof(glm::vec3));
    std::vector<float> lift, shift, zero(24 * 3, 0.0f);
    for (const glm::vec3& p : pos) {
        lift.insert(lift.end(), {0.0f, p.y > 0.0f ? 1.0f : 0.0f, 0.0f});
        shift.insert(shift.end(), {0.5f, 0.0f, 0.0f});
    }
    const std::size_t liftAt = bin.size();
    test::detail_fixture::appendFloats(bin, lift);
    const std::size_t shiftAt = bin.size();
    test::detail_fixture::appendFloats(bin, shift);
    const std::size_t zeroAt = bin.size();
    test::detail_fixture::appendFloats(bin, zero);
    const std::size_t timesAt = bin.size();
    test::detail_fixture::appendFloats(bin, {0.0f, 1.0f});
    const std::size_t weightsAt = bin.size();
    test::detail_fixture::appendFloats(bin, {0.0f, 0.0f, 1.0f, 1.0f});
    const std::string json = fmt::format(
        R"({{"asset":{{"version":"2.0","generator":"Khronos glTF Blender I/O v3.6.27"}},
"scene":0,"scenes":[{{"name":"Scene","nodes":[0]}}],
"nodes":[{{"mesh":0,"name":"Cube"}}],
"meshes":[{{"name":"Cube","weights":[{},{}],"extras":{{"targetNames":["Lift","Shift"]}},
 "primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3,
  "targets":[{{"POSITION":4,"NORMAL":6}},{{"POSITION":5,"NORMAL":6}}]}}]}}],
"accessors":[
 {{"bufferView":0,"componentType":5126,"count":24,"type":"VEC3","min":[-0.5,-0.5,-0.5],"max":[0.5,0.5,0.5]}},
 {{"bufferView":1,"componentType":5126,"count":24,"type":"VEC3"}},
 {{"bufferView":2,"componentType":5126,"count":24,"type":"VEC2"}},
 {{"bufferView":3,"componentType":5123,"count":36,"type":"SCALAR"}},
 {{"bufferView":4,"componentType":5126,"count":24,"type":"VEC3","min":[0,0,0],"max":[0,1,0]}},
 {{"bufferView":5,"componentType":5126,"count":24,"type":"VEC3","min":[0.5,0,0],"max":[0.5,0,0]}},
 {{"bufferView":6,"componentType":5126,"count":24,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}},
 {{"bufferView":7,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}},
 {{"bufferView":8,"componentType":5126,"count":4,"type":"SCALAR"}}],
"bufferViews":[
 {{"buffer":0,"byteOffset":{},"byteLength":288}},{{"buffer":0,"byteOffset":{},"byteLength":288}},
 {{"buffer":0,"byteOffset":{},"byteLength":192}},{{"buffer":0,"byteOffset":{},"byteLength":72}},
 {{"buffer":0,"byteOffset":{},"byteLength":288}},{{"buffer":0,"byteOffset":{},"byteLength":288}},
 {{"buffer":0,"byteOffset":{},"byteLength":288}},{{"buffer":0,"byteOffset":{},"byteLength":8}},
 {{"buffer":0,"byteOffset":{},"byteLength":16}}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]{}}})",
        kDefault[0], kDefault[1], p0, n0, u0, i0, liftAt, shiftAt, zeroAt, timesAt, weightsAt,
        bin.size(), test::base64(bin),
        animated ? R"(,"animations":[{"name":"KeyAction","channels":[{"sampler":0,"target":{"node":0,"path":"weights"}}],"samplers":[{"input":7,"output":8,"interpolation":"LINEAR"}]}])"
                 : "");
    const auto path = dir / (animated ? "morph-animated.gltf" : "morph.gltf");
    std::ofstream(path) << json;
    return path;
}

/// Every vertex of the loaded mesh against the weights: its unmorphed position is a box
/// corner, its position that corner displaced as the targets say.
void expectMorphed(const Mesh& mesh, float w0, float w1, const std::string& what) {
    ASSERT_EQ(mesh.morphTargets.size(), 2u) << what;
    ASSERT_EQ(mesh.basePositions.size(), mesh.positions.size()) << what;
    int top = 0;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3& b = mesh.basePositions[i];
        for (int k = 0; k < 3; ++k) ASSERT_FLOAT_EQ(std::abs(b[k]), kHalf) << what;
        top += b.y > 0.0f;
        const glm::vec3 want = morphed(b, w0, w1);
        EXPECT_LT(glm::length(mesh.positions[i] - want), 1e-6f)
            << what << ", vertex " << i << ": " << mesh.positions[i].x << " "
            << mesh.positions[i].y << " " << mesh.positions[i].z;
        // The targets move no normal: the side faces stay vertical.
        EXPECT_LT(glm::length(mesh.normals[i] - mesh.baseNormals[i]), 1e-6f) << what;
    }
    EXPECT_GT(top, 0) << what;
}

TEST(GltfMorph, DefaultWeightsAndTheWeightsChannelMoveTheVertices) {
    test::TempDir dir("mvr-gltf-morph");
    {
        auto scene = loadScene(writeMorphBox(dir.path(), false));
        ASSERT_TRUE(scene) << scene.status().message();
        ASSERT_EQ(scene->meshes.size(), 1u);
        expectMorphed(scene->meshes[0], kDefault[0], kDefault[1], "default weights");
        // The top at +h + 0.5: the bounds follow the morphed mesh.
        EXPECT_FLOAT_EQ(scene->meshes[0].bounds().max.y, kHalf + kDefault[0]);
    }
    SceneLoadInfo info;
    auto scene = loadScene(writeMorphBox(dir.path(), true), &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_TRUE(info.animation);
    for (const std::string& w : info.warnings)
        EXPECT_EQ(w.find("weights"), std::string::npos) << w;  // played, not warned about
    EXPECT_DOUBLE_EQ(info.animation->duration, 1.0);
    Scene s = *scene;
    for (double t : {0.0, 0.25, 0.6, 1.0, 2.0}) {
        animateScene(s, *info.animation, t);
        const float w = float(std::clamp(t, 0.0, 1.0));  // (0, 0) → (1, 1), clamped after
        expectMorphed(s.meshes[0], w, w, fmt::format("t = {}", t));
    }
}

TEST(GltfMorph, ApplyMorphWeightsRenormalisesDisplacedNormals) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.indices = {0, 1, 2};
    m.basePositions = m.positions;
    m.baseNormals = m.normals;
    MorphTarget t;
    t.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 2}};
    t.normals.assign(3, glm::vec3(1, 0, -1));
    m.morphTargets.push_back(t);
    applyMorphWeights(m, {0.5f});
    EXPECT_FLOAT_EQ(m.positions[2].z, 1.0f);
    // (0, 0, 1) + 0.5 · (1, 0, −1) = (0.5, 0, 0.5), normalised.
    EXPECT_NEAR(m.normals[0].x, std::sqrt(0.5f), 1e-6f);
    EXPECT_NEAR(m.normals[0].z, std::sqrt(0.5f), 1e-6f);
    EXPECT_TRUE(validateMesh(m, "m"));
    m.morphTargets[0].positions.pop_back();
    const Status bad = validateMesh(m, "m");
    EXPECT_FALSE(bad);
    EXPECT_NE(bad.message().find("morph target 0 has 2 positions and 3 normals for 3 vertices"),
              std::string::npos)
        << bad.message();
}

}  // namespace
}  // namespace mvr
