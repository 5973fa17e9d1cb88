// The conformance suite: every method of every backend in the registry (mvr::backends(), each
// backend's methods()) against soft:multipass, the reference, over the cases below, with the
// bounds of tolerances.h. The cases are enumerated when GoogleTest registers its tests, after
// static initialisation, so a backend that registerBackend() adds before then (a file linked
// into this executable is enough) is tested too, with no edit here.
//
// Tests: Cpu/Conformance.MatchesSoftMultipass/<backend>_<method> for the CPU backends, Gpu/…
// for those the registry marks gpu (ctest label gl: they need an EGL context); each runs every
// case below that its row allows and prints a "[ measured ]" line per case. A method that
// cannot run here (no EGL display, an extension the driver lacks) skips with the backend's own
// supports() message; a case over a driver limit (Unsupported from render()) is reported as
// skipped and the others still run. 160×120 views keep the suite quick on llvmpipe.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "gl_requirements.h"
#include "test_scenes.h"
#include "tolerances.h"
#include "mvr_test_support.h"

namespace mvr::conformance {
namespace {

constexpr int kW = 160, kH = 120;
const glm::vec3 kClear{0.1f, 0.15f, 0.2f};
const Rgba8 kClear8{26, 38, 51, 255};

// ---- the cases ---------------------------------------------------------------------------------

/// One scene, rig and shading. Scenes: "default" (procedural), "suzanne", "mirrored-suzanne"
/// (test_scenes.h), "octahedra" (convex objects, listed front to back).
struct SceneCase {
    std::string scene;
    int columns = 2, rows = 1;
    Shading shading = Shading::Vertex;
    bool cull = false, wire = false;
    bool shadows = false;  ///< RenderSettings::shadows (issue 15), maps of 512²
    int samples = 1;       ///< RenderSettings::samples (issue 38, --aa)
    bool perView = false;  ///< RenderSettings::specular PerView (issue 39, --specular per-view)

