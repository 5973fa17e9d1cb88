// Textured shading in the soft backend (issue 14): unified == multipass bit for bit on textured
// scenes (every shading mode, culling, wireframe, rows and grids, 2..45 views, alpha modes,
// double-sided, point and spot lights), and a texel sampled at a known texture coordinate shows
// up where an independently computed projection puts it, with the color the lighting model
// gives.
#include <cstring>
#include <random>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/core/lighting.h"
#include "mvr/core/texture_sampling.h"
#include "mvr/raster/soft_backend.h"
#include "test_scenes.h"

namespace mvr::raster {
namespace {

std::string difference(const RenderOutput& a, const RenderOutput& b) {
    if (a.color.size() != b.color.size()) return "view count";
    for (std::size_t v = 0; v < a.color.size(); ++v) {
        if (a.color[v].rgba != b.color[v].rgba) {
            for (std::size_t i = 0; i < a.color[v].rgba.size(); ++i)
                if (a.color[v].rgba[i] != b.color[v].rgba[i])
                    return fmt::format("view {} color byte {}: {} vs {}", v, i, a.color[v].rgba[i],
                                       b.color[v].rgba[i]);
        }
        if (std::memcmp(a.depth[v].depth.data(), b.depth[v].depth.data(),
                        a.depth[v].depth.size() * sizeof(float)) != 0)
            return fmt::format("view {} depth", v);
    }
    return "";
}

void expectSame(Backend& backend, const Scene& scene, const Rig& rig, const RenderSettings& s) {
    auto mp = backend.render(scene, rig, s, "multipass");
    ASSERT_TRUE(mp) << mp.status().message();
    auto un = backend.render(scene, rig, s, "unified");
    ASSERT_TRUE(un) << un.status().message();
    ASSERT_EQ(difference(*mp, *un), "")
        << "views " << rig.viewCount() << " " << rig.columns << "x" << rig.rows << " shading "
        << int(s.shading) << " cull " << s.cullBackFaces << " wireframe " << s.wireframe;
}

Camera texturedCamera(float aspect) {
    Camera cam;
    cam.position = {0.5f, 1.8f, 6.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.aspect = aspect;
    return cam;
}

/// The textured scene with the extras every path must handle: a masked, a blended and a
/// double-sided instance, a point and a spot light.
Scene richTexturedScene() {
    Scene scene = makeTexturedScene();
    const std::size_t n = scene.instances.size();
    for (std::size_t i = 0; i < n; ++i) {
        Instance extra = scene.instances[i];
        extra.worldFromModel =
            glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0.4f, 0.8f)) * extra.worldFromModel;
        if (i % 3 == 0) extra.material.alphaMode = AlphaMode::Mask, extra.material.alpha = 0.9f;
        if (i % 3 == 1) extra.material.alphaMode = AlphaMode::Blend, extra.material.alpha = 0.5f;
        if (i % 3 == 2) extra.material.doubleSided = true;
        extra.material.sampler.wrapS = TextureWrap(i % 3);
        extra.material.sampler.minFilter = TextureFilter(i % 2);
        extra.material.sampler.magFilter = TextureFilter((i / 2) % 2);
        scene.instances.push_back(extra);
    }
    Light point;
    point.type = LightType::Point;
    point.position = {1.0f, 2.0f, 2.0f};
    point.color = glm::vec3(4.0f);
    point.range = 8.0f;
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {-1.5f, 3.0f, 1.0f};
    spot.towardLight = glm::normalize(glm::vec3(-1.5f, 3.0f, 1.0f));
    spot.color = glm::vec3(6.0f);
    spot.innerConeCos = 0.95f, spot.outerConeCos = 0.8f;
    scene.lights.resize(2);
    scene.lights.push_back(point);
    scene.lights.push_back(spot);
    return scene;
}

TEST(TexturedUnifiedEqualsMultipass, TexturedSceneRowsAndGrids) {
    auto backend = makeSoftBackend();
    for (const Scene& scene : {makeTexturedScene(), richTexturedScene()}) {
        const Camera cam = texturedCamera(72.0f / 54.0f);
        for (int views : {2, 3, 5, 9, 16, 45}) {
            for (int mode = 0; mode < 6; ++mode) {
                RenderSettings s;
                s.width = 72, s.height = 54;
                s.shading = static_cast<Shading>(mode % 3);
                s.cullBackFaces = mode >= 3;
                s.wireframe = views == 3 && mode < 3;
                RigParams p;
                p.columns = views, p.rows = 1, p.interaxial = 0.15f, p.convergence = 6.0f;
                auto rig = makeRig(cam, p);
                ASSERT_TRUE(rig);
                expectSame(*backend, scene, *rig, s);
            }
        }
        for (auto [c, r] : {std::pair{2, 2}, {3, 3}, {4, 2}}) {
            RigParams p;
            p.columns = c, p.rows = r, p.interaxial = 0.3f, p.convergence = 6.0f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig);
            RenderSettings s;
            s.width = 64, s.height = 48;
            for (int mode = 0; mode < 3; ++mode) {
                s.shading = static_cast<Shading>(mode);
                s.cullBackFaces = mode == 1;
                expectSame(*backend, scene, *rig, s);
                s.wireframe = true;
                expectSame(*backend, scene, *rig, s);
                s.wireframe = false;
            }
        }
    }
}

