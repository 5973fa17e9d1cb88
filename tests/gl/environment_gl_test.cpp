// Image lighting on the gl backend (issue 39 item 2, `--environment MAP`; environment.h,
// lighting.h environmentTerms): a synthetic radiance map (upper half warm, lower half cool, a
// bright patch) built with buildEnvironment and put on scenes of Blinn-Phong and
// metallic-roughness materials, untextured, textured and with glTF's maps, half of them
// double-sided, rendered by every gl method in flat, vertex and pixel shading against the soft
// backend (the reference) and against gl:multipass; the environment changes the image and
// taking it away restores it; values known in closed form (a uniform map of radiance c).
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "gl_test_util.h"
#include "mvr/core/environment.h"
#include "mvr/core/lighting.h"
#include "mvr/raster/soft_backend.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

constexpr int kW = 160, kH = 120;

RenderSettings settings(Shading shading) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = shading;
    s.cullBackFaces = false;  // the double-sided materials' back faces show
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

/// 64 × 32: the upper half warm, the lower half cool, a bright patch above the horizon ahead
/// and to the right (u ≈ 0.6, v ≈ 0.3), so reflections, the SH's bands and the prefiltered
/// levels all vary.
RadianceMap syntheticMap() {
    RadianceMap m;
    m.width = 64;
    m.height = 32;
    m.name = "synthetic";
    m.texels.resize(std::size_t(m.width * m.height));
    for (int y = 0; y < m.height; ++y) {
        for (int x = 0; x < m.width; ++x) {
            glm::vec3 c = y < m.height / 2 ? glm::vec3(1.0f, 0.8f, 0.55f)
                                           : glm::vec3(0.15f, 0.25f, 0.45f);
            if (x >= 36 && x < 44 && y >= 7 && y < 12) c = glm::vec3(6.0f, 5.5f, 4.5f);
            m.texels[std::size_t(y * m.width + x)] = c;
        }
    }
    return m;
}

const std::shared_ptr<const Environment>& environment() {
    static const std::shared_ptr<const Environment> env =
        std::make_shared<const Environment>(buildEnvironment(syntheticMap()));
    return env;
}

/// `s` under the environment, as the session sets it up (ambient 0: the map is the ambient
/// light), its lights at half strength (less of the picture clamped at white), every other
/// instance double-sided.
Scene lit(Scene s) {
    s.environment = environment();
    s.ambient = glm::vec3(0.0f);
    for (Light& l : s.lights) l.color *= 0.5f;
    for (std::size_t i = 0; i < s.instances.size(); i += 2)
        s.instances[i].material.doubleSided = true;
    return s;
}

struct Case {
    std::string name;
    Scene scene;
    bool textured = false;
};

const std::vector<Case>& cases() {
    static const std::vector<Case> c = [] {
        std::vector<Case> v;
        v.push_back({"blinn-phong", lit(defaultScene()), false});
        v.push_back({"metallic-roughness", lit(::mvr::test::pbrScene()), false});
        v.push_back({"textured", lit(makeTexturedScene()), true});
        v.push_back({"mapped", lit(::mvr::test::mappedScene()), true});
        // The environment alone (no lights): its terms are the whole picture.
        Scene dark = lit(::mvr::test::withMetallicRoughness(makeDefaultScene()));
        dark.lights.clear();
        v.push_back({"environment-only", std::move(dark), false});
        return v;
    }();
    return c;
}