    int views() const { return columns * rows; }
    std::vector<std::string> tags() const {
        std::vector<std::string> t{scene};
        if (scene.rfind("textured-", 0) == 0 || scene == "mapped" || scene == "environment")
            t.push_back("textured");
        if (cull) t.push_back("cull");
        if (wire) t.push_back("wire");
        if (shadows) t.push_back(shading == Shading::Flat ? "shadows-flat" : "shadows");
        if (samples > 1) t.push_back("aa");
        return t;
    }
    std::string name() const {
        std::string s = fmt::format("{}_{}_{}x{}{}{}{}{}", scene, shadingName(shading), columns,
                                    rows, cull ? "_cull" : "", wire ? "_wire" : "",
                                    shadows ? "_shadows" : "",
                                    samples > 1 ? fmt::format("_aa{}", samples) : "") +
                        (perView ? "_perview" : "");
        for (char& c : s) c = (c == '-') ? '_' : c;
        return s;
    }
};

// What the gl tests compared before (tests/gl): every exact method vs gl:multipass on Suzanne
// stereo and default-scene grids in each shading, a culled row of 5, a wireframe 2x2, a mono
// "rig", kalaiah2007's 3x1 and 3x3; gl:multipass vs soft:multipass on both scenes in each
// shading; sorbier2008's gs-mrt / gs-depthmap on both scenes with and without culling; gs-mrt on
// sorted convex objects; flat normals under a mirrored transform. Every method runs every case
// its row allows.
const std::vector<SceneCase>& sceneCases() {
    static const std::vector<SceneCase> cases = {
        {"suzanne", 2, 1, Shading::Flat},
        {"suzanne", 2, 1, Shading::Vertex},
        {"suzanne", 2, 1, Shading::Pixel},
        {"suzanne", 2, 1, Shading::Vertex, true},
        {"default", 2, 1, Shading::Flat},
        {"default", 2, 1, Shading::Vertex},
        {"default", 2, 1, Shading::Vertex, true},
        {"default", 2, 1, Shading::Pixel},
        {"default", 3, 2, Shading::Flat},
        {"default", 3, 2, Shading::Vertex},
        {"default", 3, 2, Shading::Pixel},
        {"default", 5, 1, Shading::Vertex, true},
        {"default", 2, 2, Shading::Flat, false, true},
        {"default", 1, 1, Shading::Pixel},
        {"default", 3, 1, Shading::Vertex},
        {"default", 3, 3, Shading::Vertex},
        {"octahedra", 2, 1, Shading::Pixel, true},
        {"mirrored-suzanne", 2, 1, Shading::Flat},
        {"mirrored-suzanne", 2, 1, Shading::Flat, true},
        // Issue 14: base color textures (sRGB, mipmaps, repeat), every shading.
        {"textured", 2, 1, Shading::Flat},
        {"textured", 2, 1, Shading::Vertex},
        {"textured", 2, 1, Shading::Pixel},
        {"textured", 3, 2, Shading::Pixel},
        // Issue 15: shadow maps rendered once for all views and sampled by every view.
        {"default", 2, 1, Shading::Flat, false, false, true},
        {"default", 2, 1, Shading::Vertex, false, false, true},
        {"default", 2, 1, Shading::Pixel, false, false, true},
        {"default", 3, 2, Shading::Pixel, false, false, true},
        {"textured", 2, 1, Shading::Pixel, false, false, true},
        // A scene shaped like Khronos's 2CylinderEngine (test_scenes.h): dozens of meshes and
        // materials, more meshes than a GPU backend keeps between renders.
        {"engine", 2, 1, Shading::Vertex},
        {"engine", 3, 2, Shading::Flat, true},
        // Vertex colours (mvr.Mesh colors=, OBJ / PLY / glTF COLOR_0), every shading.
        {"colored", 2, 1, Shading::Flat},
        {"colored", 2, 1, Shading::Vertex},
        {"colored", 3, 2, Shading::Pixel},
        // Issue 38: --aa 4 in every method: four sub-pixel passes resolved (antialias.h), or
        // multisampled targets where the gl driver takes 4 samples (src/gl/multisample.cpp).
        {"suzanne", 2, 1, Shading::Vertex, false, false, false, 4},
        {"default", 3, 2, Shading::Pixel, false, false, false, 4},
        {"textured", 2, 1, Shading::Flat, false, false, false, 4},
        // Issue 39: glTF metallic-roughness materials (and an unlit one and an emissive one),
        // every shading, textured, shadowed.
        {"pbr", 2, 1, Shading::Flat},
        {"pbr", 2, 1, Shading::Vertex},
        {"pbr", 2, 1, Shading::Pixel},
        {"pbr", 3, 2, Shading::Vertex},
        {"pbr", 2, 1, Shading::Pixel, false, false, true},
        {"textured-pbr", 2, 1, Shading::Flat},
        {"textured-pbr", 2, 1, Shading::Vertex},
        {"textured-pbr", 3, 2, Shading::Pixel},
        // Issue 39 item 1: metallic-roughness, occlusion and emissive maps (test_scenes.h
        // withSurfaceMaps), every shading (the metallic-roughness map per pixel only).
        {"mapped", 2, 1, Shading::Flat},
        {"mapped", 2, 1, Shading::Vertex},
        {"mapped", 2, 1, Shading::Pixel},
        {"mapped", 3, 2, Shading::Pixel, false, false, true},
        // Issue 39 item 2: tone mapping where the clamp was (lighting.h finishColor), under
        // lights bright enough to need it.
        {"pbr-neutral", 2, 1, Shading::Vertex},
        {"pbr-neutral", 3, 2, Shading::Pixel},
        {"textured-aces", 2, 1, Shading::Vertex},
        {"textured-aces", 2, 1, Shading::Flat},
        // Issue 39 item 1: --specular per-view, each view shaded from its own eye (vertex
        // shading becomes pixel: shadedSettings); layered, tiled, batched and MRT paths alike.
        {"default", 3, 2, Shading::Pixel, false, false, false, 1, true},
        {"pbr", 2, 1, Shading::Pixel, false, false, false, 1, true},
        {"pbr", 3, 2, Shading::Vertex, false, false, false, 1, true},
        {"textured-pbr", 2, 1, Shading::Pixel, false, false, true, 1, true},
        // Issue 39 item 2: image lighting (test_scenes.h testEnvironment): the mapped scene's
        // metallic-roughness maps and occlusion, Blinn-Phong's reflection, every shading.
        {"environment", 2, 1, Shading::Flat},
        {"environment", 2, 1, Shading::Vertex},
        {"environment", 2, 1, Shading::Pixel},
        {"environment", 3, 2, Shading::Pixel, false, false, true},
        {"environment-pbr", 3, 2, Shading::Vertex},
        {"environment-pbr", 2, 1, Shading::Pixel, false, false, false, 1, true},
        {"environment-default", 2, 1, Shading::Vertex},
        {"environment-default", 3, 2, Shading::Pixel},
    };
    return cases;
}

const Scene* sceneNamed(const std::string& name) {
    if (name == "default") return &test::defaultScene();
    if (name == "suzanne") return test::suzanneScene();
    if (name == "mirrored-suzanne") return test::mirroredSuzanneScene();
    if (name == "octahedra") return &test::octahedraScene();
    if (name == "engine") return &test::engineScene();
    if (name == "colored") return &test::coloredScene();
    if (name == "pbr") return &test::pbrScene();
    if (name == "mapped") return &test::mappedScene();
    if (name == "environment") {
        static const Scene lit = test::withEnvironment(test::mappedScene());
        return &lit;
    }
    if (name == "environment-pbr") {
        static const Scene lit = test::withEnvironment(test::pbrScene());
        return &lit;
    }
    if (name == "environment-default") {
        static const Scene lit = test::withEnvironment(test::defaultScene());
        return &lit;
    }
    if (name == "textured-pbr") {
        static const Scene texturedPbr = test::withMetallicRoughness(makeTexturedScene());
        return &texturedPbr;
    }
    if (name == "pbr-neutral") {
        static const Scene neutral = test::toneMapped(test::pbrScene(), Tonemap::KhrNeutral, 3.0f);
        return &neutral;
    }
    if (name == "textured-aces") {
        static const Scene aces = test::toneMapped(makeTexturedScene(), Tonemap::Aces, 2.0f);
        return &aces;
    }
    if (name == "textured") {
        static const Scene textured = makeTexturedScene();
        return &textured;
    }
    return nullptr;
}

RenderSettings settingsFor(const SceneCase& c) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = c.shading;
    s.cullBackFaces = c.cull;
    s.wireframe = c.wire;
    s.clearColor = kClear;
    s.shadows = c.shadows;
    s.shadowMapSize = 512;
    s.samples = c.samples;
    s.specular = c.perView ? SpecularEye::PerView : SpecularEye::Center;
    return s;
}

/// One (backend, method) of the registry; the test runs every case its row allows.
struct Param {
    std::string backend, method;
    std::string makeError;  ///< the factory's error: the test fails with it
};

void PrintTo(const Param& p, std::ostream* os) { *os << p.backend << ":" << p.method; }

std::string paramName(const testing::TestParamInfo<Param>& i) {
    std::string s = i.param.backend + "_" + i.param.method;
    for (char& c : s) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return s;
}

/// Every (backend, method) of the registry's CPU (gpu = false) or GPU backends.
std::vector<Param> registryMethods(bool gpu) {
    std::vector<Param> out;
    for (const BackendEntry& entry : backends()) {
        if (entry.gpu != gpu) continue;
        auto backend = entry.make({});
        if (!backend) {
            out.push_back({entry.name, "factory", backend.status().message()});
            continue;
        }
        for (const std::string& method : (*backend)->methods()) {
            out.push_back({entry.name, method, ""});
        }
    }
    return out;
}

// ---- comparing -------------------------------------------------------------------------------

/// The first byte where two views differ, or "".
std::string firstDifference(const Image& a, const Image& b, const DepthImage* da,
                            const DepthImage* db) {
    if (a.width != b.width || a.height != b.height) {
        return fmt::format("sizes {}x{} vs {}x{}", a.width, a.height, b.width, b.height);
    }
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const Rgba8 p = a.at(x, y), q = b.at(x, y);
            if (p != q) {
                return fmt::format("colour at ({}, {}): {},{},{},{} vs {},{},{},{}", x, y, p.r, p.g,
                                   p.b, p.a, q.r, q.g, q.b, q.a);
            }
            if (da && db) {
                const float u = da->at(x, y), v = db->at(x, y);
                if (std::memcmp(&u, &v, sizeof(float)) != 0) {
                    return fmt::format("depth at ({}, {}): {:.9g} vs {:.9g}", x, y, u, v);
                }
            }
        }
    }
    return "";
}

