// Shadows (issue 15) against numbers computed by hand: a box above a plane, lit from a known
// direction (or a spot straight above it); the shadow polygon on the plane is the box's
// projection along the light, computed here from the box's corners; each pixel of every view
// is mapped back to the world through its depth and the view's inverse clip transform (not the
// shadow code), and pixels on the plane inside the polygon (away from a PCF margin) must be
// darker than the same pixel without shadows, pixels outside it exactly as lit.
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "mvr/backends.h"
#include "mvr/core/billboards.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/shadows.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

Mesh boxMesh(glm::vec3 lo, glm::vec3 hi) {
    Mesh m;
    m.name = "box";
    const glm::vec3 n[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& f : n) {
        // Two axes spanning the face, counter-clockwise seen from outside.
        glm::vec3 u = std::fabs(f.x) > 0 ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
        glm::vec3 v = glm::cross(f, u);
        const auto base = std::uint32_t(m.positions.size());
        const glm::vec3 c = (lo + hi) * 0.5f, h = (hi - lo) * 0.5f;
        for (int k = 0; k < 4; ++k) {
            const float a = (k == 1 || k == 2) ? 1.0f : -1.0f, b = k >= 2 ? 1.0f : -1.0f;
            m.positions.push_back(c + (f + a * u + b * v) * h);
            m.normals.push_back(f);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

Mesh planeMesh(float half, int cells) {
    Mesh m;
    m.name = "plane";
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            m.positions.push_back(
                {-half + 2 * half * i / cells, 0.0f, half - 2 * half * j / cells});
            m.normals.push_back({0, 1, 0});
        }
    }
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const auto a = std::uint32_t(j * (cells + 1) + i), b = a + 1,
                       c = a + std::uint32_t(cells + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, b, d, a, d, c});  // ccw seen from +y
        }
    }
    return m;
}

const glm::vec3 kBoxLo{-0.5f, 1.0f, -0.5f}, kBoxHi{0.5f, 1.5f, 0.5f};

Scene boxScene(const Light& light, int planeCells = 16) {
    Scene s;
    s.meshes = {planeMesh(4.0f, planeCells), boxMesh(kBoxLo, kBoxHi)};
    s.instances = {Instance{0, glm::mat4(1.0f), Material{}},
                   Instance{1, glm::mat4(1.0f), Material{}}};
    s.lights = {light};
    s.ambient = glm::vec3(0.1f);
    return s;
}

Rig stereoRig(int views) {
    Camera cam;
    cam.position = {1.5f, 7.0f, 5.0f};
    cam.target = {-0.5f, 0.0f, 0.0f};
    cam.aspect = 4.0f / 3.0f;
    cam.near = 0.5f;
    cam.far = 30.0f;
    RigParams p;
    p.columns = views;
    p.interaxial = 0.3f;
    p.convergence = glm::length(cam.target - cam.position);
    return *makeRig(cam, p);
}

/// Axis-aligned rectangle on the plane (x, z) with a signed distance.
struct Rect {
    float x0, x1, z0, z1;
    /// > 0 inside: distance to the border; < 0 outside.
    float inside(float x, float z) const {
        return std::min(std::min(x - x0, x1 - x), std::min(z - z0, z1 - z));
    }
};

struct Counts {
    int inside = 0, outside = 0, insideDarker = 0, outsideSame = 0;
};

