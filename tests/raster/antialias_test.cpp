// --aa N (mvr/core/antialias.h) on the soft backend: a triangle's edge pixels against the
// coverage computed here from the standard sample positions (written out below, not read from
// the code under test), the nearest sample's depth, and unified == multipass bit for bit with
// several samples a pixel.
#include <array>
#include <cmath>
#include <vector>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/core/antialias.h"
#include "mvr/raster/soft_backend.h"

namespace mvr::raster {
namespace {

constexpr int kW = 32, kH = 24;

// Direct3D's standard multisample positions, 1/16 pixel, x right, y down (rows top first).
std::vector<glm::dvec2> positions(int n) {
    std::vector<std::array<int, 2>> p;
    if (n == 2) p = {{4, 4}, {-4, -4}};
    if (n == 4) p = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    if (n == 8) p = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    std::vector<glm::dvec2> out;
    for (auto [x, y] : p) out.push_back(glm::dvec2(x, y) / 16.0);
    return out;
}

// A triangle in pixel units, y up (x, y of the window with row 0 at the top: y = H - row).
const glm::dvec2 kTri[3] = {{3.3, 2.1}, {27.7, 9.4}, {11.2, 21.9}};

/// Signed distance-like edge values; > 0 inside (counter-clockwise); nullopt on an edge.
std::optional<bool> inside(glm::dvec2 p) {
    bool in = true;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2 a = kTri[i], b = kTri[(i + 1) % 3];
        const double e = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        if (std::abs(e) / glm::length(b - a) < 1e-3) return std::nullopt;
        in = in && e > 0.0;
    }
    return in;
}

Scene triangleScene() {
    Mesh m;
    m.name = "triangle";
    for (const glm::dvec2& v : kTri) {
        m.positions.push_back({float(v.x), float(v.y), -1.0f});
        m.normals.push_back({0.0f, 0.0f, 1.0f});
    }
    m.indices = {0, 1, 2};
    Scene s;
    s.lights = defaultLights();
    s.meshes = {std::move(m)};
    Instance inst;
    inst.material.albedo = {0.9f, 0.6f, 0.3f};
    inst.material.specular = 0.0f;  // one colour over the whole triangle
    s.instances = {inst};
    return s;
}

/// One orthographic view: world x, y in pixels (y up), looking down −Z from z = 0.
Rig pixelRig() {
    Camera cam;
    cam.position = {kW / 2.0f, kH / 2.0f, 5.0f};
    cam.target = {kW / 2.0f, kH / 2.0f, 0.0f};
    cam.aspect = float(kW) / float(kH);
    View v;
    v.viewFromWorld = glm::mat4(1.0f);
    v.clipFromView = glm::ortho(0.0f, float(kW), 0.0f, float(kH), 0.5f, 2.0f);
    return std::move(makeListRig(cam, {v})).value();
}

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
                    int k = 0;
                    bool tie = false;
                    for (const glm::dvec2& o : positions(n)) {
                        const auto in = inside({x + 0.5 + o.x, kH - (row + 0.5 + o.y)});
                        if (!in) tie = true;
                        k += in.value_or(false);
                    }
                    if (tie) continue;
                    ++checked;
                    partial += k > 0 && k < n;
                    const Rgba8 got = aa->color[0].at(x, row);
                    auto mix = [&](int f, int c) { return (f * k + c * (n - k) + n / 2) / n; };
                    EXPECT_EQ(got.r, mix(fill.r, clear.r)) << x << "," << row << " k " << k;
                    EXPECT_EQ(got.g, mix(fill.g, clear.g)) << x << "," << row << " k " << k;
                    EXPECT_EQ(got.b, mix(fill.b, clear.b)) << x << "," << row << " k " << k;
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