/// Checks `out` against `ref` view by view; returns a one-line summary of the worst view.
std::string expectWithin(const std::string& refName, const RenderOutput& ref,
                         const RenderOutput& out, const Bound& bound) {
    const int views = static_cast<int>(ref.color.size());
    const double pixels = static_cast<double>(kW) * kH;
    double worstShare = 0.0, worstDepth = 0.0;
    int worstMax = 0;
    for (int v = 0; v < views; ++v) {
        const auto i = static_cast<std::size_t>(v);
        const Image& a = ref.color[i];
        const Image& b = out.color[i];
        const bool bothDepth = ref.depth.size() > i && out.depth.size() > i;
        const ImageDiff d = compareImages(a, b, bound.channel);
        worstMax = std::max(worstMax, d.maxDelta);
        if (bound.exact) {
            const std::string diff = firstDifference(a, b, bothDepth ? &ref.depth[i] : nullptr,
                                                     bothDepth ? &out.depth[i] : nullptr);
            EXPECT_EQ(diff, "") << "view " << v << " vs " << refName
                                << " (exact): " << compareImages(a, b, 0).differingPixels
                                << " pixels differ, max " << d.maxDelta;
            if (!diff.empty()) worstShare = std::max(worstShare, 1.0 / pixels);
            continue;
        }
        if (a.width != b.width || a.height != b.height) {
            ADD_FAILURE() << "view " << v << ": " << b.width << "x" << b.height << " vs " << refName
                          << "'s " << a.width << "x" << a.height;
            return "sizes differ";
        }
        const double share = static_cast<double>(d.differingPixels) / pixels;
        const Share allowed = bound.shareFor(v);
        EXPECT_TRUE(allowed.holds(share))
            << "view " << v << " vs " << refName << ": " << d.differingPixels << " pixels ("
            << 100.0 * share << " %) off by more than " << bound.channel << "/255, allowed "
            << (allowed.strict ? "below " : "at most ") << 100.0 * allowed.fraction << " %; max "
            << d.maxDelta << " at (" << d.worstX << "," << d.worstY << ")";
        worstShare = std::max(worstShare, share);
        if (bothDepth) {
            float maxDepth = 0.0f;
            const double ds =
                test::depthMismatch(ref.depth[i], out.depth[i], bound.depth, &maxDepth);
            EXPECT_TRUE(bound.depthShare.holds(ds))
                << "view " << v << " depth vs " << refName << ": " << 100.0 * ds
                << " % of the pixels differ by more than " << bound.depth << ", max " << maxDepth;
            worstDepth = std::max(worstDepth, ds);
        }
    }
    if (bound.exact) {
        return fmt::format("vs {}: {}", refName, worstShare == 0.0 ? "bit for bit" : "DIFFERENT");
    }
    return fmt::format("vs {}: worst view {:.3f} % > {}/255 (max {}), depth {:.3f} %", refName,
                       100.0 * worstShare, bound.channel, worstMax, 100.0 * worstDepth);
}

