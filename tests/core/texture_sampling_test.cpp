// Texture sampling (texture_sampling.h) and point / spot lights (lighting.h) against values
// computed independently here (in double, from the formulas of the GL spec, IEC 61966-2-1 and
// KHR_lights_punctual).
#include <cmath>

#include <gtest/gtest.h>

#include "mvr/core/lighting.h"
#include "mvr/core/texture_sampling.h"

namespace mvr {
namespace {

double srgbRef(int b) {
    const double c = b / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// A w×h texture whose texel (i, j) has red = i·16 + 8, green = j·16 + 8 (sRGB bytes).
Image gradientImage(int w, int h) {
    Image im(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            im.set(i, j, Rgba8{std::uint8_t(i * 16 + 8), std::uint8_t(j * 16 + 8), 0, 255});
    return im;
}

TEST(TextureSampling, SrgbDecodeIsTheExactCurve) {
    EXPECT_EQ(srgbToLinear(0), 0.0f);
    EXPECT_EQ(srgbToLinear(255), 1.0f);
    for (int b = 0; b < 256; ++b) EXPECT_NEAR(srgbToLinear(std::uint8_t(b)), srgbRef(b), 1e-7);
    EXPECT_NEAR(srgbToLinear(10), 10.0 / 255.0 / 12.92, 1e-9);  // linear segment
    EXPECT_NEAR(srgbToLinear(128), 0.2158605, 1e-6);            // the familiar 0.216
}

TEST(TextureSampling, WrapModes) {
    // Repeat
    EXPECT_EQ(wrapTexel(0, 4, TextureWrap::Repeat), 0);
    EXPECT_EQ(wrapTexel(4, 4, TextureWrap::Repeat), 0);
    EXPECT_EQ(wrapTexel(-1, 4, TextureWrap::Repeat), 3);
    EXPECT_EQ(wrapTexel(-5, 4, TextureWrap::Repeat), 3);
    // ClampToEdge
    EXPECT_EQ(wrapTexel(-1, 4, TextureWrap::ClampToEdge), 0);
    EXPECT_EQ(wrapTexel(9, 4, TextureWrap::ClampToEdge), 3);
    // MirroredRepeat: ... 1 0 | 0 1 2 3 | 3 2 1 0 | 0 1 ...
    const int expect[12] = {1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0, 1};
    for (int i = -2; i < 10; ++i)
        EXPECT_EQ(wrapTexel(i, 4, TextureWrap::MirroredRepeat), expect[i + 2]) << i;
}

TEST(TextureSampling, NearestAndBilinearAtKnownCoordinates) {
    const Image image = gradientImage(4, 4);
    const MipChain chain = buildMipChain(image, false);
    ASSERT_EQ(chain.levels.size(), 1u);
    TextureSampler s;
    // Texel (2, 1)'s centre is uv ((2 + ½)/4, (1 + ½)/4): nearest and bilinear both give it.
    const glm::vec2 c(2.5f / 4, 1.5f / 4);
    const glm::vec4 n = sampleNearest(chain.levels[0], c, s);
    EXPECT_FLOAT_EQ(n.x, float(srgbRef(2 * 16 + 8)));
    EXPECT_FLOAT_EQ(n.y, float(srgbRef(1 * 16 + 8)));
    EXPECT_FLOAT_EQ(n.w, 1.0f);
    const glm::vec4 b = sampleBilinear(chain.levels[0], c, s);
    EXPECT_NEAR(b.x, srgbRef(40), 1e-6);
    // Halfway between texel columns 1 and 2, row 1: the mean of their linear values.
    const glm::vec4 h = sampleBilinear(chain.levels[0], glm::vec2(2.0f / 4, 1.5f / 4), s);
    EXPECT_NEAR(h.x, 0.5 * (srgbRef(24) + srgbRef(40)), 1e-6);
    // Repeat across the u = 0 edge: between column 3 and column 0.
    const glm::vec4 e = sampleBilinear(chain.levels[0], glm::vec2(0.0f, 1.5f / 4), s);
    EXPECT_NEAR(e.x, 0.5 * (srgbRef(56) + srgbRef(8)), 1e-6);
    // ClampToEdge at the same place: column 0 alone.
    s.wrapS = TextureWrap::ClampToEdge;
    const glm::vec4 k = sampleBilinear(chain.levels[0], glm::vec2(0.0f, 1.5f / 4), s);
    EXPECT_NEAR(k.x, srgbRef(8), 1e-6);
    // Nearest, u = 1.1 repeats to texel column 0 (floor(4.4) = 4 → 0).
    s.wrapS = TextureWrap::Repeat;
    EXPECT_FLOAT_EQ(sampleNearest(chain.levels[0], glm::vec2(1.1f, 0.1f), s).x, float(srgbRef(8)));
}

TEST(TextureSampling, MipChainBoxFiltersInLinearSpace) {
    Image im(2, 2);
    im.set(0, 0, {255, 255, 255, 255});
    im.set(1, 0, {0, 0, 0, 255});
    im.set(0, 1, {0, 0, 0, 0});
    im.set(1, 1, {255, 255, 255, 255});
    const MipChain chain = buildMipChain(im, true);
    ASSERT_EQ(chain.levels.size(), 2u);
    EXPECT_EQ(chain.levels[1].width, 1);
    EXPECT_FLOAT_EQ(chain.levels[1].texels[0].x, 0.5f);   // linear mean of 1, 0, 0, 1
    EXPECT_FLOAT_EQ(chain.levels[1].texels[0].w, 0.75f);  // straight alpha mean
    // 5×3: levels 5×3, 2×1, 1×1 (GL sizes floor(w/2), at least 1).
    const Image oddImage = gradientImage(5, 3);
    const MipChain odd = buildMipChain(oddImage, true);
    ASSERT_EQ(odd.levels.size(), 3u);
    EXPECT_EQ(odd.levels[1].width, 2);
    EXPECT_EQ(odd.levels[1].height, 1);
    EXPECT_EQ(odd.levels[2].width, 1);
}

TEST(TextureSampling, LevelOfDetailFromDerivatives) {
    UvDerivatives d;
    // One texel per pixel on a 256² texture: ρ = 1, λ = 0.
    d.dx = glm::vec2(1.0f / 256, 0.0f), d.dy = glm::vec2(0.0f, 1.0f / 256);
    EXPECT_FLOAT_EQ(textureLod(d, 256, 256), 0.0f);
    // 4 texels per pixel in x, 1 in y: ρ = max(4, 1), λ = 2.
    d.dx = glm::vec2(4.0f / 256, 0.0f);
    EXPECT_FLOAT_EQ(textureLod(d, 256, 256), 2.0f);
    // Diagonal derivative (3, 4) texels: length 5, λ = log2 5.
    d.dx = glm::vec2(3.0f / 256, 4.0f / 128), d.dy = glm::vec2(0.0f);
    EXPECT_NEAR(textureLod(d, 256, 128), std::log2(5.0), 1e-6);
    // Zero derivatives: magnification.
    EXPECT_TRUE(samplerMagnifies(TextureSampler{}, textureLod(UvDerivatives{}, 8, 8)));
}

TEST(TextureSampling, PerspectiveDerivativesMatchFiniteDifferences) {
    // u = Σ l_i q_i u_i / Σ l_i q_i with l affine in x: compare with a central difference.
    const float q[3] = {1.0f, 0.5f, 0.25f};
    const glm::vec2 uv[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};
    const float gx[3] = {-0.01f, 0.01f, 0.0f}, gy[3] = {-0.02f, 0.0f, 0.02f};
    auto at = [&](double x, double y, int c) {
        const double l1 = 0.2 + 0.01 * x, l2 = 0.3 + 0.02 * y, l0 = 1 - l1 - l2;
        const double p[3] = {l0 * q[0], l1 * q[1], l2 * q[2]};
        return (p[0] * uv[0][c] + p[1] * uv[1][c] + p[2] * uv[2][c]) / (p[0] + p[1] + p[2]);
    };
    const double l1 = 0.2, l2 = 0.3, l0 = 0.5;
    const float inv = float(1.0 / (l0 * q[0] + l1 * q[1] + l2 * q[2]));
    const glm::vec2 u(float(at(0, 0, 0)), float(at(0, 0, 1)));
    const UvDerivatives d = uvDerivatives(gx, gy, q, uv, u, inv);
    for (int c = 0; c < 2; ++c) {
        EXPECT_NEAR(d.dx[c], (at(1e-3, 0, c) - at(-1e-3, 0, c)) / 2e-3, 1e-5);
        EXPECT_NEAR(d.dy[c], (at(0, 1e-3, c) - at(0, -1e-3, c)) / 2e-3, 1e-5);
    }
}

TEST(TextureSampling, TrilinearMixesLevels) {
    const Image image = gradientImage(4, 4);
    const MipChain chain = buildMipChain(image, true);
    ASSERT_EQ(chain.levels.size(), 3u);
    TextureSampler s;
    const glm::vec2 uv(0.5f, 0.5f);
    const glm::vec4 l0 = sampleBilinear(chain.levels[0], uv, s);
    const glm::vec4 l1 = sampleBilinear(chain.levels[1], uv, s);
    const glm::vec4 t = sampleTexture(chain, s, uv, 0.25f);
    EXPECT_NEAR(t.x, 0.75 * l0.x + 0.25 * l1.x, 1e-6);
    // λ beyond the last level: the 1×1 level, the mean of all 16 linear texels.
    double mean = 0;
    for (int i = 0; i < 4; ++i) mean += srgbRef(i * 16 + 8);
    EXPECT_NEAR(sampleTexture(chain, s, uv, 9.0f).x, mean / 4, 1e-6);
    // Magnification (λ < 0) uses level 0 with the mag filter.
    s.magFilter = TextureFilter::Nearest;
    EXPECT_FLOAT_EQ(sampleTexture(chain, s, glm::vec2(0.1f, 0.1f), -1.0f).x, float(srgbRef(8)));
}

TEST(Lights, PointAndSpotFollowKhrLightsPunctual) {
    Light point;
    point.type = LightType::Point;
    point.position = glm::vec3(0.0f, 2.0f, 0.0f);
    point.color = glm::vec3(1.0f);
    point.range = 4.0f;
    const LightSample s = lightAt(point, glm::vec3(0.0f));
    EXPECT_FLOAT_EQ(s.toLight.y, 1.0f);
    // d = 2, range 4: (1 − (2/4)^4) / 4 = (15/16) / 4.
    EXPECT_NEAR(s.attenuation, (15.0 / 16.0) / 4.0, 1e-7);
    point.range = 0.0f;  // infinite: 1/d²
    EXPECT_NEAR(lightAt(point, glm::vec3(0.0f)).attenuation, 0.25, 1e-7);
    point.range = 1.0f;  // beyond range: 0
    EXPECT_EQ(lightAt(point, glm::vec3(0.0f)).attenuation, 0.0f);

    Light spot = point;
    spot.type = LightType::Spot;
    spot.range = 0.0f;
    spot.towardLight = glm::vec3(0.0f, 1.0f, 0.0f);  // axis straight down
    spot.innerConeCos = std::cos(0.2f);
    spot.outerConeCos = std::cos(0.6f);
    EXPECT_NEAR(lightAt(spot, glm::vec3(0.0f)).attenuation, 0.25, 1e-6);  // on the axis
    // At 0.4 rad off the axis: t = (cos 0.4 − cos 0.6) / (cos 0.2 − cos 0.6), attenuation t²/d².
    const double a = 0.4, d = 2.0 / std::cos(a);
    const glm::vec3 p(float(2.0 * std::tan(a)), 0.0f, 0.0f);
    const double t = (std::cos(a) - std::cos(0.6)) / (std::cos(0.2) - std::cos(0.6));
    EXPECT_NEAR(lightAt(spot, p).attenuation, t * t / (d * d), 1e-5);
    // Outside the outer cone: 0.
    EXPECT_EQ(lightAt(spot, glm::vec3(3.0f, 0.0f, 0.0f)).attenuation, 0.0f);

    // Flat with a point light above a floor: ambient + n·l · att · albedo.
    ShadingContext ctx;
    ctx.ambient = glm::vec3(0.1f);
    point.range = 0.0f;
    Light lights[1] = {point};
    ctx.lights = lights;
    Material m(glm::vec3(0.5f));
    const glm::vec3 c = shadeFlat(ctx, m, glm::vec3(0, 1, 0), glm::vec3(0.0f));
    EXPECT_NEAR(c.x, 0.1 * 0.5 + 1.0 * 0.25 * 0.5, 1e-6);
    // The textured form gives the same for a white texel.
    const glm::vec3 tc =
        shadeTextured(m.albedo, flatTerms(ctx, m, glm::vec3(0, 1, 0), glm::vec3(0.0f)));
    EXPECT_NEAR(tc.x, c.x, 1e-6);
}

TEST(Lights, DoubleSidedFlipsTowardTheCenterEye) {
    ShadingContext ctx;
    ctx.centerEye = glm::vec3(0.0f, 0.0f, -5.0f);
    Material m;
    EXPECT_EQ(facingNormal(ctx, m, glm::vec3(0, 0, 1), glm::vec3(0.0f)), glm::vec3(0, 0, 1));
    m.doubleSided = true;
    EXPECT_EQ(facingNormal(ctx, m, glm::vec3(0, 0, 1), glm::vec3(0.0f)), glm::vec3(0, 0, -1));
    EXPECT_EQ(facingNormal(ctx, m, glm::vec3(0, 0, -1), glm::vec3(0.0f)), glm::vec3(0, 0, -1));
}

}  // namespace
}  // namespace mvr
