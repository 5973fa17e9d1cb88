// glTF skins (issue 39 item 3; mesh.h poseSkin, animation.h SceneAnimation::Skin): a two-bone
// strip laid out as Blender's exporter writes an armature (an "Armature" node holding the bone
// nodes and the skinned mesh node, JOINTS_0 as unsigned bytes, WEIGHTS_0, inverse bind
// matrices, a rotation channel on the second bone), read from .gltf; its vertices in the
// file's rest pose and at animation times, against the joint transforms multiplied out by
// hand in the test.
#include <cmath>

#include <gtest/gtest.h>

#include "gltf_fixture.h"
#include "mvr/core/animation.h"
#include "mvr/io/scene_io.h"
#include "test_files.h"

namespace mvr {
namespace {

// The armature stands at x = 2; bone "Root" at its origin, bone "Tip" 1 above it. The strip:
// 5 rows of 2 vertices at y = 0, 0.5, 1, 1.5, 2 and x = 2 ∓ 0.1 (bind pose, root space): rows
// 0-1 follow Root, row 2 half each, rows 3-4 follow Tip.
constexpr float kRows[5] = {0.0f, 0.5f, 1.0f, 1.5f, 2.0f};

float tipWeight(float y) { return y < 0.75f ? 0.0f : y > 1.25f ? 1.0f : 0.5f; }
/// With `eight` influences the middle row is Tip 0.3, Root 0.1 and four more joints at Root's
/// place 0.15 each (JOINTS_1 / WEIGHTS_1 hold two of them): Tip's share 0.3 of all eight (the 4
/// largest alone would give it 0.3 / 0.75 = 0.4).
float tipWeight(float y, bool eight) { return eight && y > 0.75f && y < 1.25f ? 0.3f : tipWeight(y); }

/// Where a bind-pose vertex goes when Tip is turned by `degrees` about +z at its head (2, 1):
/// Root's matrix world · IBM is the identity, Tip's T(2, 1, 0) · R(θ) · T(−2, −1, 0).
glm::vec3 posed(const glm::vec3& bind, float degrees, bool eight = false) {
    const float a = glm::radians(degrees), c = std::cos(a), s = std::sin(a);
    const glm::vec3 d = bind - glm::vec3(2, 1, 0);
    const glm::vec3 tip = glm::vec3(2, 1, 0) + glm::vec3(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
    const float w = tipWeight(bind.y, eight);
    return (1.0f - w) * bind + w * tip;
}

/// `restDegrees`: Tip's rest rotation (the node's own "rotation"); `animated`: a LINEAR
/// rotation channel on Tip from 0° at t = 0 to 90° at t = 1.
/// `twice`: a second node ("Copy", 5 to the right) instances the skinned mesh too.
/// `eight`: four more joints ("J2".."J5", children of Root at its place) and the middle row
/// spread over six influences, JOINTS_1 / WEIGHTS_1 as Blender writes a vertex of more than 4
/// groups (not with `twice`).
std::filesystem::path writeSkinnedStrip(const std::filesystem::path& dir, float restDegrees,
                                        bool animated, bool twice = false, bool eight = false) {
    std::string bin;
    std::vector<float> pos, nrm;
    std::vector<std::uint8_t> joints, joints1;
    std::vector<float> weights, weights1;
    for (float y : kRows) {
        for (float x : {1.9f, 2.1f}) {
            pos.insert(pos.end(), {x, y, 0.0f});
            nrm.insert(nrm.end(), {0.0f, 0.0f, 1.0f});
            const float w = tipWeight(y);
            if (eight && w == 0.5f) {
                joints.insert(joints.end(), {0, 1, 2, 3});
                weights.insert(weights.end(), {0.1f, 0.3f, 0.15f, 0.15f});
                joints1.insert(joints1.end(), {4, 5, 0, 0});
                weights1.insert(weights1.end(), {0.15f, 0.15f, 0.0f, 0.0f});
            } else {
                joints.insert(joints.end(), {0, 1, 0, 0});
                weights.insert(weights.end(), {1.0f - w, w, 0.0f, 0.0f});
                joints1.insert(joints1.end(), {0, 0, 0, 0});
                weights1.insert(weights1.end(), {0.0f, 0.0f, 0.0f, 0.0f});
            }
        }
    }
    std::vector<std::uint16_t> idx;
    for (std::uint16_t r = 0; r < 4; ++r) {
        const std::uint16_t a = std::uint16_t(2 * r);
        idx.insert(idx.end(), {a, std::uint16_t(a + 1), std::uint16_t(a + 3), a,
                               std::uint16_t(a + 3), std::uint16_t(a + 2)});
    }
    // Inverse bind matrices (column-major): T(−2, 0, 0) and T(−2, −1, 0) (and Root's for J2..J5).
    std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2, 0, 0, 1,
                              1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2, -1, 0, 1};
    for (int k = 0; eight && k < 4; ++k)
        ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -2, 0, 0, 1});
    const float h = std::sin(glm::radians(45.0f));
    auto align = [&] { while (bin.size() % 4) bin.push_back('\0'); };
    const std::size_t posAt = bin.size();
    test::detail_fixture::appendFloats(bin, pos);
    const std::size_t nrmAt = bin.size();
    test::detail_fixture::appendFloats(bin, nrm);
    const std::size_t jointsAt = bin.size();
    bin.append(reinterpret_cast<const char*>(joints.data()), joints.size());
    align();
    const std::size_t weightsAt = bin.size();
    test::detail_fixture::appendFloats(bin, weights);
    const std::size_t idxAt = bin.size();
    bin.append(reinterpret_cast<const char*>(idx.data()), idx.size() * 2);
    align();
    const std::size_t ibmAt = bin.size();
    test::detail_fixture::appendFloats(bin, ibm);
    const std::size_t timesAt = bin.size();
    test::detail_fixture::appendFloats(bin, {0.0f, 1.0f});
    const std::size_t rotAt = bin.size();
    test::detail_fixture::appendFloats(bin, {0, 0, 0, 1, 0, 0, h, h});
    const std::size_t joints1At = bin.size();
    bin.append(reinterpret_cast<const char*>(joints1.data()), joints1.size());
    align();
    const std::size_t weights1At = bin.size();
    test::detail_fixture::appendFloats(bin, weights1);
    const float ra = glm::radians(restDegrees) / 2.0f;
    const std::string json = fmt::format(
        R"({{"asset":{{"version":"2.0","generator":"Khronos glTF Blender I/O v3.6.27"}},
"scene":0,"scenes":[{{"name":"Scene","nodes":[0]}}],
"nodes":[{{"name":"Armature","translation":[2,0,0],"children":[1,3{}]}},
 {{"name":"Root","children":[2{}]}},
 {{"name":"Tip","translation":[0,1,0],"rotation":[0,0,{},{}]}},
 {{"name":"Strip","mesh":0,"skin":0}}{}],
"skins":[{{"name":"Armature","inverseBindMatrices":5,"joints":[1,2{}]}}],
"meshes":[{{"name":"Strip","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"JOINTS_0":2,"WEIGHTS_0":3{}}},"indices":4}}]}}],
"accessors":[
 {{"bufferView":0,"componentType":5126,"count":10,"type":"VEC3","min":[1.9,0,0],"max":[2.1,2,0]}},
 {{"bufferView":1,"componentType":5126,"count":10,"type":"VEC3"}},
 {{"bufferView":2,"componentType":5121,"count":10,"type":"VEC4"}},
 {{"bufferView":3,"componentType":5126,"count":10,"type":"VEC4"}},
 {{"bufferView":4,"componentType":5123,"count":24,"type":"SCALAR"}},
 {{"bufferView":5,"componentType":5126,"count":{},"type":"MAT4"}},
 {{"bufferView":6,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}},
 {{"bufferView":7,"componentType":5126,"count":2,"type":"VEC4"}},
 {{"bufferView":8,"componentType":5121,"count":10,"type":"VEC4"}},
 {{"bufferView":9,"componentType":5126,"count":10,"type":"VEC4"}}],
"bufferViews":[
 {{"buffer":0,"byteOffset":{},"byteLength":120}},{{"buffer":0,"byteOffset":{},"byteLength":120}},
 {{"buffer":0,"byteOffset":{},"byteLength":40}},{{"buffer":0,"byteOffset":{},"byteLength":160}},
 {{"buffer":0,"byteOffset":{},"byteLength":48}},{{"buffer":0,"byteOffset":{},"byteLength":{}}},
 {{"buffer":0,"byteOffset":{},"byteLength":8}},{{"buffer":0,"byteOffset":{},"byteLength":32}},
 {{"buffer":0,"byteOffset":{},"byteLength":40}},{{"buffer":0,"byteOffset":{},"byteLength":160}}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}]{}}})",
        twice ? ",4" : "", eight ? ",4,5,6,7" : "", std::sin(ra), std::cos(ra),
        twice ? R"(,{"name":"Copy","mesh":0,"skin":0,"translation":[5,0,0]})"
              : eight ? R"(,{"name":"J2"},{"name":"J3"},{"name":"J4"},{"name":"J5"})" : "",
        eight ? ",4,5,6,7" : "", eight ? R"(,"JOINTS_1":8,"WEIGHTS_1":9)" : "",
        eight ? 6 : 2, posAt, nrmAt, jointsAt, weightsAt, idxAt, ibmAt, eight ? 384 : 128,
        timesAt, rotAt, joints1At, weights1At, bin.size(), test::base64(bin),
        animated ? R"(,"animations":[{"name":"Bend","channels":[{"sampler":0,"target":{"node":2,"path":"rotation"}}],"samplers":[{"input":6,"output":7,"interpolation":"LINEAR"}]}])"
                 : "");
    const auto path =
        dir / fmt::format("strip-{}-{}-{}-{}.gltf", int(restDegrees), animated, twice, eight);
    std::ofstream(path) << json;
    return path;
}