/// Renders one case with `method` of `backend` (registered as `name`) and checks it against
/// soft:multipass (and the row's sibling method). Sets *skipped (and checks nothing more)
/// where the case cannot run here.
void checkCase(const std::string& name, Backend& backend, Backend& reference,
               const std::string& method, const SceneCase& c, std::string* skipped) {
    const Tolerance& tol = toleranceFor(name, method, c.tags());
    SCOPED_TRACE(std::string("bound: ") + tol.reason);
    const Scene* scene = sceneNamed(c.scene);
    if (!scene) {
        *skipped = "model not found under " + test::sharedDir().string();
        return;
    }
    // Per-view specular: a wide cone (a light-field panel's), whose outer eyes see other
    // highlights than the centre eye.
    const Rig rig = test::rigFor(*scene, c.columns, c.rows, 4.0f / 3.0f, c.perView ? 4.0f : 1.0f);
    ASSERT_EQ(rig.viewCount(), c.views());
    const RenderSettings s = settingsFor(c);
    auto ref = reference.render(*scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    if (!scene->textures.empty()) {
        // A reference that does not sample textures yet (the same picture without them) is
        // no reference for textured shading: the case is skipped, saying so.
        Scene plain = *scene;
        for (Instance& i : plain.instances) i.material.baseColorTexture = -1;
        auto untextured = reference.render(plain, rig, s, "multipass");
        ASSERT_TRUE(untextured) << untextured.status().message();
        if (untextured->color == ref->color) {
            *skipped = "soft:multipass does not sample textures in this build";
            return;
        }
    }
    // The case is not trivially empty.
    EXPECT_GT(compareImages(ref->color[0], Image(kW, kH, kClear8), 2).differingPixels,
              kW * kH / 20);
    if (c.perView) {
        // View 0's own highlights are further from the centre eye's than this method's bound
        // allows (gs-mrt's and gs-depthmap's, 6 % and more, aside): a backend that shaded
        // every view from the centre eye would fail.
        RenderSettings centre = s;
        centre.specular = SpecularEye::Center;
        auto same = reference.render(*scene, rig, centre, "multipass");
        ASSERT_TRUE(same) << same.status().message();
        const Bound& b = tol.vsSoft;
        const double moved =
            double(compareImages(ref->color[0], same->color[0], b.exact ? 0 : b.channel)
                       .differingPixels) /
            (kW * kH);
        if (b.exact) {
            EXPECT_GT(moved, 0.0);
        } else if (b.first.fraction < 0.06) {
            EXPECT_FALSE(b.first.holds(moved))
                << "the centre eye's view 0 is within the bound: " << 100.0 * moved << " %";
        }
    }

    auto out = backend.render(*scene, rig, s, method);
    if (!out && out.status().code() == ErrorCode::Unsupported) {  // e.g. a driver's view limit
        *skipped = out.status().message();
        return;
    }
    ASSERT_TRUE(out) << out.status().message();
    const auto views = static_cast<std::size_t>(rig.viewCount());
    ASSERT_EQ(out->color.size(), views);
    switch (tol.depth) {
        case Depth::PerView: ASSERT_EQ(out->depth.size(), views); break;
        case Depth::None:
            EXPECT_TRUE(out->depth.empty()) << method << " has no per-view depth";
            break;
        case Depth::Optional: ASSERT_TRUE(out->depth.empty() || out->depth.size() == views); break;
    }

    std::string measured = expectWithin("soft:multipass", *ref, *out, tol.vsSoft);
    const std::string sibling = tol.sibling;
    if (!sibling.empty() && sibling != method) {
        auto sib = backend.render(*scene, rig, s, sibling);
        ASSERT_TRUE(sib) << sibling << ": " << sib.status().message();
        measured += "; " + expectWithin(name + ":" + sibling, *sib, *out, tol.vsSibling);
    }
    const std::string ran = out->method != method ? " (ran " + out->method + ")" : "";
    std::printf("[ measured ] %s:%s %s%s: %s\n", name.c_str(), method.c_str(), c.name().c_str(),
                ran.c_str(), measured.c_str());
    testing::Test::RecordProperty(c.name(), measured);
}

/// ok, or skips (Unsupported: cannot run here) / fails (anything else) with `status`.
#define MVR_SKIP_UNSUPPORTED(status, what)                                                \
    do {                                                                                  \
        const ::mvr::Status s_ = (status);                                                \
        if (!s_) {                                                                        \
            if (s_.code() == ::mvr::ErrorCode::Unsupported) MVR_SKIP(MethodUnsupportedByDriver) << s_.message(); \
            FAIL() << (what) << ": " << s_.message();                                     \
        }                                                                                 \
    } while (0)

class Conformance : public testing::TestWithParam<Param> {};

// Every case of sceneCases() that the method's row allows (its view count), one after the other
// in one process (one backend, one context: a process per case would cost more than the cases).
TEST_P(Conformance, MatchesSoftMultipass) {
    const Param& p = GetParam();
    ASSERT_EQ(p.makeError, "") << "backend " << p.backend << " could not be created";
    auto backend = makeBackend(p.backend);
    ASSERT_TRUE(backend) << backend.status().message();
    if (p.backend == "gl") {
        // CI's GL runs (gl_requirements.h): no context, another driver than the one asked
        // for, or a refusal of a method the driver must run fails instead of skipping.
        const Status context = (*backend)->supports("multipass");
        if (!context && test::requireGl()) FAIL() << "MVR_REQUIRE_GL=1: " << context.message();
        const Status has = (*backend)->supports(p.method);
        if (context) {
            const std::vector<std::string> info = (*backend)->info();
            const std::string wrong = test::wrongGlDriver(info);
            if (!wrong.empty()) FAIL() << wrong;
            const std::string must = test::mustRun(info, (*backend)->methods(), p.method);
            if (!has && !must.empty()) FAIL() << must << ": " << has.message();
        }
    }
    MVR_SKIP_UNSUPPORTED((*backend)->supports(p.method), p.backend + ":" + p.method);
    auto reference = makeBackend("soft");
    ASSERT_TRUE(reference) << reference.status().message();
    int ran = 0;
    for (const SceneCase& c : sceneCases()) {
        const Tolerance& tol = toleranceFor(p.backend, p.method, c.tags());
        if (tol.views != 0 && tol.views != c.views()) continue;
        if (!std::string(tol.sibling).empty()) {
            MVR_SKIP_UNSUPPORTED((*backend)->supports(tol.sibling), p.backend + ":" + tol.sibling);
        }
        SCOPED_TRACE(p.backend + ":" + p.method + " " + c.name());
        std::string skipped;
        checkCase(p.backend, **backend, **reference, p.method, c, &skipped);
        if (!skipped.empty()) {
            std::printf("[ skipped  ] %s:%s %s: %s\n", p.backend.c_str(), p.method.c_str(),
                        c.name().c_str(), skipped.c_str());
            continue;
        }
        ++ran;
    }
    if (ran == 0) MVR_SKIP(NoGlContext) << "no case could run here";
}

INSTANTIATE_TEST_SUITE_P(Cpu, Conformance, testing::ValuesIn(registryMethods(false)), paramName);
INSTANTIATE_TEST_SUITE_P(Gpu, Conformance, testing::ValuesIn(registryMethods(true)), paramName);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Conformance);

