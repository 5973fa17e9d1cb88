// KHR_texture_transform rendered (issue 39 item 4): a glTF quad filling the view, textured with
// a 2×2 texture of four colours sampled NEAREST with REPEAT, loaded with an offset of 0.5 or a
// rotation of 90°: each sampled pixel shows the texel that the extension's formula, computed
// here from the pixel's texture coordinate, picks; soft:unified == soft:multipass.
#include <cmath>
#include <numbers>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/io/scene_io.h"
#include "mvr/raster/soft_backend.h"
#include "test_scenes.h"
#include "texture_transform_fixture.h"

namespace mvr {
namespace {

constexpr int kSize = 64;

/// The texel (x, y) of the 2×2 texture that uv lands in with REPEAT.
glm::ivec2 texelAt(glm::dvec2 uv) {
    const glm::dvec2 wrapped = uv - glm::floor(uv);
    return {int(std::floor(wrapped.x * 2.0)), int(std::floor(wrapped.y * 2.0))};
}

void expectTexels(const std::string& what, const std::string& extension, glm::dvec2 offset,
                  double rotation) {
    test::TempDir dir("mvr-texture-transform-render");
    test::TransformQuadOptions o;
    o.baseColorTextureExtra = extension;
    auto loaded = loadScene(test::writeTransformQuad(dir.path(), "quad", o));
    ASSERT_TRUE(loaded) << loaded.status().message();
    Scene scene = std::move(loaded).value();
    // Lit along the normal with ambient 0.1 and no specular: every channel is 0 or
    // min(1, 1.1 · 1) = 1, so a pixel is its texel's colour exactly (Blinn-Phong: the file's
    // metallic-roughness material has a specular lobe of its own).
    scene.instances[0].material.model = MaterialModel::BlinnPhong;
    Light l;
    l.towardLight = {0, 0, 1};
    scene.lights = {l};
    scene.ambient = glm::vec3(0.1f);
    scene.instances[0].material.specular = 0.0f;
    const Rig rig = raster::test::identityRig(1);
    RenderSettings s;
    s.width = s.height = kSize;
    s.shading = Shading::Pixel;
    auto backend = raster::makeSoftBackend();
    auto out = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(out) << out.status().message();
    auto unified = backend->render(scene, rig, s, "unified");
    ASSERT_TRUE(unified) << unified.status().message();
    EXPECT_EQ(out->color[0].rgba, unified->color[0].rgba) << what;
    const Image texture = test::twoByTwoTexture();
    const double c = std::cos(rotation), sn = std::sin(rotation);
    // Pixel centres 4 + 8k: their texture coordinates stay 1/16 away from the texel edges.
    for (int py = 4; py < kSize; py += 8) {
        for (int px = 4; px < kSize; px += 8) {
            // The identity rig: NDC = world; TEXCOORD_0 = ((x + 1) / 2, (1 − y) / 2).
            const glm::dvec2 uv((px + 0.5) / kSize, (py + 0.5) / kSize);
            // uv' = T · R · S · uv, R's rows (cos r, sin r), (−sin r, cos r); scale 1.
            const glm::dvec2 t = offset + glm::dvec2(c * uv.x + sn * uv.y, -sn * uv.x + c * uv.y);
            const glm::ivec2 texel = texelAt(t);
            const Rgba8 want = texture.at(texel.x, texel.y);
            const Rgba8 got = out->color[0].at(px, py);
            EXPECT_EQ(got.r, want.r) << what << " pixel " << px << "," << py;
            EXPECT_EQ(got.g, want.g) << what << " pixel " << px << "," << py;
            EXPECT_EQ(got.b, want.b) << what << " pixel " << px << "," << py;
        }
    }
}

TEST(TextureTransformRender, OffsetHalfShowsTheTexelTheFormulaPicks) {
    expectTexels("offset 0.5", R"(,"extensions":{"KHR_texture_transform":{"offset":[0.5,0]}})",
                 {0.5, 0.0}, 0.0);
}

TEST(TextureTransformRender, Rotation90ShowsTheTexelTheFormulaPicks) {
    expectTexels("rotation 90",
                 R"(,"extensions":{"KHR_texture_transform":{"rotation":1.5707963267948966}})",
                 {0.0, 0.0}, std::numbers::pi / 2);
}

TEST(TextureTransformRender, UntransformedQuadShowsTheTextureAsIs) {
    // The baseline the two above depart from: without the extension, the top-left quarter of
    // the view is texel (0, 0) (red) and so on.
    expectTexels("none", "", {0.0, 0.0}, 0.0);
}

}  // namespace
}  // namespace mvr