Counts classify(const Rig& rig, const RenderOutput& lit, const RenderOutput& shadowed,
                const Rect& shadow, float margin) {
    Counts c;
    for (int v = 0; v < rig.viewCount(); ++v) {
        const glm::mat4 worldFromClip = glm::inverse(rig.views[std::size_t(v)].clipFromWorld());
        const DepthImage& d = shadowed.depth[std::size_t(v)];
        const Image& a = lit.color[std::size_t(v)];
        const Image& b = shadowed.color[std::size_t(v)];
        for (int row = 0; row < d.height; ++row) {
            for (int x = 0; x < d.width; ++x) {
                const std::size_t i = std::size_t(row) * d.width + x;
                const float z = d.depth[i];
                if (!(z < 1.0f)) continue;
                const glm::vec4 ndc((x + 0.5f) / d.width * 2 - 1, 1 - (row + 0.5f) / d.height * 2,
                                    2 * z - 1, 1);
                glm::vec4 w = worldFromClip * ndc;
                const glm::vec3 p = glm::vec3(w) / w.w;
                if (std::fabs(p.y) > 0.02f) continue;  // not on the plane
                const float s = shadow.inside(p.x, p.z);
                const int la = a.rgba[4 * i] + a.rgba[4 * i + 1] + a.rgba[4 * i + 2];
                const int lb = b.rgba[4 * i] + b.rgba[4 * i + 1] + b.rgba[4 * i + 2];
                if (s > margin) {
                    ++c.inside;
                    c.insideDarker += lb + 60 < la;
                } else if (s < -margin) {
                    ++c.outside;
                    c.outsideSame += std::abs(lb - la) <= 3;
                }
            }
        }
    }
    return c;
}

struct Case {
    std::string backend, method;
};

/// One backend of each name per process (gl: one EGL context); nullptr where it cannot be made.
Backend* backendNamed(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Backend>> made;
    auto it = made.find(name);
    if (it == made.end()) {
        auto b = makeBackend(name);
        it = made.emplace(name, b ? std::move(*b) : nullptr).first;
    }
    return it->second.get();
}

std::vector<Case> cases() {
    std::vector<Case> out;
    for (const BackendEntry& e : backends()) {
        Backend* b = backendNamed(e.name);
        if (!b) continue;
        for (const std::string& m : b->methods()) {
            if (m == "auto") continue;
            if (!b->supports(m)) continue;
            out.push_back({e.name, m});
        }
    }
    return out;
}

/// `textured`: every material gets a white base color texture, so that the frame takes the
/// textured paths (lighting.h flatTerms / blinnPhongTerms; soft's textured attribute layout,
/// gl's LightTerms shaders), which must apply the shadow factors as the untextured ones do.
void checkShadow(const Light& light, const Rect& shadow, Shading shading, bool textured = false,
                 int planeCells = 16) {
    Scene scene = boxScene(light, planeCells);
    if (textured) {
        scene.textures.push_back(Texture{"white", Image(2, 2, Rgba8{255, 255, 255, 255})});
        for (Mesh& m : scene.meshes) m.texcoords.assign(m.positions.size(), glm::vec2(0.5f));
        for (Instance& i : scene.instances) i.material.baseColorTexture = 0;
    }
    const Rig rig = stereoRig(2);
    RenderSettings s;
    s.width = 160, s.height = 120;
    s.shading = shading;
    s.shadowMapSize = 512;
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.backend + ":" + c.method);
        Backend* backend = backendNamed(c.backend);
        RenderSettings off = s;
        // Compared with the shading the shadowed render uses (vertex: per pixel).
        off.shading = shadedSettings(RenderSettings{.shading = s.shading, .shadows = true}).shading;
        auto lit = backend->render(scene, rig, off, c.method);
        RenderSettings on = s;
        on.shadows = true;
        auto sh = backend->render(scene, rig, on, c.method);
        ASSERT_TRUE(lit) << lit.status().message();
        ASSERT_TRUE(sh) << sh.status().message();
        if (sh->depth.size() != std::size_t(rig.viewCount())) continue;  // no depth: not checkable
        // Margin: the 3x3 PCF reaches 1.5 texels; the map spans the scene (about 8.5 world
        // units along its larger side) in 512 texels; plus a pixel's footprint (~0.1 at 160 px).
        const float margin = 0.2f;
        const Counts k = classify(rig, *lit, *sh, shadow, margin);
        EXPECT_GT(k.inside, 100);
        EXPECT_GT(k.outside, 1000);
        EXPECT_EQ(k.insideDarker, k.inside);
        EXPECT_EQ(k.outsideSame, k.outside);
    }
}

