// Tests of loadScene() (scene_io.h) on files written here: the Blender-layout glTF fixture
// (gltf_fixture.h) in its three layouts, OBJ + MTL, and bad textures.
#include "mvr/core/scene_io.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "gltf_fixture.h"
#include "test_files.h"

namespace mvr {
namespace {

using test::GltfFixtureTruth;
using test::GltfLayout;

bool near(const glm::mat4& a, const glm::mat4& b, float eps = 1e-5f) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (std::abs(a[c][r] - b[c][r]) > eps) return false;
    return true;
}

const Instance* findInstance(const Scene& s, const glm::mat4& world, bool textured) {
    for (const Instance& i : s.instances)
        if (near(i.worldFromModel, world) && (i.material.baseColorTexture >= 0) == textured)
            return &i;
    return nullptr;
}

class GltfLayouts : public ::testing::TestWithParam<GltfLayout> {};

TEST_P(GltfLayouts, HierarchyMaterialsCameraLights) {
    test::TempDir dir("mvr-scene-io");
    const auto path = test::writeGltfFixture(dir.path(), "fixture", GetParam());
    SceneLoadInfo info;
    auto scene = loadScene(path, &info);
    ASSERT_TRUE(scene) << scene.status().message();
    EXPECT_TRUE(info.fromMaterials);
    // Two nodes instance a mesh of two primitives: four instances of two meshes.
    ASSERT_EQ(scene->meshes.size(), 2u);
    ASSERT_EQ(scene->instances.size(), 4u);
    const glm::mat4 a = GltfFixtureTruth::parent() * GltfFixtureTruth::childA();
    const glm::mat4 b = GltfFixtureTruth::parent() * GltfFixtureTruth::childB();
    for (const glm::mat4& world : {a, b}) {
        const Instance* tex = findInstance(*scene, world, true);
        const Instance* red = findInstance(*scene, world, false);
        ASSERT_TRUE(tex && red);
        // Textured cube: the whole texture, the sampler, MASK 0.3, double-sided.
        EXPECT_EQ(tex->material.name, "Checker");
        EXPECT_EQ(tex->material.alphaMode, AlphaMode::Mask);
        EXPECT_FLOAT_EQ(tex->material.alphaCutoff, 0.3f);
        EXPECT_TRUE(tex->material.doubleSided);
        EXPECT_EQ(tex->material.sampler.magFilter, TextureFilter::Nearest);
        EXPECT_EQ(tex->material.sampler.minFilter, TextureFilter::Linear);
        EXPECT_TRUE(tex->material.sampler.mipmaps);
        EXPECT_EQ(tex->material.sampler.wrapS, TextureWrap::ClampToEdge);
        EXPECT_EQ(tex->material.sampler.wrapT, TextureWrap::MirroredRepeat);
        // Red cube: baseColorFactor (1, 0, 0, 0.5), BLEND, single-sided, the small box at +1.
        EXPECT_EQ(red->material.alphaMode, AlphaMode::Blend);
        EXPECT_NEAR(red->material.alpha, 0.5f, 1e-6f);
        EXPECT_NEAR(red->material.albedo.x, 1.0f, 1e-6f);
        EXPECT_NEAR(red->material.albedo.y, 0.0f, 1e-6f);
        EXPECT_FALSE(red->material.doubleSided);
        const Bounds rb = scene->meshes[red->mesh].bounds();
        EXPECT_NEAR(rb.min.y, 0.75f, 1e-6f);
        EXPECT_NEAR(rb.max.y, 1.25f, 1e-6f);
    }
    // One decoded texture, the fixture's pixels; uv (0, 0) is its top-left (red) texel.
    ASSERT_EQ(scene->textures.size(), 1u);
    EXPECT_EQ(scene->textures[0].image, test::fixtureTexture());
    const Instance* tex = findInstance(*scene, a, true);
    const Mesh& cube = scene->meshes[tex->mesh];
    ASSERT_EQ(cube.texcoords.size(), cube.positions.size());
    // The +Z face's corner (x, y) = (-0.5, +0.5) is uv (0, 0) in the file (top-left).
    bool found = false;
    for (std::size_t v = 0; v < cube.positions.size(); ++v) {
        if (glm::length(cube.positions[v] - glm::vec3(-0.5f, 0.5f, 0.5f)) < 1e-6f &&
            cube.normals[v].z > 0.9f) {
            EXPECT_NEAR(cube.texcoords[v].x, 0.0f, 1e-6f);
            EXPECT_NEAR(cube.texcoords[v].y, 0.0f, 1e-6f);
            found = true;
        }
    }
    EXPECT_TRUE(found);
    // The camera: its node's translation, looking down -Z, the file's yfov / aspect / planes.
    ASSERT_TRUE(scene->camera);
    EXPECT_TRUE(near(scene->camera->worldFromCamera,
                     glm::translate(glm::mat4(1), GltfFixtureTruth::cameraPosition())));
    EXPECT_NEAR(scene->camera->yfovRadians, GltfFixtureTruth::kYfov, 1e-5f);
    EXPECT_NEAR(scene->camera->aspect, GltfFixtureTruth::kAspect, 1e-5f);
    EXPECT_NEAR(scene->camera->znear, GltfFixtureTruth::kZnear, 1e-6f);
    EXPECT_NEAR(scene->camera->zfar, GltfFixtureTruth::kZfar, 1e-4f);
    // The lights: the sun (rotated -60 degrees about X: it shines along (0, -sin60, -cos60))
    // and the point lamp at (0, 3, 2); color × intensity.
    ASSERT_EQ(scene->lights.size(), 2u);
    const Light* sun = nullptr;
    const Light* lamp = nullptr;
    for (const Light& l : scene->lights) (l.type == LightType::Directional ? sun : lamp) = &l;
    ASSERT_TRUE(sun && lamp);
    EXPECT_EQ(lamp->type, LightType::Point);
    const float s60 = std::sin(glm::radians(60.0f)), c60 = std::cos(glm::radians(60.0f));
    EXPECT_NEAR(sun->towardLight.x, 0.0f, 1e-5f);
    EXPECT_NEAR(sun->towardLight.y, s60, 1e-5f);
    EXPECT_NEAR(sun->towardLight.z, c60, 1e-5f);
    EXPECT_NEAR(sun->color.x, 2.0f, 1e-5f);
    EXPECT_NEAR(sun->color.y, 1.8f, 1e-5f);
    EXPECT_NEAR(lamp->color.z, 3.0f, 1e-5f);
    EXPECT_NEAR(glm::length(lamp->position - glm::vec3(0, 3, 2)), 0.0f, 1e-5f);
}

INSTANTIATE_TEST_SUITE_P(Layouts, GltfLayouts,
                         ::testing::Values(GltfLayout::External, GltfLayout::DataUri,
                                           GltfLayout::Glb));

}  // namespace
}  // namespace mvr
