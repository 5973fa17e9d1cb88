// Differential tests: the unified N-view pipeline equals N single-view renders (multipass) BIT
// FOR BIT, color and depth, over rigs (off-axis rows and grids, toe-in, parallel, lists), view
// counts 1..9 and long rows / big grids up to 100 views, shading modes, culling, wireframe, models and random triangle soups (crossing the
// near plane, the screen edges and the guard band); and the SIMD paths equal the scalar path.
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <random>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/io/mesh_io.h"
#include "mvr/raster/soft_backend.h"
#include "test_scenes.h"
#include "mvr_test_support.h"

namespace mvr::raster {
namespace {

std::filesystem::path modelsDir() {
    return ::mvr::test::modelsDir();  // MVR_SHARED_DIR, else the configured folder
}

/// First difference between two renders, or "" when identical bit for bit.
std::string firstDifference(const RenderOutput& a, const RenderOutput& b) {
    if (a.color.size() != b.color.size() || a.depth.size() != b.depth.size())
        return "view counts differ";
    for (std::size_t v = 0; v < a.color.size(); ++v) {
        const Image& ca = a.color[v];
        const Image& cb = b.color[v];
        if (ca.width != cb.width || ca.height != cb.height)
            return fmt::format("view {}: sizes differ", v);
        for (int y = 0; y < ca.height; ++y) {
            for (int x = 0; x < ca.width; ++x) {
                if (ca.at(x, y) != cb.at(x, y)) {
                    const Rgba8 p = ca.at(x, y), q = cb.at(x, y);
                    return fmt::format("view {} color at ({}, {}): {},{},{} vs {},{},{}", v, x, y,
                                       p.r, p.g, p.b, q.r, q.g, q.b);
                }
                const float da = a.depth[v].at(x, y), db = b.depth[v].at(x, y);
                if (std::memcmp(&da, &db, sizeof(float)) != 0) {
                    return fmt::format("view {} depth at ({}, {}): {:.9g} vs {:.9g}", v, x, y, da,
                                       db);
                }
            }
        }
    }
    return "";
}

long coveredPixels(const RenderOutput& r) {
    long n = 0;
    for (const DepthImage& d : r.depth) {
        for (float z : d.depth) n += z < 1.0f;
    }
    return n;
}

struct Stats {
    long renders = 0, covered = 0;
};

void expectSame(Backend& backend, const Scene& scene, const Rig& rig, const RenderSettings& s,
                Stats& stats) {
    auto mp = backend.render(scene, rig, s, "multipass");
    ASSERT_TRUE(mp) << mp.status().message();
    auto un = backend.render(scene, rig, s, "unified");
    ASSERT_TRUE(un) << un.status().message();
    const std::string diff = firstDifference(*mp, *un);
    ASSERT_EQ(diff, "") << "rig " << rigKindName(rig.kind) << " " << rig.columns << "x" << rig.rows
                        << " views " << rig.viewCount() << " shading " << shadingName(s.shading)
                        << " cull " << s.cullBackFaces << " wireframe " << s.wireframe;
    ++stats.renders;
    stats.covered += coveredPixels(*mp);
}

/// A camera looking at `center` from a random direction at `distance`.
Camera randomCamera(std::mt19937& rng, glm::vec3 center, float distance, float aspect) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Camera c;
    glm::vec3 dir = glm::normalize(glm::vec3(u(rng), 0.6f * u(rng), 1.0f + 0.3f * u(rng)));
    c.target = center + glm::vec3(u(rng), u(rng), u(rng)) * 0.1f * distance;
    c.position = center + dir * distance;
    c.fovYDegrees = 35.0f + 25.0f * (u(rng) * 0.5f + 0.5f);
    c.aspect = aspect;
    c.near = distance * (0.05f + 0.2f * (u(rng) * 0.5f + 0.5f));
    c.far = distance * (3.0f + 20.0f * (u(rng) * 0.5f + 0.5f));
    return c;
}

/// A random rig of a random kind: off-axis rows (1..9), off-axis grids, toe-in, parallel, lists.
Rig randomRig(std::mt19937& rng, const Camera& camera, int shape) {
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    RigParams p;
    const float dist = glm::length(camera.target - camera.position);
    p.convergence = std::max(camera.near * 1.5f, dist * (0.5f + u(rng)));
    p.interaxial = p.convergence * (0.01f + 0.08f * u(rng));
    switch (shape % 5) {
        case 0: p.kind = RigKind::OffAxis, p.columns = 1 + int(rng() % 9), p.rows = 1; break;
        case 1: {
            static const int grids[][2] = {{2, 2}, {3, 2}, {3, 3}, {2, 3}, {1, 3}};
            const auto& g = grids[rng() % 5];
            p.kind = RigKind::OffAxis, p.columns = g[0], p.rows = g[1];
            break;
        }
        case 2: p.kind = RigKind::ToeIn, p.columns = 2 + int(rng() % 4), p.rows = 1; break;
        case 3:
            p.kind = RigKind::Parallel, p.columns = 2 + int(rng() % 3), p.rows = 1 + int(rng() % 2);
            break;
        default: {
            // A list: shadow-map-like views from random positions, some orthographic.
            std::vector<View> views;
            const int n = 1 + int(rng() % 4);
            for (int i = 0; i < n; ++i) {
                Camera c = camera;
                c.position =
                    camera.target + (camera.position - camera.target) *
                                        glm::vec3(0.5f + u(rng), 0.5f + u(rng), 0.5f + u(rng));
                View v;
                v.viewFromWorld = c.viewFromWorld();
                if (i % 2 == 1) {
                    const float r = dist * 0.6f;
                    v.clipFromView = glm::ortho(-r * c.aspect, r * c.aspect, -r, r, c.near, c.far);
                } else {
                    v.clipFromView = c.clipFromView();
                }
                views.push_back(v);
            }
            return std::move(makeListRig(camera, views)).value();
        }
    }
    auto rig = makeRig(camera, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return std::move(rig).value();
}

RenderSettings randomSettings(std::mt19937& rng, int i) {
    RenderSettings s;
    s.width = 48 + int(rng() % 40);
    s.height = 32 + int(rng() % 30);
    s.shading = static_cast<Shading>(i % 3);
    s.cullBackFaces = (i / 3) % 2 == 1;
    s.clearColor = {0.1f, 0.2f, 0.3f};
    return s;
}

TEST(UnifiedEqualsMultipass, Models) {
    auto backend = makeSoftBackend();
    std::mt19937 rng(2024);
    Stats stats;
    int models = 0;
    for (const char* name : {"stanford-bunny.obj", "spot.obj", "teapot.obj", "suzanne.obj"}) {
        const auto path = modelsDir() / name;
        if (!std::filesystem::exists(path)) continue;
        auto mesh = loadMesh(path);
        ASSERT_TRUE(mesh) << mesh.status().message();
        ++models;
        const Scene scene =
            makeGridScene({std::move(mesh).value()}, name[0] == 's' && name[1] == 't' ? 1 : 2);
        const Bounds b = scene.bounds();
        for (int i = 0; i < 12; ++i) {
            SCOPED_TRACE(fmt::format("{} case {}", name, i));
            RenderSettings s = randomSettings(rng, i);
            // Mostly outside the model; every fourth case with the camera close enough that the
            // near plane cuts the model.
            const float distance = b.radius() * (i % 4 == 3 ? 0.8f : 2.0f + float(rng() % 3));
            const Camera cam =
                randomCamera(rng, b.center(), distance, float(s.width) / float(s.height));
            const Rig rig = randomRig(rng, cam, i + models);
            expectSame(*backend, scene, rig, s, stats);
        }
    }
    if (models == 0) MVR_SKIP(ModelsMissing) << "no models in " << modelsDir();
    EXPECT_GT(stats.covered, stats.renders * 50) << "the renders must draw something";
}

/// Random triangles around and behind the camera: crossing the near plane, the far plane, the
/// screen edges and (huge ones) the guard band.
Scene randomSoup(std::mt19937& rng, int count) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Mesh m;
    m.name = "soup";
    for (int t = 0; t < count; ++t) {
        const float scale = t % 7 == 0 ? 400.0f : (t % 3 == 0 ? 6.0f : 1.5f);
        const glm::vec3 c(u(rng) * 4.0f, u(rng) * 3.0f, u(rng) * 8.0f - 2.0f);
        for (int k = 0; k < 3; ++k) {
            m.positions.push_back(c + glm::vec3(u(rng), u(rng), u(rng)) * scale);
            m.normals.push_back(
                glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0, 0, 0.01f)));
            m.indices.push_back(std::uint32_t(m.positions.size() - 1));
        }
    }
    Scene s;
    s.lights = defaultLights();
    s.meshes = {std::move(m)};
    Instance inst;
    inst.material.albedo = {0.7f, 0.5f, 0.3f};
    s.instances = {inst};
    // A second instance of the same soup, moved and rotated, with its own material.
    Instance second;
    second.worldFromModel =
        glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, -0.3f, -1.0f)), 0.4f,
                    glm::vec3(0.2f, 1.0f, 0.1f));
    second.material.albedo = {0.2f, 0.6f, 0.9f};
    second.material.shininess = 8.0f;
    s.instances.push_back(second);
    return s;
}