// Light at a known angle: towardLight ∝ (1, 2, 0): a point at height y moves by −y/2 in x.
// Box bottom (y = 1) → x ∈ [−1, 0]; top (y = 1.5) → x ∈ [−1.25, −0.25]: the hull is
// x ∈ [−1.25, 0], z ∈ [−0.5, 0.5].
TEST(Shadows, DirectionalShadowFallsWhereTheProjectionPutsIt) {
    Light l;
    l.towardLight = glm::normalize(glm::vec3(1, 2, 0));
    l.color = glm::vec3(0.8f);
    for (Shading sh : {Shading::Pixel, Shading::Vertex}) {  // vertex: shaded per pixel
        SCOPED_TRACE(int(sh));
        checkShadow(l, Rect{-1.25f, 0.0f, -0.5f, 0.5f}, sh);
    }
}

// A ground of one quad (four vertices, two triangles) under a floating box, the light straight
// down: per vertex the shadow vanished (every vertex is lit, so every pixel was: issue 39's
// plate). Vertex shading with shadows is shaded per pixel (shadedSettings): the footprint is
// dark, everything else unchanged, on every backend and method.
TEST(Shadows, AGroundOfFourVerticesShowsTheShadowUnderVertexShading) {
    Light l;
    l.towardLight = {0, 1, 0};
    l.color = glm::vec3(0.8f);
    checkShadow(l, Rect{-0.5f, 0.5f, -0.5f, 0.5f}, Shading::Vertex, false, 1);
    RenderSettings s;
    s.shading = Shading::Vertex;
    EXPECT_EQ(shadedSettings(s).shading, Shading::Vertex);  // no shadows: as asked
    s.shadows = true;
    EXPECT_EQ(shadedSettings(s).shading, Shading::Pixel);
    s.shading = Shading::Flat;
    EXPECT_EQ(shadedSettings(s).shading, Shading::Flat);
}

// Light straight down: the shadow is the box's footprint x, z ∈ [−0.5, 0.5].
TEST(Shadows, StraightDownShadowIsTheFootprint) {
    Light l;
    l.towardLight = {0, 1, 0};
    l.color = glm::vec3(0.8f);
    checkShadow(l, Rect{-0.5f, 0.5f, -0.5f, 0.5f}, Shading::Pixel);
}

// A spot at (0, 4, 0) pointing down: a corner at height y projects to x·4/(4 − y); the top
// (y = 1.5) gives ±0.8, the bottom ±0.667: the hull is x, z ∈ [−0.8, 0.8].
TEST(Shadows, SpotShadowIsThePerspectiveProjection) {
    Light l;
    l.type = LightType::Spot;
    l.position = {0, 4, 0};
    l.towardLight = {0, 1, 0};
    l.outerConeCos = std::cos(glm::radians(60.0f));
    l.innerConeCos = std::cos(glm::radians(55.0f));
    // Spot lights fall off as 1 / d² (lighting.h, KHR_lights_punctual): 16 × 0.8 gives the
    // plane below (d ≈ 4) about the 0.8 of the directional cases, so the shadow stays visible.
    l.color = glm::vec3(0.8f * 16.0f);
    checkShadow(l, Rect{-0.8f, 0.8f, -0.8f, 0.8f}, Shading::Pixel);
}

// Textured surfaces (issue 14's textured shading) are shadowed like untextured ones, in every
// shading mode's textured path.
TEST(Shadows, TexturedSurfacesAreShadowedToo) {
    Light l;
    l.towardLight = {0, 1, 0};
    l.color = glm::vec3(0.8f);
    for (Shading sh : {Shading::Pixel, Shading::Flat}) {
        SCOPED_TRACE(int(sh));
        checkShadow(l, Rect{-0.5f, 0.5f, -0.5f, 0.5f}, sh, true);
    }
}

bool sameImages(const RenderOutput& a, const RenderOutput& b) {
    if (a.color.size() != b.color.size()) return false;
    for (std::size_t v = 0; v < a.color.size(); ++v) {
        if (a.color[v].rgba != b.color[v].rgba) return false;
        if (a.depth[v].depth != b.depth[v].depth) return false;
    }
    return true;
}