/// An off-axis rig of columns × rows views closer to the scene than rigFor's (the default
/// scene's objects fill the views: its ground is large), so most pixels show the lighting.
Rig closeRig(const Scene& scene, int columns, int rows) {
    Camera cam = cameraFor(scene, float(kW) / kH);
    const float r = scene.bounds().radius();
    cam.position = cam.target + glm::vec3(0.0f, 0.3f * r, 0.9f * r);
    RigParams p;
    p.columns = columns;
    p.rows = rows;
    const float dist = glm::length(cam.position - cam.target);
    p.convergence = dist;
    p.interaxial = 0.06f * dist;
    p.interaxialY = 0.03f * dist;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

mvr::Backend& soft() {
    static std::unique_ptr<mvr::Backend> b = raster::makeSoftBackend();
    return *b;
}

struct Worst {
    double share = 0.0;
    int maxDelta = 0;
    std::string where;
    void add(const ImageDiff& d, double share_, const std::string& w) {
        if (share_ > share || (share_ == share && d.maxDelta > maxDelta)) where = w;
        share = std::max(share, share_);
        maxDelta = std::max(maxDelta, d.maxDelta);
    }
};

// Every gl method (the artifact rows too, on two views: gs-mrt, gs-depthmap) in every shading
// against soft:multipass. The bounds are the conformance suite's for gl vs soft (kGlVsSoft
// untextured, kTexturedGlVsSoft textured) and, for each exact method, gl:multipass's kGlExact.
TEST(GlEnvironment, EveryMethodMatchesSoftAndMultipass) {
    MVR_SKIP_WITHOUT_GL();
    for (const Case& c : cases()) {
        for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
            const Rig rig = closeRig(c.scene, 3, 2);
            const RenderSettings s = settings(sh);
            auto want = soft().render(c.scene, rig, s, "multipass");
            ASSERT_TRUE(want) << want.status().message();
            auto ref = backend().render(c.scene, rig, s, "multipass");
            ASSERT_TRUE(ref) << ref.status().message();
            const conformance::Bound& vsSoft =
                c.textured ? conformance::kTexturedGlVsSoft : conformance::kGlVsSoft;
            Worst worstSoft, worstExact;
            for (std::size_t v = 0; v < want->color.size(); ++v) {
                const ImageDiff d = compareImages(want->color[v], ref->color[v], vsSoft.channel);
                const double share = double(d.differingPixels) / (kW * kH);
                worstSoft.add(d, share, fmt::format("view {}", v));
                EXPECT_TRUE(vsSoft.shareFor(int(v)).holds(share))
                    << c.name << " " << shadingName(sh) << " view " << v << ": " << 100 * share
                    << " % off soft by more than " << vsSoft.channel << "/255, max "
                    << d.maxDelta;
            }
            for (const std::string& m : exactMethods()) {
                if (m == "multipass" || !backend().supports(m)) continue;
                auto out = backend().render(c.scene, rig, s, m);
                if (!out && out.status().code() == ErrorCode::Unsupported) continue;
                ASSERT_TRUE(out) << m << ": " << out.status().message();
                ASSERT_EQ(out->color.size(), ref->color.size()) << m;
                const conformance::Bound& b = conformance::kGlExact;
                for (std::size_t v = 0; v < ref->color.size(); ++v) {
                    const ImageDiff d = compareImages(ref->color[v], out->color[v], b.channel);
                    const double share = double(d.differingPixels) / (kW * kH);
                    worstExact.add(d, share, fmt::format("{} view {}", m, v));
                    EXPECT_TRUE(b.shareFor(int(v)).holds(share))
                        << c.name << " " << m << " " << shadingName(sh) << " view " << v << ": "
                        << 100 * share << " % off gl:multipass by more than " << b.channel
                        << "/255, max " << d.maxDelta;
                    // ... and so within the soft bound too
                    const ImageDiff ds =
                        compareImages(want->color[v], out->color[v], vsSoft.channel);
                    worstSoft.add(ds, double(ds.differingPixels) / (kW * kH),
                                  fmt::format("{} view {}", m, v));
                }
            }
            // The artifact rows on the two views they take: drawn with the same shaders.
            const Rig pair = closeRig(c.scene, 2, 1);
            auto ref2 = backend().render(c.scene, pair, s, "multipass");
            ASSERT_TRUE(ref2) << ref2.status().message();
            for (const char* m : {"gs-mrt", "gs-depthmap"}) {
                if (!backend().supports(m)) continue;
                auto out = backend().render(c.scene, pair, s, m);
                if (!out && out.status().code() == ErrorCode::Unsupported) continue;
                ASSERT_TRUE(out) << m << ": " << out.status().message();
                // The painter's order / disocclusion errors are the rows' own (tolerances.h);
                // here: the environment is drawn (the images are near gl:multipass's).
                for (std::size_t v = 0; v < out->color.size() && v < 2; ++v) {
                    const ImageDiff d = compareImages(ref2->color[v], out->color[v], 2);
                    EXPECT_LT(double(d.differingPixels) / (kW * kH), 0.31)
                        << c.name << " " << m << " " << shadingName(sh) << " view " << v;
                }
            }
            std::printf("[ measured ] environment %s %s: vs soft %.3f %% > %d/255 (max %d, %s); "
                        "exact methods vs gl:multipass %.3f %% > 2/255 (max %d, %s)\n",
                        c.name.c_str(), shadingName(sh), 100 * worstSoft.share,
                        vsSoft.channel, worstSoft.maxDelta, worstSoft.where.c_str(),
                        100 * worstExact.share, worstExact.maxDelta, worstExact.where.c_str());
        }
    }
}