TEST(UnifiedEqualsMultipass, RandomTriangleSoups) {
    auto backend = makeSoftBackend();
    std::mt19937 rng(77);
    Stats stats;
    for (int i = 0; i < 60; ++i) {
        SCOPED_TRACE(fmt::format("soup case {}", i));
        const Scene scene = randomSoup(rng, 40 + int(rng() % 60));
        RenderSettings s = randomSettings(rng, i);
        s.wireframe = i % 10 == 9;
        Camera cam;
        cam.position = {0.0f, 0.0f, 3.0f};
        cam.target = {0.2f, -0.1f, 0.0f};
        cam.near = 0.3f, cam.far = 30.0f;
        cam.aspect = float(s.width) / float(s.height);
        const Rig rig = randomRig(rng, cam, i);
        expectSame(*backend, scene, rig, s, stats);
    }
    EXPECT_GT(stats.covered, stats.renders * 50);
}

/// The camera the default scene's tests look through (its ground plane crosses the near plane).
Camera defaultSceneCamera(float aspect) {
    Camera cam;
    cam.position = {0.5f, 1.5f, 6.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.aspect = aspect;
    return cam;
}

TEST(UnifiedEqualsMultipass, EveryViewCountAndShading) {
    // The default procedural scene (its ground plane crosses the near plane) on off-axis rows of
    // 1..9 views and the kalaiah2007 grids, all shading modes, culling on and off.
    auto backend = makeSoftBackend();
    const Scene scene = makeDefaultScene();
    Stats stats;
    const Camera cam = defaultSceneCamera(80.0f / 60.0f);
    for (int views = 1; views <= 9; ++views) {
        for (int mode = 0; mode < 6; ++mode) {
            RenderSettings s;
            s.width = 80, s.height = 60;
            s.shading = static_cast<Shading>(mode % 3);
            s.cullBackFaces = mode >= 3;
            RigParams p;
            p.columns = views, p.rows = 1, p.interaxial = 0.2f, p.convergence = 6.0f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig);
            expectSame(*backend, scene, *rig, s, stats);
        }
    }
    for (auto [c, r] : {std::pair{2, 1}, {3, 1}, {2, 2}, {3, 2}, {3, 3}}) {
        RigParams p;
        p.columns = c, p.rows = r, p.interaxial = 0.3f, p.convergence = 6.0f;
        auto rig = makeRig(cam, p);
        ASSERT_TRUE(rig);
        RenderSettings s;
        s.width = 64, s.height = 48;
        for (int mode = 0; mode < 3; ++mode) {
            s.shading = static_cast<Shading>(mode);
            s.cullBackFaces = mode == 1;
            expectSame(*backend, scene, *rig, s, stats);
            s.wireframe = true;
            expectSame(*backend, scene, *rig, s, stats);
            s.wireframe = false;
        }
    }
    EXPECT_GT(stats.covered, stats.renders * 500);
}