/// Every vertex of the strip's instance in world space against posed(its bind position).
void expectPosed(const Scene& scene, float degrees, const std::string& what,
                 std::size_t instance = 0, bool eight = false) {
    ASSERT_GT(scene.instances.size(), instance) << what;
    const Instance& inst = scene.instances[instance];
    const Mesh& mesh = scene.meshes.at(std::size_t(inst.mesh));
    ASSERT_EQ(mesh.basePositions.size(), 10u) << what;
    ASSERT_EQ(mesh.joints.size(), 10u) << what;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        // The file's positions are the bind pose in the scene's space (world(joint) · IBM is
        // the identity at bind); the mesh node (at the armature's x = 2) does not place a
        // skinned mesh (glTF), so the instance's own matrix must not move it twice.
        const glm::vec3 bind = mesh.basePositions[i];
        const glm::vec3 got = glm::vec3(inst.worldFromModel * glm::vec4(mesh.positions[i], 1));
        const glm::vec3 want = posed(bind, degrees, eight);
        EXPECT_LT(glm::length(got - want), 1e-5f)
            << what << ": vertex at (" << bind.x << ", " << bind.y << ") is at (" << got.x
            << ", " << got.y << ", " << got.z << "), expected (" << want.x << ", " << want.y
            << ")";
    }
}