// --specular per-view (pixel shading, each view's own eye: reflections move between views)
// against soft, and every exact method against gl:multipass.
TEST(GlEnvironment, PerViewEyeMatchesSoft) {
    MVR_SKIP_WITHOUT_GL();
    const Case& c = cases()[1];  // metallic-roughness: the reflections show the eye
    const Rig rig = closeRig(c.scene, 3, 2);
    RenderSettings s = settings(Shading::Pixel);
    s.specular = SpecularEye::PerView;
    auto want = soft().render(c.scene, rig, s, "multipass");
    ASSERT_TRUE(want) << want.status().message();
    auto ref = backend().render(c.scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    // The views' images differ from the centre eye's (the test sees the per-view eye).
    RenderSettings centre = settings(Shading::Pixel);
    auto central = backend().render(c.scene, rig, centre, "multipass");
    ASSERT_TRUE(central);
    EXPECT_GT(compareImages(central->color[0], ref->color[0], 2).differingPixels, 100);
    const conformance::Bound& b = conformance::kGlVsSoft;
    double worst = 0.0;
    int maxDelta = 0;
    for (std::size_t v = 0; v < want->color.size(); ++v) {
        const ImageDiff d = compareImages(want->color[v], ref->color[v], b.channel);
        const double share = double(d.differingPixels) / (kW * kH);
        worst = std::max(worst, share);
        maxDelta = std::max(maxDelta, d.maxDelta);
        EXPECT_TRUE(b.shareFor(int(v)).holds(share))
            << "view " << v << ": " << 100 * share << " %, max " << d.maxDelta;
    }
    for (const std::string& m : exactMethods()) {
        if (m == "multipass" || !backend().supports(m)) continue;
        auto out = backend().render(c.scene, rig, s, m);
        if (!out && (out.status().code() == ErrorCode::Unsupported ||
                     out.status().code() == ErrorCode::Usage))
            continue;
        ASSERT_TRUE(out) << m << ": " << out.status().message();
        for (std::size_t v = 0; v < ref->color.size(); ++v) {
            const ImageDiff d = compareImages(ref->color[v], out->color[v], 2);
            EXPECT_TRUE(conformance::kGlExact.shareFor(int(v))
                            .holds(double(d.differingPixels) / (kW * kH)))
                << m << " view " << v << ": max " << d.maxDelta;
        }
    }
    std::printf("[ measured ] environment per-view eye: vs soft %.3f %% > 2/255 (max %d)\n",
                100 * worst, maxDelta);
}

// Shadows (SHADOWS, unit 3) and the environment together: the shadows darken the lights' terms
// only (the environment has no shadow), against soft within the shadowed bounds, every exact
// method against gl:multipass.
TEST(GlEnvironment, WithShadowsMatchesSoft) {
    MVR_SKIP_WITHOUT_GL();
    const Case& c = cases()[1];
    const Rig rig = closeRig(c.scene, 2, 1);
    for (Shading sh : {Shading::Flat, Shading::Pixel}) {
        RenderSettings s = settings(sh);
        s.shadows = true;
        s.shadowMapSize = 512;
        auto want = soft().render(c.scene, rig, s, "multipass");
        ASSERT_TRUE(want) << want.status().message();
        const conformance::Bound& b = sh == Shading::Flat ? conformance::kShadowedFlatGlVsSoft
                                                          : conformance::kShadowedGlVsSoft;
        double worst = 0.0;
        int maxDelta = 0;
        for (const std::string& m : exactMethods()) {
            if (!backend().supports(m)) continue;
            auto out = backend().render(c.scene, rig, s, m);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            for (std::size_t v = 0; v < want->color.size(); ++v) {
                const ImageDiff d = compareImages(want->color[v], out->color[v], b.channel);
                const double share = double(d.differingPixels) / (kW * kH);
                worst = std::max(worst, share);
                maxDelta = std::max(maxDelta, d.maxDelta);
                EXPECT_TRUE(b.shareFor(int(v)).holds(share))
                    << m << " " << shadingName(sh) << " view " << v << ": " << 100 * share
                    << " %, max " << d.maxDelta;
            }
        }
        std::printf("[ measured ] environment with shadows %s: vs soft %.3f %% > %d/255 (max %d)\n",
                    shadingName(sh), 100 * worst, b.channel, maxDelta);
    }
}

// The environment changes the picture, and a scene without it renders as before it was drawn
// with one (its programs are the ones without ENVIRONMENT, its Frame block's SH unused).
TEST(GlEnvironment, RemovingTheEnvironmentRestoresTheImage) {
    MVR_SKIP_WITHOUT_GL();
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        for (const Case& c : {cases()[1], cases()[3]}) {
            Scene without = c.scene;
            without.environment.reset();
            const Rig rig = closeRig(c.scene, 2, 1);
            const RenderSettings s = settings(sh);
            for (const std::string& m : exactMethods()) {
                if (!backend().supports(m)) continue;
                auto before = backend().render(without, rig, s, m);
                if (!before && before.status().code() == ErrorCode::Unsupported) continue;
                ASSERT_TRUE(before) << m << ": " << before.status().message();
                auto with = backend().render(c.scene, rig, s, m);
                ASSERT_TRUE(with) << m << ": " << with.status().message();
                auto after = backend().render(without, rig, s, m);
                ASSERT_TRUE(after) << m << ": " << after.status().message();
                for (std::size_t v = 0; v < before->color.size(); ++v) {
                    EXPECT_GT(compareImages(before->color[v], with->color[v], 8).differingPixels,
                              kW * kH / 10)
                        << c.name << " " << m << " " << shadingName(sh) << " view " << v;
                    const ImageDiff d = compareImages(before->color[v], after->color[v], 0);
                    EXPECT_EQ(d.differingPixels, 0L)
                        << c.name << " " << m << " " << shadingName(sh) << " view " << v
                        << ": max " << d.maxDelta;
                }
                // ... and without the environment, gl still matches soft as it did
                if (m == "multipass") {
                    auto ref = soft().render(without, rig, s, "multipass");
                    ASSERT_TRUE(ref);
                    const conformance::Bound& b =
                        c.textured ? conformance::kTexturedGlVsSoft : conformance::kGlVsSoft;
                    for (std::size_t v = 0; v < ref->color.size(); ++v) {
                        const ImageDiff d =
                            compareImages(ref->color[v], after->color[v], b.channel);
                        EXPECT_TRUE(
                            b.shareFor(int(v)).holds(double(d.differingPixels) / (kW * kH)))
                            << c.name << " " << shadingName(sh) << " without: max " << d.maxDelta;
                    }
                }
            }
        }
    }
}

