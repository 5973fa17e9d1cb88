#include "mvr/composite/anaglyph.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "test_views.h"

namespace mvr::composite {
namespace {
using namespace mvr::composite::test;

// Independent double-precision reference of the documented per-pixel formula.
double decodeRef(int v) {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
int encodeRef(double l) {
    l = std::min(1.0, std::max(0.0, l));
    const double c = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
    return static_cast<int>(std::floor(c * 255.0 + 0.5));
}
Rgba8 reference(const double ml[9], const double mr[9], Rgba8 a, Rgba8 b) {
    const double l[3] = {decodeRef(a.r), decodeRef(a.g), decodeRef(a.b)};
    const double r[3] = {decodeRef(b.r), decodeRef(b.g), decodeRef(b.b)};
    int o[3];
    for (int row = 0; row < 3; ++row) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += ml[row * 3 + k] * l[k] + mr[row * 3 + k] * r[k];
        o[row] = encodeRef(s);
    }
    return {static_cast<std::uint8_t>(o[0]), static_cast<std::uint8_t>(o[1]),
            static_cast<std::uint8_t>(o[2]), 255};
}

// Dubois 2009 least-squares matrices, typed from the source independently of anaglyph.cpp.
const double kDuboisRcL[9] = {0.437, 0.449, 0.164, -0.062, -0.062, -0.024, -0.048, -0.050, -0.017};
const double kDuboisRcR[9] = {-0.011, -0.032, -0.007, 0.377, 0.761, 0.009, -0.026, -0.093, 1.234};
const double kDuboisGmL[9] = {-0.062, -0.158, -0.039, 0.284, 0.668, 0.143, -0.015, -0.027, 0.021};
const double kDuboisGmR[9] = {0.529, 0.705, 0.024, -0.016, -0.015, -0.065, 0.009, 0.075, 0.937};
const double kDuboisAbL[9] = {1.062, -0.205, 0.299, -0.026, 0.908, 0.068, -0.038, -0.173, 0.022};
const double kDuboisAbR[9] = {-0.016, -0.123, -0.017, 0.006, 0.062, -0.017, 0.094, 0.185, 0.911};
constexpr double kY[3] = {0.2126, 0.7152, 0.0722};

void expectNear(Rgba8 got, Rgba8 want, int tol, const std::string& where) {
    EXPECT_LE(std::abs(got.r - want.r), tol)
        << where << " r " << int(got.r) << " vs " << int(want.r);
    EXPECT_LE(std::abs(got.g - want.g), tol)
        << where << " g " << int(got.g) << " vs " << int(want.g);
    EXPECT_LE(std::abs(got.b - want.b), tol)
        << where << " b " << int(got.b) << " vs " << int(want.b);
    EXPECT_EQ(got.a, 255) << where;
}

TEST(Anaglyph, SrgbRoundTripIsExactOnAll8BitValues) {
    for (int i = 0; i < 256; ++i) {
        const float l = srgbToLinear(i / 255.0f);
        EXPECT_EQ(static_cast<int>(std::floor(linearToSrgb(l) * 255.0f + 0.5f)), i) << i;
    }
    EXPECT_FLOAT_EQ(srgbToLinear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgbToLinear(1.0f), 1.0f);
    EXPECT_NEAR(srgbToLinear(0.5f), 0.214041, 1e-5);  // IEC 61966-2-1
}

TEST(Anaglyph, DuboisMatricesAreDubois2009) {
    const AnaglyphMatrices& rc = anaglyphMatrices(AnaglyphMethod::Dubois);
    const AnaglyphMatrices& gm = anaglyphMatrices(AnaglyphMethod::DuboisGreenMagenta);
    const AnaglyphMatrices& ab = anaglyphMatrices(AnaglyphMethod::DuboisAmberBlue);
    for (int i = 0; i < 9; ++i) {
        EXPECT_FLOAT_EQ(rc.left[i], static_cast<float>(kDuboisRcL[i])) << i;
        EXPECT_FLOAT_EQ(rc.right[i], static_cast<float>(kDuboisRcR[i])) << i;
        EXPECT_FLOAT_EQ(gm.left[i], static_cast<float>(kDuboisGmL[i])) << i;
        EXPECT_FLOAT_EQ(gm.right[i], static_cast<float>(kDuboisGmR[i])) << i;
        EXPECT_FLOAT_EQ(ab.left[i], static_cast<float>(kDuboisAbL[i])) << i;
        EXPECT_FLOAT_EQ(ab.right[i], static_cast<float>(kDuboisAbR[i])) << i;
    }
}

TEST(Anaglyph, ColorTakesRedFromLeftAndGreenBlueFromRightExactly) {
    const Image left = solid(3, 2, {200, 10, 20, 77});
    const Image right = solid(3, 2, {30, 100, 150, 9});
    Result<Image> out = anaglyph(left, right, AnaglyphMethod::Color);
    ASSERT_TRUE(out) << out.status().message();
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) EXPECT_EQ(out->at(x, y), (Rgba8{200, 100, 150, 255}));
}

TEST(Anaglyph, EveryMethodMatchesTheDocumentedFormulaOnEveryPixel) {
    // Views with many different colors: x, y and the view in every channel.
    Image left(16, 16), right(16, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            left.set(x, y,
                     {std::uint8_t(x * 17), std::uint8_t(y * 17), std::uint8_t((x ^ y) * 17), 255});
            right.set(x, y,
                      {std::uint8_t(255 - y * 17), std::uint8_t(x * 16), std::uint8_t(128), 255});
        }
    double colorL[9] = {1, 0, 0, 0, 0, 0, 0, 0, 0}, colorR[9] = {0, 0, 0, 0, 1, 0, 0, 0, 1};
    double lumL[9] = {kY[0], kY[1], kY[2], 0, 0, 0, 0, 0, 0};
    double grayR[9] = {0, 0, 0, kY[0], kY[1], kY[2], kY[0], kY[1], kY[2]};
    double trueR[9] = {0, 0, 0, 0, 0, 0, kY[0], kY[1], kY[2]};
    struct Case {
        AnaglyphMethod method;
        const char* name;
        const double* l;
        const double* r;
    } cases[] = {
        {AnaglyphMethod::Color, "anaglyph-color", colorL, colorR},
        {AnaglyphMethod::HalfColor, "anaglyph-half-color", lumL, colorR},
        {AnaglyphMethod::Gray, "anaglyph-gray", lumL, grayR},
        {AnaglyphMethod::True, "anaglyph-true", lumL, trueR},
        {AnaglyphMethod::Dubois, "anaglyph-dubois", kDuboisRcL, kDuboisRcR},
        {AnaglyphMethod::DuboisGreenMagenta, "anaglyph-dubois-gm", kDuboisGmL, kDuboisGmR},
        {AnaglyphMethod::DuboisAmberBlue, "anaglyph-dubois-ab", kDuboisAbL, kDuboisAbR},
    };
    for (const Case& c : cases) {
        const Image views[2] = {left, right};
        Result<Image> out = compose(c.name, views);
        ASSERT_TRUE(out) << out.status().message();
        ASSERT_EQ(out->width, 16);
        ASSERT_EQ(out->height, 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const Rgba8 want = reference(c.l, c.r, left.at(x, y), right.at(x, y));
                // float vs double arithmetic: at most one step of rounding apart.
                expectNear(out->at(x, y), want, 1, std::string(c.name));
                EXPECT_EQ(out->at(x, y),
                          anaglyphPixel(anaglyphMatrices(c.method), left.at(x, y), right.at(x, y)));
            }
    }
}

TEST(Anaglyph, KnownDuboisValues) {
    const AnaglyphMatrices& m = anaglyphMatrices(AnaglyphMethod::Dubois);
    // White in both eyes stays white: the rows sum to ~1 (red 1.000, green 0.999, blue 1.000).
    EXPECT_EQ(anaglyphPixel(m, {255, 255, 255, 255}, {255, 255, 255, 255}),
              (Rgba8{255, 255, 255, 255}));
    // Black stays black.
    EXPECT_EQ(anaglyphPixel(m, {0, 0, 0, 255}, {0, 0, 0, 255}), (Rgba8{0, 0, 0, 255}));
    // Pure red left, black right: red 0.437 linear, green and blue negative → clamped to 0.
    const Rgba8 red = anaglyphPixel(m, {255, 0, 0, 255}, {0, 0, 0, 255});
    EXPECT_EQ(red.r, encodeRef(0.437));
    EXPECT_EQ(red.g, 0);
    EXPECT_EQ(red.b, 0);
    // Pure blue right: blue 1.234 → clamped to 1 (255); red −0.007 → 0.
    const Rgba8 blue = anaglyphPixel(m, {0, 0, 0, 255}, {0, 0, 255, 255});
    EXPECT_EQ(blue, (Rgba8{0, static_cast<std::uint8_t>(encodeRef(0.009)), 255, 255}));
}

TEST(Anaglyph, SwapEyesExchangesTheViews) {
    const Image a = solid(2, 2, {200, 10, 20, 255});
    const Image b = solid(2, 2, {30, 100, 150, 255});
    const Image views[2] = {a, b};
    ComposeOptions swap;
    swap.swapEyes = true;
    Result<Image> out = compose("anaglyph-color", views, swap);
    ASSERT_TRUE(out);
    EXPECT_EQ(out->at(1, 1), (Rgba8{30, 10, 20, 255}));
}

TEST(Anaglyph, GlslIsColumnMajorAndComplete) {
    const std::string glsl = anaglyphGlsl(AnaglyphMethod::Dubois);
    // First column of the left matrix is (0.437, -0.062, -0.048): the red, green and blue
    // outputs' weights of the left red input.
    EXPECT_NE(glsl.find("const mat3 kLeft = mat3(0.437000, -0.062000, -0.048000, 0.449000"),
              std::string::npos)
        << glsl;
    EXPECT_NE(glsl.find("const mat3 kRight = mat3(-0.011000, 0.377000, -0.026000, -0.032000"),
              std::string::npos)
        << glsl;
    EXPECT_NE(glsl.find("vec3 mvrAnaglyph(vec3 left, vec3 right)"), std::string::npos);
    EXPECT_NE(glsl.find("0.04045"), std::string::npos);
    EXPECT_NE(anaglyphGlsl(AnaglyphMethod::Color)
                  .find("mat3(1.000000, 0.000000, 0.000000, 0.000000, 0.000000"),
              std::string::npos);
}

TEST(Anaglyph, FormatNamesMapToMethods) {
    for (int i = 0; i < 7; ++i) {
        const auto method = static_cast<AnaglyphMethod>(i);
        EXPECT_EQ(anaglyphMethod(anaglyphFormatName(method)), method);
    }
    EXPECT_EQ(anaglyphMethod("anaglyph-dubois"), AnaglyphMethod::Dubois);
    EXPECT_FALSE(anaglyphMethod("sbs"));
}

TEST(Anaglyph, RejectsViewsOfDifferentSizes) {
    Result<Image> out = anaglyph(solid(2, 2, {}), solid(3, 2, {}), AnaglyphMethod::Dubois);
    ASSERT_FALSE(out);
    EXPECT_EQ(out.status().code(), ErrorCode::Usage);
    EXPECT_EQ(out.status().message(),
              "mvr::composite::anaglyph(): views differ in size: view 0 is 2x2, view 1 is 3x2 "
              "(expected one size)");
}

}  // namespace
}  // namespace mvr::composite