// --aa N (antialias.h): each sample is an exact pair, so the resolve is too — over the random
// soups, the models and the default scene's rows and grids, 2, 4 and 8 samples a pixel.
TEST(UnifiedEqualsMultipass, SeveralSamplesAPixel) {
    auto backend = makeSoftBackend();
    std::mt19937 rng(38);
    Stats stats;
    for (int i = 0; i < 24; ++i) {
        SCOPED_TRACE(fmt::format("soup case {}", i));
        const Scene scene = randomSoup(rng, 40 + int(rng() % 60));
        RenderSettings s = randomSettings(rng, i);
        s.samples = i % 6 == 5 ? 8 : i % 6 == 4 ? 2 : 4;
        s.wireframe = i % 10 == 9;
        Camera cam;
        cam.position = {0.0f, 0.0f, 3.0f};
        cam.target = {0.2f, -0.1f, 0.0f};
        cam.near = 0.3f, cam.far = 30.0f;
        cam.aspect = float(s.width) / float(s.height);
        const Rig rig = randomRig(rng, cam, i);
        expectSame(*backend, scene, rig, s, stats);
    }
    for (const char* name : {"stanford-bunny.obj", "teapot.obj"}) {
        const auto path = modelsDir() / name;
        if (!std::filesystem::exists(path)) continue;
        auto mesh = loadMesh(path);
        ASSERT_TRUE(mesh) << mesh.status().message();
        const Scene scene = makeGridScene({std::move(mesh).value()}, 2);
        const Bounds b = scene.bounds();
        for (int i = 0; i < 4; ++i) {
            RenderSettings s = randomSettings(rng, i);
            s.samples = 4;
            const Camera cam = randomCamera(rng, b.center(), b.radius() * 2.5f,
                                            float(s.width) / float(s.height));
            expectSame(*backend, scene, randomRig(rng, cam, i), s, stats);
        }
    }
    const Scene scene = makeDefaultScene();
    for (auto [c, r] : {std::pair{2, 1}, {9, 1}, {3, 3}, {45, 1}}) {
        RigParams p;
        p.columns = c, p.rows = r, p.interaxial = 0.2f, p.convergence = 6.0f;
        auto rig = makeRig(defaultSceneCamera(80.0f / 60.0f), p);
        ASSERT_TRUE(rig);
        RenderSettings s;
        s.width = 80, s.height = 60, s.samples = 4;
        expectSame(*backend, scene, *rig, s, stats);
        // The samples moved the image: not the one-sample render.
        RenderSettings one = s;
        one.samples = 1;
        auto a = backend->render(scene, *rig, s, "unified");
        auto b = backend->render(scene, *rig, one, "unified");
        ASSERT_TRUE(a && b);
        EXPECT_NE(firstDifference(*a, *b), "");
    }
    EXPECT_GT(stats.covered, stats.renders * 50);
}

TEST(UnifiedEqualsMultipass, GridViewsInAnyOrder) {
    // unified computes x once per column of a grid (views with the same shear.x share it) and
    // lets a row reuse another row's interleaved x: the views' order must not matter. A 3x2 grid
    // with its views shuffled (columns split across rows, rows swapped) against multipass.
    auto backend = makeSoftBackend();
    const Scene scene = makeDefaultScene();
    Stats stats;
    const Camera cam = defaultSceneCamera(64.0f / 48.0f);
    RigParams p;
    p.columns = 3, p.rows = 2, p.interaxial = 0.3f, p.convergence = 6.0f;
    auto grid = makeRig(cam, p);
    ASSERT_TRUE(grid);
    const std::vector<View> v = grid->views;
    for (const std::vector<int>& order :
         {std::vector<int>{0, 4, 2, 1, 5, 3}, std::vector<int>{3, 4, 5, 0, 1, 2},
          std::vector<int>{5, 0, 4, 1, 3, 2}}) {
        Rig rig = *grid;
        for (std::size_t i = 0; i < order.size(); ++i) rig.views[i] = v[std::size_t(order[i])];
        RenderSettings s;
        s.width = 64, s.height = 48;
        for (int mode = 0; mode < 3; ++mode) {
            s.shading = static_cast<Shading>(mode);
            s.cullBackFaces = mode == 1;
            expectSame(*backend, scene, rig, s, stats);
            s.wireframe = true;
            expectSame(*backend, scene, rig, s, stats);
            s.wireframe = false;
        }
    }
    EXPECT_GT(stats.covered, stats.renders * 500);
}

