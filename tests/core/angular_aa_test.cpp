// Angular anti-aliasing (mvr/core/angular_aa.h): the focal plane stays as it was, a plane at
// twice the convergence distance is blurred by the box the test computes from the rig's
// parameters (focal length in pixels, interaxial step, convergence), not through the library.
#include "mvr/core/angular_aa.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

namespace mvr {
namespace {

constexpr int kW = 200, kH = 120;

struct RigSetup {
    Camera camera;
    RigParams params;
    Rig rig;
    float focalPx = 0, focalPxY = 0;  ///< focal lengths in pixels, computed here
};

RigSetup setup(int columns, int rows, float interaxial, float convergence) {
    RigSetup s;
    s.camera.aspect = float(kW) / float(kH);
    s.camera.near = 0.5f;
    s.camera.far = 100.0f;
    s.params.columns = columns;
    s.params.rows = rows;
    s.params.interaxial = interaxial;
    s.params.convergence = convergence;
    s.rig = *makeRig(s.camera, s.params);
    const float tanHalf = std::tan(glm::radians(s.camera.fovYDegrees) * 0.5f);
    s.focalPx = 0.5f * kW / (s.camera.aspect * tanHalf);
    s.focalPxY = 0.5f * kH / tanHalf;
    return s;
}

/// Window depth of eye distance w for glFrustum's z row (written out, not through the library).
float depthOf(const Camera& c, float w) {
    const float n = c.near, f = c.far;
    const float ndc = (f + n) / (f - n) - 2.0f * f * n / ((f - n) * w);
    return ndc * 0.5f + 0.5f;
}

/// The fraction of the box [c − k/2, c + k/2] that lies at or beyond `edge`.
double beyond(double c, double k, double edge) {
    return std::clamp((c + 0.5 * k - edge) / k, 0.0, 1.0);
}

TEST(AngularAA, FocalPlaneIsUnchanged) {
    RigSetup s = setup(8, 1, 0.5f, 5.0f);
    std::vector<Image> color;
    std::vector<DepthImage> depth;
    for (int v = 0; v < s.rig.viewCount(); ++v) {
        Image im(kW, kH);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                im.set(x, y,
                       {std::uint8_t((x * 37 + y * 11 + v) % 256), std::uint8_t((x / 3 % 2) * 255),
                        std::uint8_t(y * 2), 255});
        color.push_back(im);
        depth.emplace_back(kW, kH, depthOf(s.camera, 5.0f));
    }
    const std::vector<Image> before = color;
    ASSERT_TRUE(applyAngularAA(s.rig, color, depth, 1.0f));
    for (int v = 0; v < s.rig.viewCount(); ++v) {
        const ImageDiff d = compareImages(before[v], color[v]);
        EXPECT_LE(d.maxDelta, 1) << "view " << v;
    }
}

TEST(AngularAA, TwiceTheConvergenceIsBlurredByTheKernelWidth) {
    const float interaxial = 0.6f, convergence = 5.0f;
    RigSetup s = setup(6, 1, interaxial, convergence);
    // The step between adjacent views at w = 2C: f · b · (1/C − 1/w) = f · b / (2C) pixels.
    const double step = s.focalPx * interaxial / (2.0 * convergence);
    for (const float scale : {1.0f, 0.5f}) {
        const double k = (step - 1.0) * scale;
        ASSERT_GT(k, 3.0);  // a ramp worth measuring
        const int edge = kW / 2;
        std::vector<Image> color;
        std::vector<DepthImage> depth;
        for (int v = 0; v < s.rig.viewCount(); ++v) {
            Image im(kW, kH, {0, 0, 0, 255});
            for (int y = 0; y < kH; ++y)
                for (int x = edge; x < kW; ++x) im.set(x, y, {255, 255, 255, 255});
            color.push_back(im);
            depth.emplace_back(kW, kH, depthOf(s.camera, 2.0f * convergence));
        }
        ASSERT_TRUE(applyAngularAA(s.rig, color, depth, scale));
        for (int v = 0; v < s.rig.viewCount(); ++v) {
            int ramp = 0;
            for (int x = 0; x < kW; ++x) {
                const double want = 255.0 * beyond(x + 0.5, k, edge);
                const int got = color[v].at(x, kH / 2).r;
                EXPECT_NEAR(got, want, 1.0) << "view " << v << " x " << x << " k " << k;
                ramp += got > 0 && got < 255;
            }
            // The ramp is k pixels wide: the pixel centres inside (edge − k/2, edge + k/2).
            EXPECT_GE(ramp, int(std::floor(k)) - 1) << "view " << v;
            EXPECT_LE(ramp, int(std::ceil(k)) + 1) << "view " << v;
        }
    }
}

TEST(AngularAA, GridIsBlurredVerticallyToo) {
    const float interaxial = 0.6f, convergence = 5.0f;
    RigSetup s = setup(3, 3, interaxial, convergence);
    const double kx = s.focalPx * interaxial / (2.0 * convergence) - 1.0;
    const double ky = s.focalPxY * interaxial / (2.0 * convergence) - 1.0;
    ASSERT_GT(ky, 3.0);
    std::vector<Image> color;
    std::vector<DepthImage> depth;
    for (int v = 0; v < s.rig.viewCount(); ++v) {
        Image im(kW, kH, {0, 0, 0, 255});  // a white quadrant: bottom right
        for (int y = kH / 2; y < kH; ++y)
            for (int x = kW / 2; x < kW; ++x) im.set(x, y, {255, 255, 255, 255});
        color.push_back(im);
        depth.emplace_back(kW, kH, depthOf(s.camera, 2.0f * convergence));
    }
    ASSERT_TRUE(applyAngularAA(s.rig, color, depth, 1.0f));
    for (int v = 0; v < s.rig.viewCount(); ++v) {
        for (int y = 0; y < kH; y += 3)
            for (int x = 0; x < kW; x += 3) {
                const double want =
                    255.0 * beyond(x + 0.5, kx, kW / 2) * beyond(y + 0.5, ky, kH / 2);
                // Two rounded passes: each within ½, the second scaling the first's error.
                EXPECT_NEAR(color[v].at(x, y).r, want, 1.5)
                    << "view " << v << " at " << x << "," << y;
            }
    }
}

TEST(AngularAA, SharpFocalPlaneInFrontStaysSharp) {
    // A focal-plane bar in front of a far plane: the bar's pixels keep their values, and the
    // far plane beside it does not take the bar's colour (the bar's kernel is 0: it reaches
    // no neighbour).
    const float convergence = 5.0f;
    RigSetup s = setup(4, 1, 0.6f, convergence);
    std::vector<Image> color;
    std::vector<DepthImage> depth;
    for (int v = 0; v < s.rig.viewCount(); ++v) {
        Image im(kW, kH, {0, 0, 80, 255});
        DepthImage d(kW, kH, depthOf(s.camera, 4.0f * convergence));
        for (int y = 0; y < kH; ++y)
            for (int x = 90; x < 110; ++x) {
                im.set(x, y, {std::uint8_t(x % 2 ? 255 : 0), 200, 0, 255});
                d.depth[std::size_t(y) * kW + x] = depthOf(s.camera, convergence);
            }
        color.push_back(im);
        depth.push_back(d);
    }
    const std::vector<Image> before = color;
    ASSERT_TRUE(applyAngularAA(s.rig, color, depth, 1.0f));
    for (int v = 0; v < s.rig.viewCount(); ++v)
        for (int y = 0; y < kH; y += 7)
            for (int x = 0; x < kW; ++x) {
                const Rgba8 want = before[v].at(x, y), got = color[v].at(x, y);
                EXPECT_EQ(got, want) << "view " << v << " at " << x << "," << y;
            }
}

TEST(AngularAA, Refusals) {
    RigSetup s = setup(2, 1, 0.5f, 5.0f);
    std::vector<Image> color(2, Image(kW, kH));
    std::vector<DepthImage> depth(2, DepthImage(kW, kH));
    std::vector<DepthImage> none;
    Status noDepth = applyAngularAA(s.rig, color, none, 1.0f);
    EXPECT_EQ(noDepth.code(), ErrorCode::Unsupported);
    EXPECT_EQ(noDepth.message(), "angular anti-aliasing needs a depth buffer");
    EXPECT_EQ(applyAngularAA(s.rig, color, depth, 0.0f).code(), ErrorCode::Usage);
    EXPECT_EQ(applyAngularAA(s.rig, color, depth, NAN).code(), ErrorCode::Usage);
    RigParams toeIn = s.params;
    toeIn.kind = RigKind::ToeIn;
    Rig rig = *makeRig(s.camera, toeIn);
    Status st = applyAngularAA(rig, color, depth, 1.0f);
    EXPECT_EQ(st.code(), ErrorCode::Unsupported);
    EXPECT_NE(st.message().find("needs an off-axis rig"), std::string::npos) << st.message();
}

TEST(AngularAA, ViewConeStepsAreThePerViewGaps) {
    // A view cone spreads the views by C · tan(θ_i): the outer gaps are wider than the inner.
    RigSetup s = setup(5, 1, 0.5f, 5.0f);
    s.params.viewConeDegrees = 40.0f;
    Rig rig = *makeRig(s.camera, s.params);
    const float tanHalf = std::tan(glm::radians(s.camera.fovYDegrees) * 0.5f);
    const float a = 5.0f * s.camera.aspect * tanHalf;  // half the window at the convergence plane
    auto offset = [&](int i) { return 5.0f * std::tan(glm::radians(-20.0f + 10.0f * i)); };
    EXPECT_NEAR(adjacentShearStep(rig, 0).x, (offset(1) - offset(0)) / a, 1e-4f);
    EXPECT_NEAR(adjacentShearStep(rig, 2).x, 0.5f * (offset(3) - offset(1)) / a, 1e-4f);
    EXPECT_EQ(adjacentShearStep(rig, 2).y, 0.0f);
}

}  // namespace
}  // namespace mvr
