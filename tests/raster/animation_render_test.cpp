// A glTF animation played and rendered (soft backend): at chosen times the red cube (mover,
// LINEAR), the green cube (tip, under the STEP-rotated arm) and the camera (LINEAR) are where
// the keys, interpolated by hand and projected with a camera matrix computed here, put them;
// soft:unified == soft:multipass at every time.
#include <cmath>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "exactness.h"
#include "gltf_anim_fixture.h"
#include "mvr/core/animation.h"
#include "mvr/core/mesh.h"
#include "mvr/io/scene_io.h"
#include "mvr/raster/soft_backend.h"

namespace mvr {
namespace {

using test::GltfAnimTruth;

constexpr int kSize = 128;
constexpr float kDistance = 6.0f;  // the base camera's target distance (= convergence)

/// The centroid of the pixels of one hue (red: r well above g and b; green: g above r, b).
std::optional<glm::vec2> centroid(const Image& im, bool red) {
    glm::dvec2 sum(0.0);
    int n = 0;
    for (int y = 0; y < im.height; ++y) {
        for (int x = 0; x < im.width; ++x) {
            const Rgba8 p = im.at(x, y);
            const int main = red ? p.r : p.g, o1 = red ? p.g : p.r, o2 = p.b;
            if (main > o1 + 15 && main > o2 + 15) {
                sum += glm::dvec2(x + 0.5, y + 0.5);
                ++n;
            }
        }
    }
    if (n < 4) return std::nullopt;
    return glm::vec2(sum / double(n));
}

/// Where a world point lands in the centre view's pixels: the glTF camera at `eye` looking
/// down −Z (+Y up), a symmetric perspective of the file's yfov, computed here by hand.
glm::vec2 project(const glm::vec3& eye, const glm::vec3& p) {
    const glm::vec3 v = p - eye;  // camera axes = world axes
    const float f = 1.0f / std::tan(GltfAnimTruth::kYfov * 0.5f);
    const float ndcX = f * v.x / -v.z, ndcY = f * v.y / -v.z;  // aspect 1
    return {(ndcX + 1.0f) * 0.5f * kSize, (1.0f - ndcY) * 0.5f * kSize};
}

TEST(AnimationRender, ProjectedCentresFollowTheKeysAndUnifiedEqualsMultipass) {
    test::TempDir dir("mvr-anim-render");
    const auto path = test::writeAnimatedGltf(dir.path(), "anim", false);
    SceneLoadInfo info;
    auto loaded = loadScene(path, &info);
    ASSERT_TRUE(loaded) << loaded.status().message();
    ASSERT_TRUE(info.animation);
    Scene scene = std::move(loaded).value();
    Camera base;
    base.fovYDegrees = glm::degrees(GltfAnimTruth::kYfov);
    base.aspect = 1.0f;
    base.near = 0.1f;
    base.far = 100.0f;
    base.position = {0, 0, kDistance};
    base.target = {0, 0, 0};
    RigParams params;
    params.columns = 3;  // view 1 is the centre camera itself
    params.interaxial = 0.1f;
    params.convergence = kDistance;
    RenderSettings settings;
    settings.width = settings.height = kSize;
    auto backend = raster::makeSoftBackend();
    for (double t : {0.0, 0.3, 0.7, 1.0, 2.0}) {  // 2.0: past the end, the last keys hold
        animateScene(scene, *info.animation, t);
        const Camera camera = cameraFromNode(scene.camera->worldFromCamera, base);
        auto rig = makeRig(camera, params);
        ASSERT_TRUE(rig) << rig.status().message();
        auto mp = backend->render(scene, *rig, settings, "multipass");
        ASSERT_TRUE(mp) << mp.status().message();
        auto un = backend->render(scene, *rig, settings, "unified");
        ASSERT_TRUE(un) << un.status().message();
        for (int v = 0; v < 3; ++v)
            EXPECT_EQ(mp->color[std::size_t(v)].rgba, un->color[std::size_t(v)].rgba)
                << "t=" << t << " view " << v;
        const Image& centre = mp->color[1];
        const glm::vec3 eye = GltfAnimTruth::camera(t);
        for (bool red : {true, false}) {
            const glm::vec3 world = red ? GltfAnimTruth::mover(t) : GltfAnimTruth::tip(t);
            const glm::vec2 want = project(eye, world);
            const auto got = centroid(centre, red);
            ASSERT_TRUE(got) << "t=" << t << (red ? " red" : " green") << " cube not drawn";
            // The silhouette's centroid is within a pixel and a half of the projected centre
            // (a cube of ~8 px; its side faces shift the centroid slightly).
            EXPECT_LT(glm::length(*got - want), 1.5f)
                << "t=" << t << (red ? " red" : " green") << " at " << got->x << "," << got->y
                << " expected " << want.x << "," << want.y;
        }
    }
}

TEST(AnimationRender, UnifiedEqualsMultipassOnASkinnedAndMorphedMesh) {
    // The default scene with every mesh morphed (a ripple along its normals at weight 0.7)
    // and skinned to two joints (the upper part turned 25° about z and lifted), posed as a
    // sequence poses it (applyMorphWeights, then poseSkin) before the view-independent work.
    Scene scene = makeDefaultScene();
    std::size_t moved = 0;
    for (Mesh& m : scene.meshes) {
        m.basePositions = m.positions;
        m.baseNormals = m.normals;
        MorphTarget ripple;
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            ripple.positions.push_back(m.normals[i] * (0.15f * std::sin(3.0f * m.positions[i].x)));
            ripple.normals.push_back(glm::vec3(0.2f * std::cos(3.0f * m.positions[i].x), 0, 0));
        }
        m.morphTargets = {ripple};
        float lo = m.positions[0].y, hi = lo;
        for (const glm::vec3& p : m.positions) lo = std::min(lo, p.y), hi = std::max(hi, p.y);
        for (const glm::vec3& p : m.positions) {
            const float w = hi > lo ? glm::clamp((p.y - lo) / (hi - lo), 0.0f, 1.0f) : 0.0f;
            m.joints.emplace_back(0, 1, 0, 0);
            m.weights.emplace_back(1.0f - w, w, 0.0f, 0.0f);
        }
        applyMorphWeights(m, {0.7f});
        const std::vector<glm::vec3> morphed = m.positions;
        const glm::mat4 turn = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.2f, 0.0f)) *
                               glm::rotate(glm::mat4(1.0f), glm::radians(25.0f), {0, 0, 1});
        poseSkin(m, {glm::mat4(1.0f), turn});
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            moved += glm::length(m.positions[i] - morphed[i]) > 1e-3f ? 1 : 0;
    }
    ASSERT_GT(moved, 100u);  // the pose moved the meshes
    auto backend = raster::makeSoftBackend();
    raster::test::expectUnifiedEqualsMultipass(*backend, scene, {{2, 1}, {5, 1}, {16, 1}, {3, 2}},
                                               80, 60);
}

}  // namespace
}  // namespace mvr