/// Off-axis rows and grids of `shapes` (columns, rows) on small random soups (near plane, guard
/// band): every shading, culling on and off, wireframe.
void expectSameOnSoups(Backend& backend, std::mt19937& rng,
                       const std::vector<std::pair<int, int>>& shapes, Stats& stats) {
    int i = 0;
    for (auto [c, r] : shapes) {
        for (int mode = 0; mode < 7; ++mode, ++i) {
            SCOPED_TRACE(fmt::format("{}x{} mode {}", c, r, mode));
            const Scene scene = randomSoup(rng, 12 + int(rng() % 12));
            RenderSettings s;
            s.width = 24 + int(rng() % 16), s.height = 16 + int(rng() % 12);
            s.shading = static_cast<Shading>(mode % 3);
            s.cullBackFaces = mode >= 3 && mode < 6;
            s.wireframe = mode == 6;
            Camera cam;
            cam.position = {0.0f, 0.0f, 3.0f};
            cam.target = {0.2f, -0.1f, 0.0f};
            cam.near = 0.3f, cam.far = 30.0f;
            cam.aspect = float(s.width) / float(s.height);
            RigParams p;
            p.kind = RigKind::OffAxis, p.columns = c, p.rows = r;
            p.convergence = 3.0f, p.interaxial = 3.0f * (0.005f + 0.02f * float(rng() % 4));
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig) << rig.status().message();
            ASSERT_EQ(rig->viewCount(), c * r);
            expectSame(backend, scene, *rig, s, stats);
        }
    }
}

TEST(UnifiedEqualsMultipass, ViewsThatLeaveTheGuardBandOnTheirOwn) {
    // Big triangles with one vertex at the guard band's edge (|x| ~ 64 w in the centre view): the
    // shear moves it across the edge in some views of a row and not in others, so the row's
    // triangle needs left/right clipping in some views and is drawn unclipped (x, outcode and
    // snapped x derived from the centre: UnifiedData::viewX / viewCode / viewSx) in the others.
    auto backend = makeSoftBackend();
    std::mt19937 rng(6464);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Stats stats;
    for (auto [c, r] : {std::pair{2, 1}, {3, 1}, {5, 1}, {8, 1}, {3, 3}, {16, 1}}) {
        for (int mode = 0; mode < 6; ++mode) {
            SCOPED_TRACE(fmt::format("{}x{} mode {}", c, r, mode));
            RenderSettings s;
            s.width = 40, s.height = 30;
            s.shading = static_cast<Shading>(mode % 3);
            s.cullBackFaces = mode >= 3;
            Camera cam;
            cam.position = {0.0f, 0.0f, 3.0f};
            cam.target = {0.0f, 0.0f, 0.0f};
            cam.near = 0.3f, cam.far = 30.0f;
            cam.aspect = float(s.width) / float(s.height);
            const glm::mat4 worldFromClip = glm::inverse(cam.clipFromView() * cam.viewFromWorld());
            auto world = [&](float x, float y, float z) {
                const glm::vec4 p = worldFromClip * glm::vec4(x, y, z, 1.0f);
                return glm::vec3(p) / p.w;
            };
            Mesh m;
            m.name = "guard band";
            for (int t = 0; t < 24; ++t) {
                const float side = t % 2 == 0 ? 1.0f : -1.0f;
                const glm::vec3 p[3] = {world(side * (64.0f + u(rng)), u(rng), 0.9f * u(rng)),
                                        world(0.9f * u(rng), 0.9f * u(rng), 0.9f * u(rng)),
                                        world(0.9f * u(rng), 0.9f * u(rng), 0.9f * u(rng))};
                for (const glm::vec3& q : p) {
                    m.positions.push_back(q);
                    m.normals.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.0f)));
                    m.indices.push_back(std::uint32_t(m.positions.size() - 1));
                }
            }
            Scene scene;
            scene.lights = defaultLights();
            scene.meshes = {std::move(m)};
            scene.instances = {Instance{}};
            RigParams p;
            p.kind = RigKind::OffAxis, p.columns = c, p.rows = r;
            p.convergence = 3.0f, p.interaxial = 0.6f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig) << rig.status().message();
            expectSame(*backend, scene, *rig, s, stats);
        }
    }
    EXPECT_GT(stats.covered, stats.renders * 300);
}

