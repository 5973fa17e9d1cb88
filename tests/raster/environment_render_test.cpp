// Image lighting in the soft backend (issue 39 item 2; environment.h, lighting.h
// environmentTerms): a white Lambertian quad under a uniform map shows the map's radiance in
// every shading and method; a mirror quad shows, at each pixel, the half of a split map that
// the reflection law (computed here from the rig's eye) points at; an occlusion map darkens the
// environment's light by its texel; unified == multipass bit for bit on the mapped, metallic
// and Blinn-Phong scenes under a map, at 2 to 45 views and in grids.
#include <cmath>

#include <gtest/gtest.h>

#include "../support/test_scenes.h"
#include "mvr/core/environment.h"
#include "mvr/core/lighting.h"
#include "mvr/raster/soft_backend.h"
#include "exactness.h"
#include "test_scenes.h"

namespace mvr::raster {
namespace {

std::shared_ptr<const Environment> environmentOf(glm::vec3 (*radiance)(glm::vec3)) {
    RadianceMap m;
    m.width = 128, m.height = 64;
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width; ++i)
            m.texels.push_back(radiance(equirectDirection((i + 0.5f) / m.width, (j + 0.5f) / m.height)));
    return std::make_shared<const Environment>(buildEnvironment(m));
}

/// A quad filling the identity rig's view, lit by `env` alone (no lights, no ambient).
Scene quadUnder(std::shared_ptr<const Environment> env) {
    Scene s = test::quadScene({-1, -1, 0.5f}, {1, 1, 0.5f});
    s.lights.clear();
    s.ambient = glm::vec3(0.0f);
    s.environment = std::move(env);
    return s;
}

TEST(EnvironmentRender, AUniformMapShowsItsRadianceOnAWhiteLambertianSurface) {
    const glm::vec3 c(0.2f, 0.5f, 0.8f);
    static glm::vec3 uniform;
    uniform = c;
    Scene scene = quadUnder(environmentOf([](glm::vec3) { return uniform; }));
    Material& m = scene.instances[0].material;
    m.albedo = glm::vec3(1.0f);
    m.specular = 0.0f;
    auto backend = makeSoftBackend();
    for (int mode = 0; mode < 3; ++mode) {
        for (const char* method : {"multipass", "unified"}) {
            RenderSettings s;
            s.width = s.height = 16;
            s.shading = Shading(mode);
            auto out = backend->render(scene, test::identityRig(2), s, method);
            ASSERT_TRUE(out) << out.status().message();
            const Rgba8 px = out->color[1].at(8, 8);
            EXPECT_NEAR(px.r, c.x * 255, 1.0) << method << " shading " << mode;
            EXPECT_NEAR(px.g, c.y * 255, 1.0) << method << " shading " << mode;
            EXPECT_NEAR(px.b, c.z * 255, 1.0) << method << " shading " << mode;
        }
    }
}

TEST(EnvironmentRender, AMirrorReflectsTheHalfOfTheMapTheReflectionLawPointsAt) {
    // +X half red, −X half blue; a white metal of roughness 0 facing +z.
    Scene scene = quadUnder(environmentOf([](glm::vec3 d) {
        return d.x > 0 ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 0.0f, 1.0f);
    }));
    Material& m = scene.instances[0].material;
    m.model = MaterialModel::MetallicRoughness;
    m.albedo = glm::vec3(1.0f);
    m.metallic = 1.0f, m.roughness = 0.0f;
    scene.meshes[0].normals.assign(4, glm::normalize(glm::vec3(0.0f, 0.0f, 1.0f)));
    const Rig rig = test::identityRig(1);
    const glm::vec3 eye = rig.centerEye();
    auto backend = makeSoftBackend();
    RenderSettings s;
    s.width = s.height = 32;
    s.shading = Shading::Pixel;
    auto out = backend->render(scene, rig, s, "unified");
    ASSERT_TRUE(out) << out.status().message();
    int checked = 0;
    for (int x = 1; x < 32; x += 3) {
        // The pixel's world point (identity rig: NDC = world), the view vector to the eye and
        // its mirror image about n = +z.
        const glm::vec3 p((x + 0.5f) / 16.0f - 1.0f, 0.0f, 0.5f);
        const glm::vec3 v = glm::normalize(eye - p), n(0, 0, 1);
        const glm::vec3 r = 2.0f * glm::dot(n, v) * n - v;
        if (std::abs(r.x) < 0.05f) continue;  // the seam, blurred by the bilinear lookups
        const Rgba8 px = out->color[0].at(x, 16);
        if (r.x > 0) {
            EXPECT_GT(px.r, 200) << x;
            EXPECT_LT(px.b, 20) << x;
        } else {
            EXPECT_GT(px.b, 200) << x;
            EXPECT_LT(px.r, 20) << x;
        }
        ++checked;
    }
    EXPECT_GE(checked, 8);
}

TEST(EnvironmentRender, AnOcclusionMapDarkensTheEnvironmentsLightByItsTexel) {
    static const glm::vec3 grey(0.6f);
    Scene scene = quadUnder(environmentOf([](glm::vec3) { return grey; }));
    scene.meshes[0].texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    Texture t;
    t.name = "occlusion";
    t.linear = true;
    t.image = Image(4, 4, Rgba8{128, 255, 255, 255});
    scene.textures = {t};
    auto backend = makeSoftBackend();
    RenderSettings s;
    s.width = s.height = 16;
    s.shading = Shading::Pixel;
    for (const MaterialModel model : {MaterialModel::MetallicRoughness, MaterialModel::BlinnPhong}) {
        Material& m = scene.instances[0].material;
        m.model = model;
        m.albedo = glm::vec3(1.0f);
        m.metallic = 0.0f, m.roughness = 1.0f;
        m.occlusionTexture = 0;
        m.occlusionStrength = 1.0f;
        auto with = backend->render(scene, test::identityRig(1), s, "multipass");
        scene.instances[0].material.occlusionTexture = -1;
        auto without = backend->render(scene, test::identityRig(1), s, "multipass");
        ASSERT_TRUE(with && without);
        // The whole environment term scales by the occlusion (128 / 255), diffuse and specular.
        const double ratio =
            double(with->color[0].at(8, 8).g) / double(without->color[0].at(8, 8).g);
        EXPECT_NEAR(ratio, 128.0 / 255.0, 0.02) << int(model);
    }
}

TEST(EnvironmentRender, UnifiedEqualsMultipassUnderAMap) {
    auto backend = makeSoftBackend();
    const Scene scenes[] = {mvr::test::withEnvironment(mvr::test::mappedScene()),
                            mvr::test::withEnvironment(mvr::test::pbrScene()),
                            mvr::test::withEnvironment(mvr::test::defaultScene())};
    Camera cam;
    cam.position = {0.5f, 1.8f, 6.0f};
    cam.aspect = 72.0f / 54.0f;
    for (const Scene& scene : scenes) {
        test::expectUnifiedEqualsMultipass(*backend, scene, {{2, 1}, {5, 1}, {16, 1}, {45, 1}, {3, 2}},
                                           72, 54);
        // The map changes the image (the test would pass with it ignored otherwise).
        Scene without = scene;
        without.environment.reset();
        RenderSettings s;
        s.width = 72, s.height = 54;
        RigParams p;
        auto rig = makeRig(cam, p);
        auto a = backend->render(scene, *rig, s, "unified");
        auto b = backend->render(without, *rig, s, "unified");
        ASSERT_TRUE(a && b);
        EXPECT_NE(a->color[0].rgba, b->color[0].rgba);
    }
}

}  // namespace
}  // namespace mvr::raster