TEST(Shadows, SoftUnifiedEqualsMultipassBitForBit) {
    Scene scene = makeDefaultScene();
    Backend* backend = backendNamed("soft");
    Camera cam;
    cam.position = {0, 2.5f, 7};
    RigParams p;
    p.columns = 4;
    p.interaxial = 0.2f;
    p.convergence = 7.0f;
    const Rig rig = *makeRig(cam, p);
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        RenderSettings s;
        s.width = 200, s.height = 150;
        s.shading = sh;
        s.shadows = true;
        s.shadowMapSize = 512;
        auto a = backend->render(scene, rig, s, "multipass");
        auto b = backend->render(scene, rig, s, "unified");
        ASSERT_TRUE(a && b);
        EXPECT_TRUE(sameImages(*a, *b)) << "shading " << int(sh);
        s.shadows = false;
        auto c = backend->render(scene, rig, s, "unified");
        ASSERT_TRUE(c);
        EXPECT_FALSE(sameImages(*b, *c)) << "shadows changed nothing, shading " << int(sh);
    }
}

// kalaiah2007 §3: the lights are the views. Four casters (three directional, one spot): their
// maps as ONE multi-view render equal the four single-view renders bit for bit.
TEST(Shadows, KLightsOnePassEqualsKPasses) {
    Scene scene = makeDefaultScene();
    for (Light& l : scene.lights) l.castsShadow = true;
    Light spot;
    spot.type = LightType::Spot;
    spot.position = {1, 5, 2};
    spot.towardLight = glm::normalize(glm::vec3(1, 5, 2));
    spot.castsShadow = true;
    scene.lights.push_back(spot);
    ASSERT_EQ(shadowCasters(scene).size(), 4u);
    Backend* backend = backendNamed("soft");
    for (const char* method : {"unified", "multipass"}) {
        auto one = renderShadowSet(*backend, scene, 256, method, true);
        auto many = renderShadowSet(*backend, scene, 256, method, false);
        ASSERT_TRUE(one && many);
        ASSERT_EQ(one->maps.size(), 4u);
        for (std::size_t k = 0; k < 4; ++k) {
            EXPECT_EQ(one->maps[k].depth, many->maps[k].depth) << method << " light " << k;
            int covered = 0;
            for (float d : one->maps[k].depth) covered += d < one->maps[k].far;
            EXPECT_GT(covered, 1000) << "light " << k << " saw nothing";
        }
    }
}

// gl within a bound of soft:multipass with shadows, every gl method that returns depth, on this
// test's own camera (the conformance suite runs its camera with the same bounds). The bound:
// kGlVsSoft's edge pixels (2/255) plus shadow edges: gl's map is rasterized by llvmpipe (float
// edge functions), so a map texel at a silhouette may hold the occluder in one backend and the
// receiver in the other, which moves one 3x3 PCF tap (1/9 of the light, ~18/255 here) on the
// pixels whose kernel covers that texel — a band about one pixel wide along the shadow's edge.
TEST(Shadows, GlWithinBoundOfSoft) {
    Scene scene = makeDefaultScene();
    Backend* soft = backendNamed("soft");
    Backend* gl = backendNamed("gl");
    if (!gl) MVR_SKIP(FeatureNotBuilt) << "no gl backend";
    if (Status st = gl->supports("multipass"); !st) MVR_SKIP(NoGlContext) << st.message();
    Camera cam;
    cam.position = {0, 2.5f, 7};
    RigParams p;
    p.columns = 2;
    p.interaxial = 0.2f;
    p.convergence = 7.0f;
    const Rig rig = *makeRig(cam, p);
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        RenderSettings s;
        s.width = 160, s.height = 120;
        s.shading = sh;
        s.shadows = true;
        s.shadowMapSize = 512;
        auto ref = soft->render(scene, rig, s, "multipass");
        ASSERT_TRUE(ref);
        for (const std::string& m : gl->methods()) {
            if (m == "auto" || !gl->supports(m)) continue;
            auto out = gl->render(scene, rig, s, m);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            if (out->depth.empty()) continue;  // gs-mrt / gs-depthmap: their own bounds
            for (std::size_t v = 0; v < out->color.size(); ++v) {
                const auto& a = ref->color[v].rgba;
                const auto& b = out->color[v].rgba;
                int off = 0;
                for (std::size_t i = 0; i < a.size(); i += 4) {
                    bool bad = false;
                    for (int c = 0; c < 3; ++c) bad |= std::abs(int(a[i + c]) - int(b[i + c])) > 2;
                    off += bad;
                }
                const double share = double(off) / double(s.width * s.height);
                std::printf("[ measured ] gl:%s shading %d view %zu: %.3f %% > 2/255\n", m.c_str(),
                            int(sh), v, 100.0 * share);
                // The conformance table's shadow bounds (tests/conformance/tolerances.h, with
                // their reasons): flat 5 %, vertex / pixel 0.5 %; measured 0 % on llvmpipe.
                const conformance::Bound& bound = sh == Shading::Flat
                                                      ? conformance::kShadowedFlatGlVsSoft
                                                      : conformance::kShadowedGlVsSoft;
                EXPECT_TRUE(bound.first.holds(share)) << m << " shading " << int(sh) << " view " << v;
            }
        }
    }
}