TEST(TexturedUnifiedEqualsMultipass, StreamedBands) {
    // Textured fragments with every band streamed (SoftOptions::streamAboveBytes = 0: drawn into
    // the workers' scratch, then copied into the images).
    auto backend = makeSoftBackend(SoftOptions{.streamAboveBytes = 0});
    for (const Scene& scene : {makeTexturedScene(), richTexturedScene()}) {
        const Camera cam = texturedCamera(72.0f / 54.0f);
        for (auto [c, r] : {std::pair{3, 1}, {45, 1}, {3, 3}}) {
            for (int mode = 0; mode < 4; ++mode) {
                RenderSettings s;
                s.width = 72, s.height = 54;
                s.shading = static_cast<Shading>(mode % 3);
                s.cullBackFaces = mode == 1;
                s.wireframe = mode == 3;
                RigParams p;
                p.columns = c, p.rows = r, p.interaxial = 0.15f, p.convergence = 6.0f;
                auto rig = makeRig(cam, p);
                ASSERT_TRUE(rig);
                expectSame(*backend, scene, *rig, s);
            }
        }
    }
}

TEST(TexturedUnifiedEqualsMultipass, RandomTexturedSoups) {
    auto backend = makeSoftBackend();
    std::mt19937 rng(1414);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int i = 0; i < 30; ++i) {
        SCOPED_TRACE(fmt::format("case {}", i));
        Scene scene = richTexturedScene();
        scene.meshes.clear();
        scene.instances.resize(4);
        Mesh m;
        m.name = "soup";
        const int count = 30 + int(rng() % 40);
        for (int t = 0; t < count; ++t) {
            const float scale = t % 9 == 0 ? 50.0f : 1.5f;
            const glm::vec3 c(u(rng) * 3.0f, u(rng) * 2.0f, u(rng) * 4.0f);
            for (int k = 0; k < 3; ++k) {
                m.positions.push_back(c + glm::vec3(u(rng), u(rng), u(rng)) * scale);
                m.normals.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.0f)));
                m.texcoords.push_back(glm::vec2(u(rng), u(rng)) * 3.0f);
                m.indices.push_back(std::uint32_t(m.positions.size() - 1));
            }
        }
        scene.meshes = {m};
        for (std::size_t k = 0; k < scene.instances.size(); ++k) {
            scene.instances[k].mesh = 0;
            scene.instances[k].worldFromModel =
                glm::translate(glm::mat4(1.0f), glm::vec3(float(k) * 0.3f, 0.0f, -float(k)));
        }
        RenderSettings s;
        s.width = 48 + int(rng() % 30), s.height = 32 + int(rng() % 20);
        s.shading = static_cast<Shading>(i % 3);
        s.cullBackFaces = (i / 3) % 2 == 1;
        s.wireframe = i % 10 == 9;
        Camera cam = texturedCamera(float(s.width) / float(s.height));
        cam.position = {u(rng), u(rng), 6.0f};
        RigParams p;
        p.columns = 2 + int(rng() % 8), p.rows = i % 4 == 0 ? 2 : 1;
        p.interaxial = 0.2f, p.convergence = 5.0f;
        auto rig = makeRig(cam, p);
        ASSERT_TRUE(rig);
        expectSame(*backend, scene, *rig, s);
    }
}

/// A full-screen quad in an identity rig (NDC = world), textured with a 4×4 texture sampled
/// NEAREST: texel (i, j) covers image pixels [16i, 16i + 16) × [16j, 16j + 16) of a 64×64
/// image (uv (0, 0) = top-left). Lit by one directional light along the normal, ambient 0.1.
Scene texelQuadScene(AlphaMode mode, float alpha) {
    Scene scene = test::quadScene({-1, -1, 0.5f}, {1, 1, 0.5f});
    scene.meshes[0].texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    Texture tex;
    tex.name = "4x4";
    tex.image = Image(4, 4);
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            tex.image.set(i, j,
                          Rgba8{std::uint8_t(30 + 60 * i), std::uint8_t(20 + 70 * j), 200,
                                std::uint8_t(i < 2 ? 255 : 40)});
    scene.textures = {tex};
    Material& m = scene.instances[0].material;
    m.albedo = {0.5f, 0.6f, 0.7f};
    m.specular = 0.0f;
    m.baseColorTexture = 0;
    m.sampler.magFilter = m.sampler.minFilter = TextureFilter::Nearest;
    m.alphaMode = mode;
    m.alpha = alpha;
    Light l;
    l.towardLight = {0, 0, 1};
    l.color = glm::vec3(1.0f);
    scene.lights = {l};
    scene.ambient = glm::vec3(0.1f);
    return scene;
}