RadianceMap uniformMap(glm::vec3 c) {
    RadianceMap m;
    m.width = 64;
    m.height = 32;
    m.name = "uniform";
    m.texels.assign(std::size_t(m.width * m.height), c);
    return m;
}

// Values known in closed form. A uniform map of radiance c: a white Lambertian Blinn-Phong quad
// (specular 0), no lights, ambient 0, shows c in every shading and method (diffuseLight of a
// uniform map is c; S = specular · … = 0). A metal (metallic 1, roughness 0) of base colour b
// mirrors it: b ⊙ c · A + c · B with (A, B) = splitSum(n·v = 1, 0) at the quad's centre (the
// prefiltered map of a uniform map is c at every level); flat shading: Lambert of the base,
// b ⊙ c.
TEST(GlEnvironment, UniformMapGivesKnownValues) {
    MVR_SKIP_WITHOUT_GL();
    const glm::vec3 c(0.3f, 0.55f, 0.8f);
    Scene scene;
    scene.meshes.push_back(quadMesh());
    Instance inst;
    inst.material.albedo = glm::vec3(1.0f);
    inst.material.specular = 0.0f;
    scene.instances.push_back(inst);
    scene.ambient = glm::vec3(0.0f);
    scene.environment = std::make_shared<const Environment>(buildEnvironment(uniformMap(c)));
    const glm::vec3 base(0.9f, 0.6f, 0.3f);
    Scene metal = scene;
    metal.instances[0].material.model = MaterialModel::MetallicRoughness;
    metal.instances[0].material.albedo = base;
    metal.instances[0].material.metallic = 1.0f;
    metal.instances[0].material.roughness = 0.0f;
    const glm::vec2 ab = splitSum(1.0f, 0.0f);
    const glm::dvec3 wantMetal = glm::dvec3(base * c * ab.x + c * ab.y);
    const glm::dvec3 wantFlat = glm::dvec3(base * c);
    // The map's own values, checked here too: the SH's irradiance is c (to 0.5/255).
    const glm::vec3 e = diffuseLight(*scene.environment, glm::vec3(0, 0, 1));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(e[k], c[k], 0.5 / 255.0);
    EXPECT_GT(ab.x + ab.y, 0.9f);
    auto expectPixel = [&](const Image& img, glm::dvec3 want, const std::string& what) {
        const Rgba8 got = img.at(kW / 2, kH / 2);
        const int have[3] = {got.r, got.g, got.b};
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(have[k], std::clamp(want[k], 0.0, 1.0) * 255.0, 1.0)
                << what << " channel " << k;
    };
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        for (const std::string& m : exactMethods()) {
            if (!backend().supports(m)) continue;
            auto out = backend().render(scene, monoRig(), settings(sh), m);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            expectPixel(out->color[0], glm::dvec3(c), "Lambert " + m + " " + shadingName(sh));
            auto mo = backend().render(metal, monoRig(), settings(sh), m);
            ASSERT_TRUE(mo) << m << ": " << mo.status().message();
            expectPixel(mo->color[0], sh == Shading::Flat ? wantFlat : wantMetal,
                        "metal " + m + " " + shadingName(sh));
        }
    }
}

