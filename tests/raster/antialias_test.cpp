// --aa N (mvr/core/antialias.h) on the soft backend: a triangle's edge pixels against the
// coverage computed from the standard sample positions (tests/support/coverage_triangle.h,
// written out there, not read from the code under test), the nearest sample's depth, and
// unified == multipass bit for bit with several samples a pixel.
#include <optional>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "coverage_triangle.h"
#include "mvr/core/antialias.h"
#include "mvr/raster/soft_backend.h"

namespace mvr::raster {
namespace {

using namespace test::coverage;

TEST(Antialias, EdgePixelsAreTheCoverageOfTheSamplePositions) {
    auto backend = makeSoftBackend();
    const Scene scene = triangleScene();
    const Rig rig = pixelRig();
    RenderSettings s;
    s.width = kW, s.height = kH;
    s.shading = Shading::Flat;
    s.clearColor = {0.1f, 0.2f, 0.3f};
    auto one = backend->render(scene, rig, s, "multipass");
    ASSERT_TRUE(one) << one.status().message();
    const Rgba8 fill = one->color[0].at(12, 12), clear = one->color[0].at(0, 0);  // inside, outside
    const float triangleDepth = one->depth[0].at(12, 12);
    ASSERT_NE(fill, clear);
    for (const int n : {2, 4, 8}) {
        for (const char* method : {"multipass", "unified"}) {
            SCOPED_TRACE(fmt::format("{} samples, {}", n, method));
            s.samples = n;
            auto aa = backend->render(scene, rig, s, method);
            ASSERT_TRUE(aa) << aa.status().message();
            int partial = 0, checked = 0;
            for (int row = 0; row < kH; ++row) {
                for (int x = 0; x < kW; ++x) {
                    const std::optional<int> covered = coveredSamples(x, row, n);
                    if (!covered) continue;
                    const int k = *covered;
                    ++checked;
                    partial += k > 0 && k < n;
                    const Rgba8 got = aa->color[0].at(x, row), want = resolvedMix(k, n, fill, clear);
                    EXPECT_EQ(got, want) << x << "," << row << " k " << k << ": " << int(got.r)
                                         << "," << int(got.g) << "," << int(got.b);
                    // The nearest sample's depth: the triangle's wherever a sample is on it.
                    // (within rounding: the plane's depth interpolated at a moved position)
                    EXPECT_NEAR(aa->depth[0].at(x, row), k > 0 ? triangleDepth : 1.0f, 1e-6f)
                        << x << "," << row;
                }
            }
            EXPECT_GT(checked, kW * kH * 9 / 10);
            EXPECT_GT(partial, 20);  // the edges are there to test
        }
    }
    s.samples = 3;
    auto bad = backend->render(scene, rig, s, "unified");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message(), "3 samples a pixel (expected 1, 2, 4 or 8)");
}

}  // namespace
}  // namespace mvr::raster