TEST(UnifiedEqualsMultipass, GridRowsBinnedFromTheOuterRowsKeepWhatOnlyAnInnerRowSees) {
    // unified bins a grid's triangles from its two outermost rows (a vertex's y is monotone in
    // the row's shear). A triangle near the camera with a vertical parallax larger than the
    // screen lies above the screen in one outer row, below it in the other and on screen in the
    // rows between: it must reach those rows' bands. Where each view sees it is computed here
    // from the rig's own view matrices; then unified against multipass, 1 and 3 columns, 3 and
    // 5 rows, every shading and wireframe.
    auto backend = makeSoftBackend();
    Stats stats;
    Camera cam;
    cam.position = {0.0f, 0.0f, 3.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.near = 0.1f, cam.far = 30.0f;
    RenderSettings s;
    s.width = 48, s.height = 64;  // 4 bands of 16 rows
    cam.aspect = float(s.width) / float(s.height);
    int seenOnlyInside = 0;
    for (auto [c, r] : {std::pair{1, 3}, {3, 3}, {1, 5}, {3, 5}}) {
        RigParams p;
        p.kind = RigKind::OffAxis, p.columns = c, p.rows = r;
        p.convergence = 3.0f, p.interaxial = 0.4f;
        auto rig = makeRig(cam, p);
        ASSERT_TRUE(rig) << rig.status().message();
        // A small triangle 0.5 in front of the camera, on its axis.
        const glm::vec3 centre{0.0f, 0.0f, 2.5f};
        const glm::vec3 tri[3] = {centre + glm::vec3(-0.01f, -0.01f, 0.0f),
                                  centre + glm::vec3(0.01f, -0.01f, 0.0f),
                                  centre + glm::vec3(0.0f, 0.01f, 0.0f)};
        // Its NDC y in each view: all three vertices above (+1) or below (-1) the screen, or not.
        auto side = [&](const View& v) {
            int above = 0, below = 0;
            for (const glm::vec3& q : tri) {
                const glm::vec4 clip = v.clipFromWorld() * glm::vec4(q, 1.0f);
                above += clip.y > clip.w, below += clip.y < -clip.w;
            }
            return above == 3 ? 1 : below == 3 ? -1 : 0;
        };
        const int first = side(rig->views.front()), last = side(rig->views.back());
        ASSERT_EQ(first * last, -1)
            << c << "x" << r << ": the outer rows must see it on opposite sides";
        ASSERT_EQ(side(rig->views[std::size_t(c * (r / 2))]), 0) << "the middle row sees it";
        Mesh m;
        m.name = "parallax";
        for (const glm::vec3& q : tri) {
            m.positions.push_back(q);
            m.normals.push_back({0.0f, 0.0f, 1.0f});
            m.indices.push_back(std::uint32_t(m.positions.size() - 1));
        }
        Scene scene;
        scene.lights = defaultLights();
        scene.meshes = {std::move(m)};
        scene.instances = {Instance{}};
        for (int mode = 0; mode < 4; ++mode) {
            s.shading = static_cast<Shading>(mode % 3);
            s.wireframe = mode == 3;
            expectSame(*backend, scene, *rig, s, stats);
            auto mp = backend->render(scene, *rig, s, "multipass");
            ASSERT_TRUE(mp);
            long inner = 0, outer = 0;
            for (int row = 0; row < r; ++row) {
                for (int col = 0; col < c; ++col) {
                    const DepthImage& d = mp->depth[std::size_t(row * c + col)];
                    const long n = std::count_if(d.depth.begin(), d.depth.end(),
                                                 [](float z) { return z < 1.0f; });
                    (row == 0 || row == r - 1 ? outer : inner) += n;
                }
            }
            EXPECT_EQ(outer, 0);
            EXPECT_GT(inner, 0);
            seenOnlyInside += inner > 0 && outer == 0;
        }
    }
    EXPECT_EQ(seenOnlyInside, 16);
}

TEST(UnifiedEqualsMultipass, SmallGridsKeepEachViewsOrderAcrossFullFlushes) {
    // Grids of 2-4 rows of 2-4 views queue a triangle's rows at once and draw the lane queue
    // whenever it is full, moving the lanes past the 16th to the next flush
    // (LaneQueue::addRows / flushFull). Hundreds of pixel-sized triangles, a third of them
    // repeating an earlier one with other normals (other vertex colors, the same depth: the
    // first drawn must keep the pixel) and some lying in one plane (ties between different
    // triangles): any lane drawn out of its view's order, with another triangle's slot, or
    // dropped changes colors. Unified against multipass, vertex and flat shading, 3 band
    // heights (rows of a triangle straddle bands).
    auto backend = makeSoftBackend();
    std::mt19937 rng(9090);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    Stats stats;
    int i = 0;
    for (auto [c, r] : {std::pair{2, 2}, {3, 2}, {2, 3}, {3, 3}, {4, 4}, {4, 2}, {2, 4}, {3, 4}}) {
        for (int mode = 0; mode < 3; ++mode, ++i) {
            SCOPED_TRACE(fmt::format("{}x{} mode {}", c, r, mode));
            Mesh m;
            m.name = "ties";
            const int count = 300 + int(rng() % 200);
            for (int t = 0; t < count; ++t) {
                const std::size_t base = m.positions.size();
                if (t > 3 && t % 3 == 0) {
                    // an earlier triangle again, other normals
                    const std::size_t src = 3 * (rng() % std::size_t(t));
                    for (int k = 0; k < 3; ++k) m.positions.push_back(m.positions[src + k]);
                } else {
                    const bool plane = t % 5 == 1;
                    const glm::vec3 centre(u(rng) * 1.2f, u(rng) * 0.9f, plane ? 0.0f : u(rng));
                    const float size = 0.02f + 0.05f * (u(rng) * 0.5f + 0.5f);
                    for (int k = 0; k < 3; ++k) {
                        glm::vec3 d(u(rng), u(rng), plane ? 0.0f : u(rng) * 0.3f);
                        m.positions.push_back(centre + d * size);
                    }
                }
                for (int k = 0; k < 3; ++k) {
                    m.normals.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.0f)));
                    m.indices.push_back(std::uint32_t(base + std::size_t(k)));
                }
            }
            Scene scene;
            scene.lights = defaultLights();
            scene.meshes = {std::move(m)};
            scene.instances = {Instance{}};
            RenderSettings s;
            s.width = 64 + 32 * (i % 3), s.height = 48 + 40 * (i % 3);
            s.shading = mode == 1 ? Shading::Flat : Shading::Vertex;
            Camera cam;
            cam.position = {0.0f, 0.0f, 3.0f};
            cam.target = {0.0f, 0.0f, 0.0f};
            cam.near = 0.3f, cam.far = 30.0f;
            cam.aspect = float(s.width) / float(s.height);
            RigParams p;
            p.kind = RigKind::OffAxis, p.columns = c, p.rows = r;
            p.convergence = 3.0f, p.interaxial = 0.05f + 0.1f * float(mode);
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig) << rig.status().message();
            expectSame(*backend, scene, *rig, s, stats);
        }
    }
    EXPECT_GT(stats.covered, stats.renders * 1000);
}

