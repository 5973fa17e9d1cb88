// glTF animations (scene_io.h's SceneLoadInfo::animation, animation.h's animateScene): the
// keys of gltf_anim_fixture.h read from .gltf (data URI) and .glb, STEP kept as STEP, the
// hierarchy re-evaluated (the tip swings with the arm and moves with the mover), the camera
// node moved; positions checked against the keys interpolated by hand.
#include <gtest/gtest.h>

#include "gltf_anim_fixture.h"
#include "mvr/core/animation.h"
#include "mvr/io/scene_io.h"

namespace mvr {
namespace {

using test::GltfAnimTruth;

void expectNear(const glm::vec3& a, const glm::vec3& b, const std::string& what) {
    EXPECT_LT(glm::length(a - b), 1e-5f) << what << ": " << a.x << " " << a.y << " " << a.z
                                         << " vs " << b.x << " " << b.y << " " << b.z;
}

TEST(GltfAnimation, NodesAndCameraFollowTheKeysThroughTheHierarchy) {
    test::TempDir dir("mvr-gltf-anim");
    for (bool glb : {false, true}) {
        const auto path = test::writeAnimatedGltf(dir.path(), "anim", glb);
        SceneLoadInfo info;
        auto scene = loadScene(path, &info);
        ASSERT_TRUE(scene) << scene.status().message();
        ASSERT_TRUE(info.animation) << path;
        const SceneAnimation& a = *info.animation;
        EXPECT_EQ(a.name, "swing");
        EXPECT_DOUBLE_EQ(a.duration, 1.0);
        ASSERT_EQ(a.nodes.size(), 4u);
        EXPECT_EQ(a.instances.size(), 2u);
        ASSERT_GE(a.cameraNode, 0);
        EXPECT_EQ(a.nodes[std::size_t(a.cameraNode)].name, "cam");
        for (const AnimatedNode& n : a.nodes) {
            if (n.name == "arm") {
                ASSERT_TRUE(n.animation && n.animation->rotation);
                EXPECT_EQ(n.animation->rotation->interpolation, Interpolation::Step);
            }
        }
        ASSERT_TRUE(scene->camera);
        Scene s = *scene;
        for (double t : {0.0, 0.25, 0.49, 0.75, 1.0, 1.5}) {
            animateScene(s, a, t);
            const std::string at = fmt::format("{} t={}", path.filename().string(), t);
            for (const Instance& inst : s.instances) {
                const glm::vec3 centre(inst.worldFromModel * glm::vec4(0, 0, 0, 1));
                if (inst.material.name == "red") expectNear(centre, GltfAnimTruth::mover(t), at);
                if (inst.material.name == "green") expectNear(centre, GltfAnimTruth::tip(t), at);
            }
            expectNear(glm::vec3(s.camera->worldFromCamera[3]), GltfAnimTruth::camera(t), at);
        }
    }
}

TEST(GltfAnimation, MalformedAnimationsNameFileAndChannel) {
    test::TempDir dir("mvr-gltf-anim-bad");
    const auto path = test::writeAnimatedGltf(dir.path(), "anim", false);
    const std::string good = test::readBytes(path);
    struct Case {
        std::string from, to, message;
    };
    const Case cases[] = {
        {R"({"sampler":2,)", R"({"sampler":9,)", "animation: channel 2: no sampler 9"},
        {R"("interpolation":"STEP")", R"("interpolation":"SMOOTH")",
         "channel 1: interpolation 'SMOOTH'"},
    };
    for (const Case& c : cases) {
        std::string text = good;
        const auto at = text.find(c.from);
        ASSERT_NE(at, std::string::npos) << c.from;
        text.replace(at, c.from.size(), c.to);
        const auto bad = dir.write("bad.gltf", text);
        auto scene = loadScene(bad);
        ASSERT_FALSE(scene) << c.to;
        EXPECT_EQ(scene.status().code(), ErrorCode::Input);
        EXPECT_NE(scene.status().message().find(c.message), std::string::npos)
            << scene.status().message();
        EXPECT_NE(scene.status().message().find("bad.gltf"), std::string::npos);
    }
}

TEST(GltfAnimation, FilesWithoutAnimationsHaveNone) {
    test::TempDir dir("mvr-gltf-anim-none");
    const auto path = test::writeGltfFixture(dir.path(), "still", test::GltfLayout::Glb);
    SceneLoadInfo info;
    auto scene = loadScene(path, &info);
    ASSERT_TRUE(scene) << scene.status().message();
    EXPECT_FALSE(info.animation);
}

}  // namespace
}  // namespace mvr
