// Tests of loadScene() (scene_io.h) on files written here: the glTF fixture (gltf_fixture.h) in
// its three layouts, the layout Blender's exporter writes against its hand-written equivalent
// (blender_fixture.h), OBJ + MTL, and bad textures.
#include "mvr/io/mesh_io.h"
#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "blender_fixture.h"
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
    // KHR_lights_punctual's range (assimp 5.2.5 drops it: read from the file's JSON, also from
    // a .glb's JSON chunk); the sun has none.
    EXPECT_EQ(lamp->range, 20.0f);
    EXPECT_EQ(sun->range, 0.0f);
}

// A quad per material: "Tex" (map_Kd) on the left, "Plain" (Kd 0.2 0.4 0.6, d 0.5) right.
constexpr const char* kQuadsObj = R"(mtllib quads.mtl
v -2 0 0
v -1 0 0
v -1 1 0
v -2 1 0
v 1 0 0
v 2 0 0
v 2 1 0
v 1 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
usemtl Tex
f 1/1 2/2 3/3 4/4
usemtl Plain
f 5/1 6/2 7/3 8/4
)";

TEST(LoadSceneObj, UsemtlKdAndMapKdWithVFlipped) {
    test::TempDir dir("mvr-scene-io");
    dir.write("quads.obj", kQuadsObj);
    dir.write("quads.mtl",
              "newmtl Tex\nKd 1 1 1\nmap_Kd tex.png\nnewmtl Plain\nKd 0.2 0.4 0.6\nd 0.5\n");
    ASSERT_TRUE(writePng(dir.path() / "tex.png", test::fixtureTexture()));
    SceneLoadInfo info;
    auto scene = loadScene(dir.path() / "quads.obj", &info);
    ASSERT_TRUE(scene) << scene.status().message();
    EXPECT_TRUE(info.fromMaterials);
    ASSERT_EQ(scene->instances.size(), 2u);
    ASSERT_EQ(scene->textures.size(), 1u);
    EXPECT_EQ(scene->textures[0].image, test::fixtureTexture());
    int textured = 0;
    for (const Instance& inst : scene->instances) {
        const Mesh& m = scene->meshes[inst.mesh];
        if (inst.material.baseColorTexture >= 0) {
            ++textured;
            EXPECT_EQ(inst.material.name, "Tex");
            // OBJ's vt (0, 1) is the top-left: Texture's uv (0, 0) at the vertex (-2, 1).
            for (std::size_t v = 0; v < m.positions.size(); ++v) {
                if (glm::length(m.positions[v] - glm::vec3(-2, 1, 0)) < 1e-6f) {
                    EXPECT_NEAR(m.texcoords[v].x, 0.0f, 1e-6f);
                    EXPECT_NEAR(m.texcoords[v].y, 0.0f, 1e-6f);
                }
            }
        } else {
            EXPECT_EQ(inst.material.name, "Plain");
            EXPECT_NEAR(inst.material.albedo.y, 0.4f, 1e-6f);
            EXPECT_NEAR(inst.material.alpha, 0.5f, 1e-6f);
            EXPECT_EQ(inst.material.alphaMode, AlphaMode::Blend);
        }
    }
    EXPECT_EQ(textured, 1);
    EXPECT_EQ(scene->lights.size(), defaultLights().size());  // the file has no lights
}

TEST(LoadSceneObj, WithoutMtllibIsThePlainMergedMesh) {
    test::TempDir dir("mvr-scene-io");
    std::string obj = kQuadsObj;
    obj = obj.substr(obj.find('\n') + 1);
    const auto path = dir.write("plain.obj", obj);
    SceneLoadInfo info;
    auto scene = loadScene(path, &info);
    ASSERT_TRUE(scene) << scene.status().message();
    EXPECT_FALSE(info.fromMaterials);
    ASSERT_EQ(scene->instances.size(), 1u);
    auto mesh = loadMesh(path);
    ASSERT_TRUE(mesh);
    EXPECT_EQ(scene->meshes[0].positions, mesh->positions);
}