// Billboards (billboards.h): in a plane parallel to the screen, drawn into every view with the
// parallax of their depth: separation × (1 − convergence / w), computed here from the rig's
// numbers; measured as the shift of each quad's pixel centroid between the two views.
TEST(Billboards, ParallaxIsThatOfTheirDepth) {
    Camera cam;
    cam.position = {0, 0, 5};
    cam.target = {0, 0, 0};
    cam.near = 0.5f, cam.far = 50.0f;
    cam.aspect = 4.0f / 3.0f;
    RigParams p;
    p.columns = 2;
    p.interaxial = 0.3f;
    p.convergence = 5.0f;
    const Rig rig = *makeRig(cam, p);
    Scene scene;
    scene.lights = defaultLights();
    const Billboard far{{0.0f, 0.8f, -3.0f}, 0.5f}, near{{0.0f, -0.5f, 2.0f}, 0.3f};
    const Billboard list[] = {far, near};
    appendBillboards(scene, list, rig.camera);
    ASSERT_TRUE(validateScene(scene));
    RenderSettings s;
    s.width = 400, s.height = 300;
    s.shading = Shading::Flat;
    auto out = backendNamed("soft")->render(scene, rig, s, "unified");
    ASSERT_TRUE(out);
    // Per view, upper half (the far quad) and lower half (the near one).
    auto centroid = [&](int v, bool upper, int* count, int* bboxArea) {
        const Image& im = out->color[std::size_t(v)];
        double sx = 0;
        int n = 0, x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1;
        for (int y = upper ? 0 : s.height / 2; y < (upper ? s.height / 2 : s.height); ++y) {
            for (int x = 0; x < s.width; ++x) {
                const std::size_t i = (std::size_t(y) * s.width + x) * 4;
                if (im.rgba[i] + im.rgba[i + 1] + im.rgba[i + 2] == 0) continue;
                sx += x + 0.5, ++n;
                x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y),
                y1 = std::max(y1, y);
            }
        }
        *count = n;
        *bboxArea = (x1 - x0 + 1) * (y1 - y0 + 1);
        return n ? sx / n : 0.0;
    };
    for (const auto& [b, upper] : {std::pair{far, true}, std::pair{near, false}}) {
        int n0, a0, n1, a1;
        const double c0 = centroid(0, upper, &n0, &a0), c1 = centroid(1, upper, &n1, &a1);
        ASSERT_GT(n0, 50);
        ASSERT_GT(n1, 50);
        // Parallel to the screen: an axis-aligned rectangle, the same in both views.
        EXPECT_EQ(n0, a0);
        EXPECT_EQ(n1, a1);
        const float w = 5.0f - b.center.z;  // distance in front of the eyes
        const double expected = double(rig.separation()) * (1.0 - 5.0 / double(w));
        // The centroid of covered pixels is within half a pixel of the quad's centre in each
        // view (its edges snap to pixel centres): one pixel for the difference of two views.
        EXPECT_NEAR((c1 - c0) / s.width, expected, 1.0 / s.width) << "w = " << w;
    }
}

TEST(Shadows, CastersAreTheKeyAndSpots) {
    Scene s = makeDefaultScene();
    EXPECT_EQ(shadowCasters(s), std::vector<int>{0});
    s.lights[2].castsShadow = true;
    EXPECT_EQ(shadowCasters(s), std::vector<int>{2});
}

}  // namespace
}  // namespace mvr