TEST(UnifiedEqualsMultipass, LongRowsAndBigGrids) {
    // Light-field panels: off-axis rows of 16..100 views and grids up to 9x9 (issue 12), every
    // shading, culling on and off, wireframe, on small random soups (near plane, guard band).
    auto backend = makeSoftBackend();
    std::mt19937 rng(4512);
    Stats stats;
    expectSameOnSoups(*backend, rng,
                      {{16, 1}, {45, 1}, {48, 1}, {66, 1}, {72, 1}, {100, 1}, {4, 4}, {8, 6}, {9, 9}},
                      stats);
    EXPECT_GT(stats.covered, stats.renders * 200);
}

/// The Stanford bunny from $MVR_SHARED_DIR/models in a grid of `copies`; nullopt when the file
/// is not there (the caller skips) or does not load (a failure, reported here).
std::optional<Scene> bunnyGrid(int copies) {
    const auto path = modelsDir() / "stanford-bunny.obj";
    if (!std::filesystem::exists(path)) return std::nullopt;
    auto mesh = loadMesh(path);
    EXPECT_TRUE(mesh) << mesh.status().message();
    if (!mesh) return std::nullopt;
    return makeGridScene({std::move(mesh).value()}, copies);
}

TEST(UnifiedEqualsMultipass, BunnyAtHundredViews) {
    // Real geometry (most triangles below a pixel) on a 100-view row, low resolution.
    const std::optional<Scene> bunny = bunnyGrid(1);
    if (!bunny) MVR_SKIP(ModelsMissing) << "no bunny in " << modelsDir();
    const Scene& scene = *bunny;
    const Bounds b = scene.bounds();
    Stats stats;
    RenderSettings s;
    s.width = 42, s.height = 56;
    Camera cam;
    cam.target = b.center();
    cam.position = b.center() + glm::vec3(0.0f, 0.0f, 2.5f * b.radius());
    cam.near = 0.5f * b.radius(), cam.far = 10.0f * b.radius();
    cam.aspect = float(s.width) / float(s.height);
    RigParams p;
    p.kind = RigKind::OffAxis, p.columns = 100, p.rows = 1;
    p.convergence = 2.5f * b.radius(), p.interaxial = p.convergence / 60.0f;
    auto rig = makeRig(cam, p);
    ASSERT_TRUE(rig) << rig.status().message();
    // Drawn into the images (streamAboveBytes at its largest: never streamed), and streamed
    // (SoftOptions::streamAboveBytes = 0: each band drawn into the workers' scratch and copied
    // into the images).
    for (const std::size_t streamAbove :
         {std::numeric_limits<std::size_t>::max(), std::size_t(0)}) {
        auto backend = makeSoftBackend(SoftOptions{.streamAboveBytes = streamAbove});
        for (int mode = 0; mode < 3; ++mode) {
            s.shading = static_cast<Shading>(mode);
            s.cullBackFaces = mode == 1;
            expectSame(*backend, scene, *rig, s, stats);
        }
    }
    EXPECT_GT(stats.covered, stats.renders * 100 * 200);
}

TEST(UnifiedEqualsMultipass, RenderingIntoAUsedOutputEqualsAFreshRender) {
    // The images of a caller's output are kept between frames (renderInto) and each band's rows
    // are cleared only by the task that draws them (clearRows): a frame drawn into an output that
    // holds another scene's pixels must equal a fresh render, every view, color and depth. The
    // first frame is the default scene; the second a small quad with another clear color, so
    // that a row left uncleared would show the first frame's pixels.
    // Drawn into the images (never streamed), and with every frame's bands streamed
    // (SoftOptions::streamAboveBytes = 0: unified draws into the workers' scratch and copies
    // each band's rows into the images).
    for (const std::size_t streamAbove :
         {std::numeric_limits<std::size_t>::max(), std::size_t(0)}) {
        auto backend = makeSoftBackend(SoftOptions{.streamAboveBytes = streamAbove});
        const Scene first = makeDefaultScene();
        const Scene second = test::quadScene({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f});
        const Camera cam = defaultSceneCamera(64.0f / 48.0f);
        long stale = 0;
        for (auto [c, r] : {std::pair{1, 1}, {2, 1}, {45, 1}, {3, 3}}) {
            RigParams p;
            p.columns = c, p.rows = r, p.interaxial = 0.05f, p.convergence = 6.0f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig) << rig.status().message();
            for (const char* method : {"multipass", "unified"}) {
                for (int mode = 0; mode < 3; ++mode) {
                    RenderSettings s;
                    s.width = 64, s.height = 48;
                    s.shading = static_cast<Shading>(mode);
                    s.clearColor = {0.1f, 0.2f, 0.3f};
                    RenderOutput out;
                    ASSERT_TRUE(backend->renderInto(first, *rig, s, method, out));
                    const RenderOutput before = out;
                    s.clearColor = {0.7f, 0.1f, 0.4f};
                    s.wireframe = mode == 2;
                    ASSERT_TRUE(backend->renderInto(second, *rig, s, method, out));
                    auto fresh = backend->render(second, *rig, s, method);
                    ASSERT_TRUE(fresh) << fresh.status().message();
                    EXPECT_EQ(firstDifference(out, *fresh), "")
                        << method << " " << c << "x" << r << " shading " << mode << " streamed "
                        << (streamAbove == 0);
                    for (std::size_t v = 0; v < before.depth.size(); ++v) {
                        for (std::size_t i = 0; i < before.depth[v].depth.size(); ++i)
                            stale +=
                                before.depth[v].depth[i] < 1.0f && fresh->depth[v].depth[i] == 1.0f;
                    }
                }
            }
        }
        EXPECT_GT(stale, 100000);  // pixels the first frame drew and the second must clear
    }
}

