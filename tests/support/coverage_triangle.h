// tests/support/coverage_triangle.h — one flat triangle in a 32×24 orthographic view whose
// edge pixels' coverage the tests compute themselves from the standard multisample positions
// (written out here, not read from mvr/core/antialias.h): `--aa N` on the soft backend
// (tests/raster/antialias_test.cpp) and multisampled gl targets (tests/gl/antialias_gl_test.cpp).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "mvr/core/image.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr::test::coverage {

inline constexpr int kW = 32, kH = 24;

/// Direct3D's standard multisample positions, 1/16 pixel, x right, y down (rows top first).
inline std::vector<glm::dvec2> positions(int n) {
    std::vector<std::array<int, 2>> p;
    if (n == 2) p = {{4, 4}, {-4, -4}};
    if (n == 4) p = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
    if (n == 8) p = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
    std::vector<glm::dvec2> out;
    for (auto [x, y] : p) out.push_back(glm::dvec2(x, y) / 16.0);
    return out;
}

/// The triangle in pixel units, y up (x, y of the window with row 0 at the top: y = H - row).
inline constexpr glm::dvec2 kTri[3] = {{3.3, 2.1}, {27.7, 9.4}, {11.2, 21.9}};

/// Whether `p` is inside (counter-clockwise edge values all > 0); nullopt within 1e-3 pixel of
/// an edge, where rounding decides.
inline std::optional<bool> inside(glm::dvec2 p) {
    bool in = true;
    for (int i = 0; i < 3; ++i) {
        const glm::dvec2 a = kTri[i], b = kTri[(i + 1) % 3];
        const double e = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        if (std::abs(e) / glm::length(b - a) < 1e-3) return std::nullopt;
        in = in && e > 0.0;
    }
    return in;
}

/// The samples of pixel (x, row) inside the triangle, of n; nullopt where one is on an edge.
inline std::optional<int> coveredSamples(int x, int row, int n) {
    int k = 0;
    for (const glm::dvec2& o : positions(n)) {
        const auto in = inside({x + 0.5 + o.x, kH - (row + 0.5 + o.y)});
        if (!in) return std::nullopt;
        k += *in;
    }
    return k;
}

/// The resolve of `in` samples of `fill` and n − in of `clear` (antialias.h's: each channel
/// (Σ + n/2) / n), written out here.
inline Rgba8 resolvedMix(int in, int n, Rgba8 fill, Rgba8 clear) {
    auto mix = [&](int f, int c) { return std::uint8_t((f * in + c * (n - in) + n / 2) / n); };
    return {mix(fill.r, clear.r), mix(fill.g, clear.g), mix(fill.b, clear.b), mix(fill.a, clear.a)};
}

/// The triangle, one unlit-looking colour (no specular) at z = -1.
inline Scene triangleScene() {
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

/// `views` copies of one orthographic view: world x, y in pixels (y up), looking down −Z from
/// z = 0 (two for the methods that render stereo pairs only).
inline Rig pixelRig(int views = 1) {
    Camera cam;
    cam.position = {kW / 2.0f, kH / 2.0f, 5.0f};
    cam.target = {kW / 2.0f, kH / 2.0f, 0.0f};
    cam.aspect = float(kW) / float(kH);
    View v;
    v.viewFromWorld = glm::mat4(1.0f);
    v.clipFromView = glm::ortho(0.0f, float(kW), 0.0f, float(kH), 0.5f, 2.0f);
    return std::move(makeListRig(cam, std::vector<View>(std::size_t(views), v))).value();
}

}  // namespace mvr::test::coverage