// The choice (scene_io.h): a bad texture is an error naming the model, material and image.
// LightWave writes MTL texture paths with Windows separators ("map_Kd .\\SpiderTex.jpg"): the
// texture beside the file is found, as other readers find it.
TEST(LoadSceneTexturePaths, WindowsSeparatorsInMtlFindTheFile) {
    test::TempDir dir("mvr-scene-io");
    dir.write("s.obj", std::string(kQuadsObj).replace(7, 5, "s"));
    dir.write("s.mtl", "newmtl Tex\nmap_Kd .\\tex.png\nnewmtl Plain\nKd 1 0 0\n");
    ASSERT_TRUE(writePng(dir.path() / "tex.png", test::fixtureTexture()));
    SceneLoadInfo info;
    info.strict = true;
    auto scene = loadScene(dir.path() / "s.obj", &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(scene->textures.size(), 1u);
    EXPECT_EQ(scene->textures[0].image.rgba, test::fixtureTexture().rgba);
}

TEST(LoadSceneBadTexture, MissingCorruptAndTruncatedTexturesNameFileAndMaterial) {
    test::TempDir dir("mvr-scene-io");
    const std::string notPng = "this is not an image";
    auto path = test::writeGltfFixture(dir.path(), "bad", GltfLayout::External, &notPng);
    auto scene = loadScene(path);
    ASSERT_FALSE(scene);
    EXPECT_EQ(scene.status().code(), ErrorCode::Input);
    EXPECT_NE(scene.status().message().find(path.string() + ": material 'Checker': texture "
                                                            "'bad.png': not a readable PNG"),
              std::string::npos)
        << scene.status().message();

    // A missing texture file: a warning naming it, the material's base colour (as viewers
    // do); --strict (SceneLoadInfo::strict) keeps it an error.
    std::filesystem::remove(dir.path() / "bad.png");
    SceneLoadInfo info;
    scene = loadScene(path, &info);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(info.warnings.size(), 1u);
    EXPECT_NE(info.warnings[0].find("material 'Checker': texture 'bad.png': file not found: the "
                                    "material's base colour is used (--strict: an error)"),
              std::string::npos)
        << info.warnings[0];
    for (const Instance& i : scene->instances) EXPECT_EQ(i.material.baseColorTexture, -1);
    SceneLoadInfo strict;
    strict.strict = true;
    scene = loadScene(path, &strict);
    ASSERT_FALSE(scene);
    EXPECT_NE(
        scene.status().message().find("material 'Checker': texture 'bad.png': file not found"),
        std::string::npos)
        << scene.status().message();

    // A truncated PNG inside a .glb.
    ASSERT_TRUE(writePng(dir.path() / "t.png", test::fixtureTexture()));
    const std::string truncated = test::readBytes(dir.path() / "t.png").substr(0, 40);
    path = test::writeGltfFixture(dir.path(), "cut", GltfLayout::Glb, &truncated);
    scene = loadScene(path);
    ASSERT_FALSE(scene);
    EXPECT_NE(scene.status().message().find(path.string() + ": material 'Checker': texture '*0'"),
              std::string::npos)
        << scene.status().message();
    EXPECT_NE(scene.status().message().find("PNG"), std::string::npos) << scene.status().message();

    // OBJ: map_Kd names a missing file.
    dir.write("q.obj", std::string(kQuadsObj).replace(7, 5, "q"));
    dir.write("q.mtl", "newmtl Tex\nmap_Kd nothere.png\nnewmtl Plain\nKd 1 0 0\n");
    scene = loadScene(dir.path() / "q.obj", &strict);
    ASSERT_FALSE(scene);
    EXPECT_NE(
        scene.status().message().find("material 'Tex': texture 'nothere.png': file not found"),
        std::string::npos)
        << scene.status().message();
}

TEST(LoadScenePlacement, MatrixAndTransformScene) {
    Placement p;
    p.position = {1, 2, 3};
    p.scale = 2;
    p.yawDegrees = 90;
    const glm::vec3 x = glm::vec3(p.matrix() * glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(glm::length(x - glm::vec3(1, 2, 1)), 0.0f, 1e-5f);  // +X turns to -Z, doubled
    Scene s;
    s.lights = {Light{}};
    s.camera = SceneCamera{};
    s.instances.push_back({0, glm::mat4(1), Material{}});
    transformScene(s, p.matrix());
    EXPECT_TRUE(near(s.instances[0].worldFromModel, p.matrix()));
    EXPECT_NEAR(glm::length(s.lights[0].towardLight - glm::vec3(1, 0, 0)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::length(glm::vec3(s.camera->worldFromCamera[3]) - p.position), 0.0f, 1e-5f);
}

// The layout Blender's exporter writes (TRS quaternions, a rotated camera node, lights in the
// exporter's units, samplers 9729/9987 without wrap modes, external .bin and .png, extras,
// KHR_materials_specular / _ior) loads as its hand-written equivalent (node matrices, data
// URIs, nothing else), and both as the values computed here from the Blender scene.
TEST(LoadSceneBlender, ExporterLayoutEqualsHandWrittenAndTheBlenderValues) {
    using T = test::BlenderTruth;
    test::TempDir dir;
    const auto exported =
        test::writeBlenderGltf(dir.path(), "exported", test::BlenderLayout::Exporter);
    const auto hand = test::writeBlenderGltf(dir.path(), "hand", test::BlenderLayout::HandWritten);
    SceneLoadInfo infoE, infoH;
    auto e = loadScene(exported, &infoE);
    auto h = loadScene(hand, &infoH);
    ASSERT_TRUE(e) << e.status().message();
    ASSERT_TRUE(h) << h.status().message();
    EXPECT_TRUE(infoE.warnings.empty()) << infoE.warnings.front();
    EXPECT_TRUE(infoE.lightsFromFile);
    for (const Scene* s : {&*e, &*h}) {
        // Two instances of the cube, where the parent's and children's TRS put them.
        ASSERT_EQ(s->instances.size(), 2u);
        for (const glm::mat4& world : {T::parent().matrix() * T::childA().matrix(),
                                       T::parent().matrix() * T::childB().matrix()}) {
            const Instance* inst = findInstance(*s, world, true);
            ASSERT_NE(inst, nullptr);
            EXPECT_TRUE(inst->material.doubleSided);
            EXPECT_EQ(inst->material.sampler.magFilter, TextureFilter::Linear);
            EXPECT_EQ(inst->material.sampler.minFilter, TextureFilter::Linear);
            EXPECT_TRUE(inst->material.sampler.mipmaps);
            EXPECT_EQ(inst->material.sampler.wrapS, TextureWrap::Repeat);
            EXPECT_EQ(inst->material.sampler.wrapT, TextureWrap::Repeat);
        }
        ASSERT_EQ(s->textures.size(), 1u);
        EXPECT_EQ(s->textures[0].image, test::fixtureTexture());
        // The rotated camera: its node's transform, the yfov Blender's lens gives.
        ASSERT_TRUE(s->camera);
        EXPECT_TRUE(near(s->camera->worldFromCamera, T::camera().matrix()));
        EXPECT_NEAR(s->camera->yfovRadians, T::yfov(), 1e-5f);
        EXPECT_NEAR(s->camera->aspect, T::kAspect, 1e-5f);
        // The lights: the exporter's W -> lux / candela, the point lamp's cutoff distance as
        // range, the spot's cone from spot_size and spot_blend; directions along each node's -Z.
        ASSERT_EQ(s->lights.size(), 3u);
        const Light& sun = s->lights[0];
        const Light& point = s->lights[1];
        const Light& spot = s->lights[2];
        EXPECT_EQ(sun.type, LightType::Directional);
        EXPECT_EQ(point.type, LightType::Point);
        EXPECT_EQ(spot.type, LightType::Spot);
        EXPECT_NEAR(sun.color.x, 0.003f * 683.0f, 1e-4f);
        EXPECT_NEAR(sun.color.z, 0.9f * 0.003f * 683.0f, 1e-4f);
        const glm::vec3 sunAxis = glm::mat3(T::sun().matrix()) * glm::vec3(0, 0, -1);
        EXPECT_NEAR(glm::length(sun.towardLight + sunAxis), 0.0f, 1e-5f);
        EXPECT_NEAR(point.color.y, 0.06f / (4.0f * T::kPi) * 683.0f, 1e-4f);
        EXPECT_NEAR(point.range, 6.0f, 1e-6f);
        EXPECT_NEAR(glm::length(point.position - glm::vec3(0.5f, 2, 1)), 0.0f, 1e-5f);
        EXPECT_NEAR(spot.color.z, 0.1f / (4.0f * T::kPi) * 683.0f, 1e-4f);
        EXPECT_EQ(spot.range, 0.0f);  // no cutoff distance: infinite
        const float outer = glm::radians(60.0f) / 2.0f, inner = outer * 0.75f;
        EXPECT_NEAR(spot.outerConeCos, std::cos(outer), 1e-6f);
        EXPECT_NEAR(spot.innerConeCos, std::cos(inner), 1e-6f);
        const glm::vec3 spotAxis = glm::mat3(T::spot().matrix()) * glm::vec3(0, 0, -1);
        EXPECT_NEAR(glm::length(spot.towardLight + spotAxis), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::length(spot.position - glm::vec3(-1, 2.5f, 2)), 0.0f, 1e-5f);
    }
}

INSTANTIATE_TEST_SUITE_P(Layouts, GltfLayouts,
                         ::testing::Values(GltfLayout::External, GltfLayout::DataUri,
                                           GltfLayout::Glb));

}  // namespace
}  // namespace mvr