/// check(scene, rig, settings) on rows of each of `viewCounts` views of the default scene in
/// every shading, with and without culling, and wireframe, at width × height.
template <class Check>
void forDefaultSceneRows(std::initializer_list<int> viewCounts, int width, int height,
                         Check&& check) {
    const Scene scene = makeDefaultScene();
    const Camera cam = defaultSceneCamera(float(width) / float(height));
    for (const int views : viewCounts) {
        for (int mode = 0; mode < 6; ++mode) {
            RenderSettings s;
            s.width = width, s.height = height;
            s.shading = static_cast<Shading>(mode % 3);
            s.cullBackFaces = mode >= 3;
            s.wireframe = mode == 5;
            RigParams p;
            p.columns = views, p.rows = 1, p.interaxial = 0.2f, p.convergence = 6.0f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig);
            check(scene, *rig, s);
        }
    }
}

/// check(scene, rig, settings) on `count` random soups (crossing the near plane and the screen
/// edges) with random settings and rigs.
template <class Check>
void forRandomSoups(std::mt19937& rng, int count, Check&& check) {
    for (int i = 0; i < count; ++i) {
        SCOPED_TRACE(fmt::format("soup case {}", i));
        const Scene soup = randomSoup(rng, 40 + int(rng() % 60));
        const RenderSettings s = randomSettings(rng, i);
        Camera c0;
        c0.position = {0.0f, 0.0f, 3.0f};
        c0.near = 0.3f, c0.far = 30.0f;
        c0.aspect = float(s.width) / float(s.height);
        check(soup, randomRig(rng, c0, i), s);
    }
}

TEST(UnifiedEqualsMultipass, MultipassStreamedEqualsDrawnIntoTheImages) {
    // Multipass streams its bands too (FrameContext::streamBands: each view's band drawn into a
    // worker's scratch, then its rows copied into the image): always streamed (streamAboveBytes
    // = 0) against never (the largest threshold), every shading, culling and wireframe, one and
    // three views of the default scene and random soups crossing the near plane and the edges.
    auto always = makeSoftBackend(SoftOptions{.streamAboveBytes = 0});
    auto never =
        makeSoftBackend(SoftOptions{.streamAboveBytes = std::numeric_limits<std::size_t>::max()});
    long covered = 0;
    auto compare = [&](const Scene& scene, const Rig& rig, const RenderSettings& s) {
        auto a = always->render(scene, rig, s, "multipass");
        ASSERT_TRUE(a) << a.status().message();
        auto n = never->render(scene, rig, s, "multipass");
        ASSERT_TRUE(n) << n.status().message();
        ASSERT_EQ(firstDifference(*a, *n), "")
            << "views " << rig.viewCount() << " shading " << shadingName(s.shading) << " cull "
            << s.cullBackFaces << " wireframe " << s.wireframe;
        covered += coveredPixels(*n);
    };
    forDefaultSceneRows({1, 3}, 96, 70, compare);  // bands of 16 rows and a shorter last one
    std::mt19937 rng(4711);
    forRandomSoups(rng, 10, compare);
    EXPECT_GT(covered, 20000);
}

TEST(UnifiedEqualsMultipass, StreamedBandsEqualMultipass) {
    // SoftOptions::streamAboveBytes = 0: every frame's bands are drawn into the workers' scratch
    // and streamed into the images (by default only frames of more than 4 MiB of images). Rows
    // of 2 and 9 views of the default scene, a 3x3 grid, long rows and a 9x9 grid of random soups,
    // random rigs (toe-in, parallel, lists), against multipass (streamed too:
    // MultipassStreamedEqualsDrawnIntoTheImages); the bunny at 100 views: BunnyAtHundredViews.
    auto backend = makeSoftBackend(SoftOptions{.streamAboveBytes = 0});
    Stats stats;
    auto same = [&](const Scene& scene, const Rig& rig, const RenderSettings& s) {
        expectSame(*backend, scene, rig, s, stats);
    };
    forDefaultSceneRows({2, 9}, 80, 60, same);
    std::mt19937 rng(909);
    expectSameOnSoups(*backend, rng, {{3, 3}, {16, 1}, {45, 1}, {100, 1}, {9, 9}}, stats);
    forRandomSoups(rng, 15, same);
    EXPECT_GT(stats.covered, stats.renders * 100);
}

TEST(UnifiedEqualsMultipass, ManyViewsAreCheckedForMemoryUpFront) {
    // kMaxViews (128) views render; their images are checked against kMaxFramebufferBytes before
    // anything is allocated: a clear Status naming the views, the size and the GiB.
    static_assert(kMaxViews >= 128);
    auto backend = makeSoftBackend();
    std::mt19937 rng(5);
    const Scene scene = randomSoup(rng, 8);
    Camera cam;
    cam.position = {0.0f, 0.0f, 3.0f};
    RigParams p;
    p.columns = kMaxViews, p.rows = 1, p.convergence = 3.0f, p.interaxial = 0.01f;
    auto rig = makeRig(cam, p);
    ASSERT_TRUE(rig) << rig.status().message();
    RenderSettings s;
    s.width = 16, s.height = 12;
    for (const char* method : {"multipass", "unified"}) {
        auto r = backend->render(scene, *rig, s, method);
        ASSERT_TRUE(r) << r.status().message();
        EXPECT_EQ(r->color.size(), std::size_t(kMaxViews));
    }
    s.width = 4096, s.height = 4096;  // 128 x 4096 x 4096 x 8 bytes = 16 GiB > 8 GiB
    for (const char* method : {"multipass", "unified"}) {
        auto r = backend->render(scene, *rig, s, method);
        ASSERT_FALSE(r);
        EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
        EXPECT_NE(r.status().message().find("128 views of 4096x4096 need 16.0 GiB"),
                  std::string::npos)
            << r.status().message();
    }
    p.columns = kMaxViews + 1;
    EXPECT_FALSE(makeRig(cam, p));
}