// A render sequence reuses one upload; another Environment (a rebuilt map) is uploaded anew and
// drawn: two maps of different radiance give their own colours through the same renderer.
TEST(GlEnvironment, AnotherEnvironmentIsUploadedAnew) {
    MVR_SKIP_WITHOUT_GL();
    Scene scene;
    scene.meshes.push_back(quadMesh());
    Instance inst;
    inst.material.albedo = glm::vec3(1.0f);
    inst.material.specular = 0.0f;
    inst.material.model = MaterialModel::MetallicRoughness;
    inst.material.metallic = 1.0f;
    inst.material.roughness = 0.0f;
    scene.instances.push_back(inst);
    scene.ambient = glm::vec3(0.0f);
    const glm::vec2 ab = splitSum(1.0f, 0.0f);
    for (const glm::vec3 c : {glm::vec3(0.2f, 0.4f, 0.6f), glm::vec3(0.7f, 0.3f, 0.1f),
                              glm::vec3(0.2f, 0.4f, 0.6f)}) {
        scene.environment = std::make_shared<const Environment>(buildEnvironment(uniformMap(c)));
        for (int frame = 0; frame < 2; ++frame) {
            auto out = backend().render(scene, monoRig(), settings(Shading::Pixel), "multipass");
            ASSERT_TRUE(out) << out.status().message();
            const Rgba8 got = out->color[0].at(kW / 2, kH / 2);
            const int have[3] = {got.r, got.g, got.b};
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(have[k], std::clamp(c[k] * (ab.x + ab.y), 0.0f, 1.0f) * 255.0f, 1.0f)
                    << "frame " << frame << " channel " << k;
        }
    }
}

// Pixel shading on more views than a geometry-shader pass takes: the environment adds no
// varying, so every method batches as without it and matches gl:multipass (kGlExact).
TEST(GlEnvironment, ManyViewsBatchOnEveryMethod) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = cases()[3].scene;  // mapped: the normal maps' tangent too
    constexpr int kViews = 40, kSmallW = 64, kSmallH = 48;
    const Rig rig = rigFor(scene, kViews, 1, float(kSmallW) / kSmallH, 0.2f);
    ASSERT_EQ(rig.viewCount(), kViews);
    RenderSettings s = settings(Shading::Pixel);
    s.width = kSmallW;
    s.height = kSmallH;
    auto ref = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    for (const std::string& m : exactMethods()) {
        if (!backend().supports(m)) continue;
        auto out = backend().render(scene, rig, s, m);
        if (!out && out.status().code() == ErrorCode::Unsupported) continue;
        ASSERT_TRUE(out) << m << ": " << out.status().message();
        ASSERT_EQ(out->color.size(), ref->color.size()) << m;
        for (std::size_t v = 0; v < ref->color.size(); ++v) {
            const ImageDiff d = compareImages(ref->color[v], out->color[v], 2);
            EXPECT_TRUE(conformance::kGlExact.shareFor(int(v))
                            .holds(double(d.differingPixels) / (kSmallW * kSmallH)))
                << m << " view " << v << ": max " << d.maxDelta;
        }
    }
}

}  // namespace
}  // namespace mvr::gl::test