TEST(TexturedShading, TexelAppearsWhereTheProjectionPutsIt) {
    auto backend = makeSoftBackend();
    const Rig rig = test::identityRig(1);
    for (int mode = 0; mode < 3; ++mode) {
        const Scene scene = texelQuadScene(AlphaMode::Opaque, 1.0f);
        RenderSettings s;
        s.width = s.height = 64;
        s.shading = static_cast<Shading>(mode);
        auto out = backend->render(scene, rig, s, "multipass");
        ASSERT_TRUE(out) << out.status().message();
        for (int j = 0; j < 4; ++j) {
            for (int i = 0; i < 4; ++i) {
                const Rgba8 t = scene.textures[0].image.at(i, j);
                const Rgba8 px = out->color[0].at(16 * i + 8, 16 * j + 8);
                // D = ambient 0.1 + n·l 1 = 1.1; color = albedo · linear(texel) · D.
                const std::uint8_t* ch[3] = {&t.r, &t.g, &t.b};
                const std::uint8_t got[3] = {px.r, px.g, px.b};
                for (int c = 0; c < 3; ++c) {
                    const double lin = srgbToLinear(*ch[c]);
                    const double want =
                        std::min(1.0, scene.instances[0].material.albedo[c] * lin * 1.1);
                    EXPECT_NEAR(got[c], want * 255.0, 0.6)
                        << "texel " << i << "," << j << " channel " << c << " mode " << mode;
                }
            }
        }
    }
}

TEST(TexturedShading, MaskDiscardsAndBlendMixes) {
    auto backend = makeSoftBackend();
    const Rig rig = test::identityRig(1);
    RenderSettings s;
    s.width = s.height = 64;
    s.shading = Shading::Pixel;
    s.clearColor = {0.2f, 0.4f, 0.6f};
    {
        const Scene scene = texelQuadScene(AlphaMode::Mask, 1.0f);
        auto out = backend->render(scene, rig, s, "multipass");
        ASSERT_TRUE(out);
        // Columns 0, 1 are opaque (alpha 255), 2, 3 have alpha 40/255 < 0.5: discarded.
        EXPECT_LT(out->depth[0].depth[8 * 64 + 8], 1.0f);
        const Rgba8 bg = out->color[0].at(56, 8);
        EXPECT_EQ(bg.r, quantizeUnorm8(0.2f));
        EXPECT_EQ(bg.b, quantizeUnorm8(0.6f));
        EXPECT_EQ(out->depth[0].depth[8 * 64 + 56], 1.0f);
    }
    {
        const Scene scene = texelQuadScene(AlphaMode::Blend, 0.5f);
        auto out = backend->render(scene, rig, s, "multipass");
        ASSERT_TRUE(out);
        // Blend writes no depth; color = src·a + clear·(1 − a), a = 0.5 · texel alpha.
        EXPECT_EQ(out->depth[0].depth[8 * 64 + 8], 1.0f);
        const Rgba8 t = scene.textures[0].image.at(0, 0);
        const double a = 0.5;
        const double src = std::min(1.0, 0.5 * double(srgbToLinear(t.r)) * 1.1);
        const double dst = quantizeUnorm8(0.2f) / 255.0;
        EXPECT_NEAR(out->color[0].at(8, 8).r, (src * a + dst * (1 - a)) * 255.0, 0.6);
    }
}

TEST(TexturedShading, DoubleSidedIsNotCulledAndLitFromTheFront) {
    auto backend = makeSoftBackend();
    const Rig rig = test::identityRig(1);
    RenderSettings s;
    s.width = s.height = 32;
    s.cullBackFaces = true;
    s.shading = Shading::Flat;
    Scene scene = test::quadScene({-1, -1, 0.5f}, {1, 1, 0.5f});
    // Reverse the winding: the quad faces away (clockwise on screen).
    scene.meshes[0].indices = {0, 2, 1, 0, 3, 2};
    scene.meshes[0].normals.assign(4, {0, 0, -1});
    Light l;
    l.towardLight = {0, 0, 1};
    scene.lights = {l};
    auto culled = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(culled);
    EXPECT_EQ(culled->depth[0].depth[16 * 32 + 16], 1.0f);
    scene.instances[0].material.doubleSided = true;
    auto drawn = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(drawn);
    EXPECT_LT(drawn->depth[0].depth[16 * 32 + 16], 1.0f);
    // The identity rig's centre eye is at the origin (in front of z = 0.5? see rig): whichever
    // side it is on, the lit face is the one toward it, so the color is not the ambient only
    // unless the light is behind that face. Compare with lighting.h directly.
    ShadingContext ctx;
    ctx.lights = scene.lights;
    ctx.ambient = scene.ambient;
    ctx.centerEye = rig.centerEye();
    const glm::vec3 want =
        shadeFlat(ctx, scene.instances[0].material, glm::vec3(0, 0, -1), glm::vec3(0, 0, 0.5f));
    const Rgba8 px = drawn->color[0].at(16, 16);
    EXPECT_EQ(px.r, quantizeUnorm8(want.x));
}

}  // namespace
}  // namespace mvr::raster