TEST(UnifiedEqualsMultipass, ScalarPathEqualsSimdPath) {
    auto scalar = makeSoftBackend(SoftOptions{.threads = 1, .simd = SimdPath::Scalar});
    auto best = makeSoftBackend(SoftOptions{.threads = 0, .simd = SimdPath::Auto});
    std::mt19937 rng(5);
    for (int i = 0; i < 8; ++i) {
        const Scene scene = randomSoup(rng, 80);
        RenderSettings s = randomSettings(rng, i);
        Camera cam;
        cam.position = {0.0f, 0.0f, 3.0f};
        cam.near = 0.3f, cam.far = 30.0f;
        cam.aspect = float(s.width) / float(s.height);
        const Rig rig = randomRig(rng, cam, i);
        for (const char* method : {"multipass", "unified"}) {
            auto a = scalar->render(scene, rig, s, method);
            auto b = best->render(scene, rig, s, method);
            ASSERT_TRUE(a && b);
            EXPECT_EQ(firstDifference(*a, *b), "") << method << " case " << i;
        }
    }
}

TEST(UnifiedEqualsMultipass, ScalarPathEqualsSimdPathOnTheBunny) {
    // Real geometry (most triangles below a pixel): the lane queue's fragments go through
    // Kernels::drawLanes on AVX-512 CPUs — in multipass always, in unified when its bands are
    // streamed (the views' scratch is one block) — and through the ordered walk on the scalar
    // path. One view, a stereo pair and a 3x3 grid, every shading, streamed and not.
    const std::optional<Scene> bunny = bunnyGrid(2);
    if (!bunny) MVR_SKIP(ModelsMissing) << "no bunny in " << modelsDir();
    const Scene& scene = *bunny;
    const Bounds b = scene.bounds();
    RenderSettings s;
    s.width = 160, s.height = 120;
    Camera cam;
    cam.target = b.center();
    cam.position = b.center() + glm::vec3(0.3f, 0.2f, 2.2f) * b.radius();
    cam.near = 0.5f * b.radius(), cam.far = 10.0f * b.radius();
    cam.aspect = float(s.width) / float(s.height);
    long covered = 0;
    for (const std::size_t streamAbove :
         {std::numeric_limits<std::size_t>::max(), std::size_t(0)}) {
        auto scalar = makeSoftBackend(
            SoftOptions{.threads = 1, .simd = SimdPath::Scalar, .streamAboveBytes = streamAbove});
        auto best = makeSoftBackend(
            SoftOptions{.threads = 2, .simd = SimdPath::Auto, .streamAboveBytes = streamAbove});
        for (const auto& [columns, rows] : {std::pair{1, 1}, {2, 1}, {3, 3}}) {
            RigParams p;
            p.columns = columns, p.rows = rows;
            p.convergence = 2.2f * b.radius(), p.interaxial = p.convergence / 30.0f;
            auto rig = makeRig(cam, p);
            ASSERT_TRUE(rig) << rig.status().message();
            for (int mode = 0; mode < 3; ++mode) {
                s.shading = static_cast<Shading>(mode);
                for (const char* method : {"multipass", "unified"}) {
                    auto a = scalar->render(scene, *rig, s, method);
                    auto c = best->render(scene, *rig, s, method);
                    ASSERT_TRUE(a && c);
                    EXPECT_EQ(firstDifference(*a, *c), "")
                        << method << " " << columns << "x" << rows << " shading "
                        << shadingName(s.shading) << " stream above " << streamAbove;
                    covered += coveredPixels(*c);
                }
            }
        }
    }
    EXPECT_GT(covered, 2L * 3 * 2 * 11 * 3000);  // ~11 views a case, each a few thousand pixels
}

TEST(UnifiedEqualsMultipass, ShearFormMatchesTheViewMatrices) {
    // The shear form both methods use must place points where the views' own matrices do.
    Camera cam;
    cam.position = {1.0f, 2.0f, 7.0f};
    cam.target = {0.0f, 0.5f, 0.0f};
    RigParams p;
    p.columns = 3, p.rows = 2, p.interaxial = 0.4f, p.convergence = 6.0f;
    auto rig = makeRig(cam, p);
    ASSERT_TRUE(rig);
    const glm::mat4 center = cam.clipFromView() * cam.viewFromWorld();
    for (const View& v : rig->views) {
        ASSERT_TRUE(v.clipShear);
        for (glm::vec3 world :
             {glm::vec3(0.0f), glm::vec3(1.0f, -1.0f, 2.0f), glm::vec3(-2.0f, 1.0f, -5.0f)}) {
            const glm::vec4 c = center * glm::vec4(world, 1.0f);
            const glm::vec4 m = v.clipFromWorld() * glm::vec4(world, 1.0f);
            EXPECT_NEAR(c.x + v.clipShear->x * (c.w - rig->convergence), m.x, 1e-4f);
            EXPECT_NEAR(c.y + v.clipShear->y * (c.w - rig->convergence), m.y, 1e-4f);
            EXPECT_NEAR(c.w, m.w, 1e-4f);
        }
    }
}

}  // namespace
}  // namespace mvr::raster