TEST(GltfSkin, StillShowsTheFilesRestPose) {
    test::TempDir dir("mvr-gltf-skin");
    for (float rest : {0.0f, 90.0f, -30.0f}) {
        auto scene = loadScene(writeSkinnedStrip(dir.path(), rest, false));
        ASSERT_TRUE(scene) << scene.status().message();
        expectPosed(*scene, rest, fmt::format("rest {}°", rest));
    }
}

TEST(GltfSkin, MoreThanFourInfluencesAreAllBlended) {
    // JOINTS_1 / WEIGHTS_1: the middle row's six influences all count (Tip 0.3 of them), at
    // rest and with Tip turned 90° by the animation.
    test::TempDir dir("mvr-gltf-skin-eight");
    SceneLoadInfo info;
    auto scene = loadScene(writeSkinnedStrip(dir.path(), 0.0f, true, false, true), &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_TRUE(info.animation);
    const Mesh& mesh = scene->meshes.at(0);
    ASSERT_EQ(mesh.joints1.size(), 10u);
    expectPosed(*scene, 0.0f, "eight, rest", 0, true);
    Scene s = *scene;
    animateScene(s, *info.animation, 1.0);
    expectPosed(s, 90.0f, "eight, 90°", 0, true);
}

TEST(GltfSkin, NodesSharingASkinnedMeshDrawItAlike) {
    // glTF: a skinned mesh's node transform is ignored, so the "Copy" node 5 to the right draws
    // the strip where its joints put it, as the first node does.
    test::TempDir dir("mvr-gltf-skin-twice");
    SceneLoadInfo info;
    auto scene = loadScene(writeSkinnedStrip(dir.path(), 0.0f, true, true), &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(scene->instances.size(), 2u);
    ASSERT_TRUE(info.animation);
    Scene s = *scene;
    animateScene(s, *info.animation, 1.0);
    expectPosed(s, 90.0f, "first node", 0);
    expectPosed(s, 90.0f, "second node", 1);
}

TEST(GltfSkin, AnimationTurnsTheTipBoneAndItsVertices) {
    test::TempDir dir("mvr-gltf-skin-anim");
    SceneLoadInfo info;
    auto scene = loadScene(writeSkinnedStrip(dir.path(), 0.0f, true), &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_TRUE(info.animation);
    ASSERT_EQ(info.animation->skins.size(), 1u);
    expectPosed(*scene, 0.0f, "loaded");
    Scene s = *scene;
    for (double t : {0.0, 0.5, 1.0, 3.0}) {
        animateScene(s, *info.animation, t);
        // slerp from 0° to 90° about one axis is linear in the angle; clamped after t = 1
        expectPosed(s, float(90.0 * std::clamp(t, 0.0, 1.0)), fmt::format("t = {}", t));
    }
    // The tip's normals turn with it: (0, 0, 1) about z stays (0, 0, 1).
    for (const glm::vec3& n : s.meshes[0].normals) EXPECT_NEAR(n.z, 1.0f, 1e-5f);
}

TEST(GltfSkin, PoseSkinBlendsJointMatricesByWeight) {
    Mesh m;
    m.positions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    m.normals.assign(3, glm::vec3(0, 0, 1));
    m.indices = {0, 1, 2};
    m.basePositions = m.positions;
    m.baseNormals = m.normals;
    m.joints.assign(3, glm::u16vec4(0, 1, 0, 0));
    m.weights = {{1, 0, 0, 0}, {0.25f, 0.75f, 0, 0}, {0, 1, 0, 0}};
    const glm::mat4 a = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 4));
    const glm::mat4 b = glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    poseSkin(m, {a, b});
    EXPECT_EQ(m.positions[0], glm::vec3(1, 0, 4));
    // 0.25 · (0, 1, 4) + 0.75 · (0, 2, 0)
    EXPECT_NEAR(glm::length(m.positions[1] - glm::vec3(0, 1.75f, 1.0f)), 0.0f, 1e-6f);
    EXPECT_EQ(m.positions[2], glm::vec3(0, 0, 2));
    // Posed again: from the base, not compounded.
    poseSkin(m, {a, b});
    EXPECT_EQ(m.positions[2], glm::vec3(0, 0, 2));
    // A vertex with no weight stays where it is (not at the origin).
    m.weights[1] = glm::vec4(0.0f);
    poseSkin(m, {a, b});
    EXPECT_EQ(m.positions[1], glm::vec3(0, 1, 0));
    EXPECT_EQ(m.normals[1], glm::vec3(0, 0, 1));
    // A joint scaled to nothing (a hidden part) still gives finite normals elsewhere.
    m.weights[1] = glm::vec4(0.5f, 0.5f, 0, 0);
    poseSkin(m, {a, glm::scale(glm::mat4(1.0f), glm::vec3(0.0f))});
    EXPECT_NEAR(glm::length(m.normals[1]), 1.0f, 1e-6f);
    // Tangents turn with their joints (a quarter turn about z), handedness kept.
    m.tangents.assign(3, glm::vec4(1, 0, 0, -1));
    m.baseTangents = m.tangents;
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1));
    poseSkin(m, {turn, turn});
    for (const glm::vec4& t : m.tangents) {
        EXPECT_NEAR(glm::length(glm::vec3(t) - glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, -1.0f);
    }
}

}  // namespace
}  // namespace mvr