// ---- sorbier2008's two one-pass stereo methods against each other ------------------------------

struct StereoErrors {
    double left = 0, right = 0;
};

/// Shares of wrong pixels (> 2/255) of `method` vs the backend's multipass.
StereoErrors stereoErrors(Backend& backend, const std::string& method, const Scene& scene,
                          bool cull) {
    const Rig rig = test::rigFor(scene, 2, 1);
    const RenderSettings s = settingsFor({"", 2, 1, Shading::Vertex, cull});
    auto ref = backend.render(scene, rig, s, "multipass");
    auto out = backend.render(scene, rig, s, method);
    EXPECT_TRUE(ref) << ref.status().message();
    EXPECT_TRUE(out) << out.status().message();
    if (!ref || !out) return {1, 1};
    return {compareImages(ref->color[0], out->color[0], 2).differingPixels / double(kW * kH),
            compareImages(ref->color[1], out->color[1], 2).differingPixels / double(kW * kH)};
}

// §5.2's depth map repairs what painter's order breaks: gs-depthmap errs nowhere more than
// gs-mrt in the left eye, and in the right eye at most by edge pixels (0.2 %) more. Each
// method's own bound is its row in tolerances.h; this is the relation between them, on every
// backend that has both.
TEST(GpuSorbier2008, DepthMapErrsNoMoreThanGsMrt) {
    int tested = 0;
    for (const BackendEntry& entry : backends()) {
        auto backend = entry.make({});
        if (!backend) continue;
        const auto methods = (*backend)->methods();
        const auto has = [&](const char* m) {
            return std::find(methods.begin(), methods.end(), m) != methods.end();
        };
        if (!has("gs-mrt") || !has("gs-depthmap")) continue;
        if (Status st = (*backend)->supports("gs-depthmap"); !st) {
            std::printf("%s: %s\n", entry.name.c_str(), st.message().c_str());
            continue;
        }
        const Scene* suz = test::suzanneScene();
        for (const Scene* scene : {&test::defaultScene(), suz}) {
            if (!scene) continue;
            for (bool cull : {false, true}) {
                const StereoErrors mrt = stereoErrors(**backend, "gs-mrt", *scene, cull);
                const StereoErrors dm = stereoErrors(**backend, "gs-depthmap", *scene, cull);
                const std::string name = scene == suz ? "suzanne" : "default";
                std::printf(
                    "[ measured ] %s %s cull=%d: gs-mrt wrong pixels left %.2f %% right "
                    "%.2f %%; gs-depthmap left %.2f %% right %.2f %%\n",
                    entry.name.c_str(), name.c_str(), cull, 100 * mrt.left, 100 * mrt.right,
                    100 * dm.left, 100 * dm.right);
                const std::string key = entry.name + "_" + name + (cull ? "_cull" : "");
                RecordProperty(key + "_gs_mrt_left_pct", fmt::format("{:.2f}", 100 * mrt.left));
                RecordProperty(key + "_gs_mrt_right_pct", fmt::format("{:.2f}", 100 * mrt.right));
                RecordProperty(key + "_gs_depthmap_left_pct", fmt::format("{:.2f}", 100 * dm.left));
                RecordProperty(key + "_gs_depthmap_right_pct",
                               fmt::format("{:.2f}", 100 * dm.right));
                EXPECT_LE(dm.left, mrt.left + 1e-9) << key;
                EXPECT_LE(dm.right, mrt.right + 0.002) << key;
            }
        }
        ++tested;
    }
    if (tested == 0) MVR_SKIP(MethodUnsupportedByDriver) << "no backend here runs both gs-mrt and gs-depthmap";
}

}  // namespace
}  // namespace mvr::conformance
