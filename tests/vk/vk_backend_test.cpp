// Tests of the vk backend (include/mvr/vk/vk_backend.h) on the machine's Vulkan device (lavapipe
// in CI), validation layers on (validation_env.cpp): the registry row, `mvr info`'s lines,
// batching past maxMultiviewViewCount, every method against vk:multipass and soft:multipass,
// depth on and off, textures and vertex colours at known places, data and colour texture maps,
// normal maps against the tangent-frame formula, image lighting (`--environment`) against soft
// and known values, and the Unsupported messages. The conformance suite (tests/conformance)
// compares every vk method with soft:multipass on all its scenes.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <regex>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "test_scenes.h"
#include "../conformance/tolerances.h"
#include "mvr/backends.h"
#include "mvr/core/environment.h"
#include "mvr/vk/vk_backend.h"
#include "mvr_test_support.h"

namespace mvr::vk::test {
namespace {

using ::mvr::test::defaultScene;
using ::mvr::test::rigFor;

constexpr int kW = 96, kH = 72;

// One backend (one device) for the process, destroyed before main() returns: Mesa's drivers
// tear their threads down in exit handlers, after which no Vulkan object can be destroyed.
std::unique_ptr<Backend>& holder() {
    static std::unique_ptr<Backend> b;
    return b;
}
Backend& backend() {
    if (!holder()) holder() = makeVkBackend();
    return *holder();
}
class ReleaseBackend : public testing::Environment {
public:
    void TearDown() override { holder().reset(); }
};
const testing::Environment* const kRelease =
    testing::AddGlobalTestEnvironment(new ReleaseBackend);

/// Skips without a Vulkan device; fails instead under MVR_REQUIRE_GL=1 (CI has lavapipe).
#define MVR_SKIP_WITHOUT_VK()                                                       \
    do {                                                                            \
        const ::mvr::Status s_ = backend().supports("multipass");                   \
        if (!s_) MVR_SKIP(NoVulkanDevice) << s_.message();                          \
    } while (0)

RenderSettings small(Shading shading = Shading::Vertex) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = shading;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

int multiviewLimit() {
    const std::regex re(R"(maxMultiviewViewCount (\d+))");
    for (const std::string& line : backend().info()) {
        std::smatch m;
        if (std::regex_search(line, m, re)) return std::stoi(m[1]);
    }
    return 0;
}

/// Share of pixels with a channel more than `channel` apart.
double offShare(const Image& a, const Image& b, int channel) {
    return double(compareImages(a, b, channel).differingPixels) / (double(a.width) * a.height);
}

TEST(VkBackend, IsInTheRegistryAndNamesItsMethods) {
    auto entry = findBackend("vk");
    ASSERT_TRUE(entry) << entry.status().message();
    EXPECT_TRUE((*entry)->gpu);
    const auto& names = vkMethodNames();
    EXPECT_EQ(names.front(), "multipass");
    EXPECT_EQ(names.back(), "auto");
    EXPECT_EQ(backend().supports("gs-mrt").code(), ErrorCode::Usage);
}

TEST(VkBackend, InfoNamesDeviceDriverAndMultiviewLimit) {
    MVR_SKIP_WITHOUT_VK();
    const auto info = backend().info();
    auto has = [&](const std::string& prefix) {
        return std::any_of(info.begin(), info.end(),
                           [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
    };
    EXPECT_TRUE(has("vk device: "));
    EXPECT_TRUE(has("vk driver: "));
    EXPECT_TRUE(has("vk validation: on")) << "validation_env.cpp should have turned it on";
    EXPECT_TRUE(has("vk image lighting: map R"));  // a filterable float format
    EXPECT_GE(multiviewLimit(), 2);
}

/// The views a multiview pass takes, as `mvr info` says (lavapipe: 1, the workaround).
int multiviewBatch() {
    const std::regex re(R"(vk method multiview: supported, (\d+) views? a batch)");
    for (const std::string& line : backend().info()) {
        std::smatch m;
        if (std::regex_search(line, m, re)) return std::stoi(m[1]);
    }
    return 0;
}

TEST(VkBackend, MultiviewBatchesPastTheDeviceLimit) {
    MVR_SKIP_WITHOUT_VK();
    const int limit = multiviewLimit();
    ASSERT_GE(limit, 1);
    const int batch = multiviewBatch();
    ASSERT_GE(batch, 1);
    ASSERT_LE(batch, limit);
    const int views = limit + 2;  // lavapipe: 8 views, one a pass (6 + 2 without the workaround)
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, views, 1, float(kW) / kH);
    auto mv = backend().render(scene, rig, small(), "multiview");
    ASSERT_TRUE(mv) << mv.status().message();
    const auto stats = backend().lastStats();
    ASSERT_TRUE(stats);
    EXPECT_EQ(stats->passes, (views + batch - 1) / batch);
    EXPECT_EQ(stats->method, "multiview");
    auto mp = backend().render(scene, rig, small(), "multipass");
    ASSERT_TRUE(mp) << mp.status().message();
    ASSERT_EQ(mv->color.size(), std::size_t(views));
    ASSERT_EQ(mv->depth.size(), std::size_t(views));
    for (int v = 0; v < views; ++v) {
        // The bound of tolerances.h's vk:multiview row (its reason says why it is not exact).
        EXPECT_LE(offShare(mv->color[v], mp->color[v], 2), 0.03) << "view " << v;
    }
}

TEST(VkBackend, EveryMethodAndShadingMatchesSoftMultipass) {
    MVR_SKIP_WITHOUT_VK();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 3, 1, float(kW) / kH);
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        auto ref = (*soft)->render(scene, rig, small(sh), "multipass");
        ASSERT_TRUE(ref) << ref.status().message();
        for (const char* m : {"multipass", "multiview", "instanced-layer", "auto"}) {
            SCOPED_TRACE(fmt::format("vk:{} {}", m, shadingName(sh)));
            if (Status s = backend().supports(m); !s) {
                ASSERT_EQ(s.code(), ErrorCode::Unsupported) << s.message();
                continue;
            }
            auto out = backend().render(scene, rig, small(sh), m);
            ASSERT_TRUE(out) << out.status().message();
            for (int v = 0; v < 3; ++v) {
                const double bound = std::string(m) == "multiview" || std::string(m) == "auto"
                                         ? 0.03
                                         : 0.01;
                EXPECT_LE(offShare(out->color[v], ref->color[v], 2), bound) << "view " << v;
            }
        }
    }
}

TEST(VkBackend, DepthFalseSkipsTheDepthImages) {
    MVR_SKIP_WITHOUT_VK();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1, float(kW) / kH);
    RenderSettings s = small();
    auto with = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(with) << with.status().message();
    ASSERT_EQ(with->depth.size(), 2u);
    // Window depth in [0, 1], 1 where nothing was drawn; something was drawn.
    const auto [lo, hi] = std::minmax_element(with->depth[0].depth.begin(),
                                              with->depth[0].depth.end());
    EXPECT_GE(*lo, 0.0f);
    EXPECT_LT(*lo, 1.0f);
    EXPECT_EQ(*hi, 1.0f);
    s.depth = false;
    auto without = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(without) << without.status().message();
    EXPECT_TRUE(without->depth.empty());
    EXPECT_EQ(without->color[1].rgba, with->color[1].rgba);
}

TEST(VkBackend, CullingKeepsTheFrontFaces) {
    MVR_SKIP_WITHOUT_VK();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1, float(kW) / kH);
    RenderSettings s = small();
    s.cullBackFaces = true;
    auto ref = (*soft)->render(scene, rig, s, "multipass");
    auto out = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref && out);
    EXPECT_LE(offShare(out->color[0], ref->color[0], 2), 0.01);
}

/// A quad filling a 90-degree view exactly, lit by an ambient 1 and no light (albedo 1, no
/// specular): what a pixel shows is its base colour times its vertex colour and texel, in
/// linear. uv (0, 0) at the view's top-left (the image's row 0, scene.h), (1, 1) bottom right.
Scene quadScene(const glm::vec4& vertexColor, bool textured) {
    Scene scene;
    Mesh quad;
    quad.name = "quad";
    quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.normals.assign(4, glm::vec3(0, 0, 1));
    quad.texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    quad.colors.assign(4, vertexColor);
    quad.indices = {0, 1, 2, 0, 2, 3};
    scene.meshes.push_back(quad);
    Material m(glm::vec3(1.0f), 0.0f, 32.0f);
    if (textured) {
        // 2x2 texels, nearest, no mip chain: each quarter of the view shows one texel.
        Texture t;
        t.name = "checker";
        t.image = Image(2, 2);
        t.image.set(0, 0, {255, 0, 0, 255});
        t.image.set(1, 0, {0, 255, 0, 255});
        t.image.set(0, 1, {0, 0, 255, 255});
        t.image.set(1, 1, {128, 64, 200, 255});
        scene.textures.push_back(t);
        m.baseColorTexture = 0;
        m.sampler.magFilter = m.sampler.minFilter = TextureFilter::Nearest;
        m.sampler.mipmaps = false;
    }
    Instance inst;
    inst.mesh = 0;
    inst.material = m;
    scene.instances.push_back(inst);
    scene.lights.clear();
    scene.ambient = glm::vec3(1.0f);
    return scene;
}

Rig quadRig(int views = 1) {
    Camera c;
    c.position = {0, 0, 1};
    c.target = {0, 0, 0};
    c.fovYDegrees = 90.0f;
    c.aspect = 1.0f;
    c.near = 0.5f;
    c.far = 2.0f;
    RigParams p;
    p.columns = views;
    if (views > 1) p.interaxial = 0.05f;  // the quad at the convergence plane fills every view
    p.convergence = 1.0f;
    auto rig = makeRig(c, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return *rig;
}

/// The 8-bit value of an sRGB-encoded 8-bit channel decoded to linear (IEC 61966-2-1).
int decoded(int srgb) {
    const double c = srgb / 255.0;
    const double linear = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    return int(std::lround(linear * 255.0));
}

TEST(VkBackend, TexelsAndVertexColoursLandWhereTheQuadPutsThem) {
    MVR_SKIP_WITHOUT_VK();
    RenderSettings s = small(Shading::Pixel);
    s.width = s.height = 64;
    const Rig rig = quadRig();
    const glm::vec4 tint(0.5f, 1.0f, 0.25f, 1.0f);
    for (const char* method : {"multipass", "multiview", "instanced-layer"}) {
        auto r = backend().render(quadScene(tint, true), rig, s, method);
        ASSERT_TRUE(r) << method << ": " << r.status().message();
        const Image& im = r->color[0];
        // The centre of each quarter: texel (i, j) decoded, times the vertex colour.
        const int texel[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 64, 200}};
        const int at[4][2] = {{16, 16}, {48, 16}, {16, 48}, {48, 48}};
        for (int q = 0; q < 4; ++q) {
            const Rgba8 p = im.at(at[q][0], at[q][1]);
            const int got[3] = {p.r, p.g, p.b};
            for (int c = 0; c < 3; ++c) {
                const int want = int(std::lround(decoded(texel[q][c]) / 255.0 * tint[c] * 255.0));
                EXPECT_NEAR(got[c], want, 2) << method << ", quarter " << q << ", channel " << c;
            }
        }
    }
    // Without a texture: the vertex colour alone, in every shading.
    for (Shading shading : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        RenderSettings sv = small(shading);
        sv.width = sv.height = 64;
        auto r = backend().render(quadScene(tint, false), rig, sv, "multipass");
        ASSERT_TRUE(r) << r.status().message();
        const Rgba8 p = r->color[0].at(32, 32);
        EXPECT_NEAR(p.r, 128, 1);
        EXPECT_NEAR(p.g, 255, 1);
        EXPECT_NEAR(p.b, 64, 1);
    }
}

// Issue 39's texture maps (lighting.h SurfaceMaps): one grey image (128) as an occlusion map
// (data: Texture::linear, sampled as 128/255) and as an emissive map (colour: sRGB-decoded), on
// a metallic-roughness quad with no base colour texture, lit by ambient (1, 1, 0) and no light,
// emissive factor (0, 0, 1): red and green show the occlusion (ambient × occlusion), blue the
// emissive texel, in every shading and method. The two uses of one image are two device images
// (colour and data keyed apart), and a material with maps but no base colour samples them.
TEST(VkBackend, DataMapsAreReadAsStoredAndColourMapsDecoded) {
    MVR_SKIP_WITHOUT_VK();
    Scene scene = quadScene(glm::vec4(1.0f), false);
    for (const bool linear : {true, false}) {
        Texture t;
        t.name = linear ? "grey (data)" : "grey (colour)";
        t.image = Image(2, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) t.image.set(x, y, {128, 128, 128, 255});
        t.linear = linear;
        scene.textures.push_back(t);
    }
    Material& m = scene.instances[0].material;
    m.model = MaterialModel::MetallicRoughness;
    m.occlusionTexture = 0;
    m.occlusionStrength = 1.0f;
    m.emissiveTexture = 1;
    m.emissive = glm::vec3(0.0f, 0.0f, 1.0f);
    m.sampler.magFilter = m.sampler.minFilter = TextureFilter::Nearest;
    m.sampler.mipmaps = false;
    scene.ambient = glm::vec3(1.0f, 1.0f, 0.0f);
    const Rig rig = quadRig();
    for (Shading shading : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        for (const char* method : {"multipass", "multiview", "instanced-layer"}) {
            RenderSettings s = small(shading);
            s.width = s.height = 64;
            auto r = backend().render(scene, rig, s, method);
            ASSERT_TRUE(r) << method << ": " << r.status().message();
            const Rgba8 p = r->color[0].at(32, 32);
            const std::string where = fmt::format("{}, shading {}", method, int(shading));
            EXPECT_NEAR(p.r, 128, 1) << where;  // not decoded(128): data
            EXPECT_NEAR(p.g, 128, 1) << where;
            EXPECT_NEAR(p.b, decoded(128), 2) << where;  // decoded: colour
        }
    }
}

/// The normal a normal map's texel gives a surface whose normal, tangent and bitangent are the
/// unit vectors n, t, b: glTF's tangent-space normal (2·rgb − 1, x and y × scale) in that frame,
/// written out in double (as tests/raster/surface_maps_test.cpp's).
glm::dvec3 mappedNormal(Rgba8 texel, double scale, glm::dvec3 t, glm::dvec3 b, glm::dvec3 n) {
    const glm::dvec3 c((2.0 * texel.r / 255.0 - 1.0) * scale,
                       (2.0 * texel.g / 255.0 - 1.0) * scale, 2.0 * texel.b / 255.0 - 1.0);
    return glm::normalize(t * c.x + b * c.y + n * c.z);
}

// Normal maps (lighting.h perturbedNormal, issue 39): the quad facing +z, u along +x and the
// image's top at +y (tangent (1, 0, 0), handedness +1: bitangent cross(n, t) = +y), one light,
// no ambient, no specular, under a uniform normal map (data) at scale 0.8: the centre of each
// view shows Lambert of the normal bent in that frame, in every method. Mirrored in x
// (worldFromModel's determinant < 0), u runs along −x and the handedness flips (raster/pipeline.h
// worldTangent): the bitangent stays +y. Per vertex, flat, or on a mesh without tangents: the
// surface's own normal.
TEST(VkBackend, NormalMapBendsTheNormalInTheTangentFrame) {
    MVR_SKIP_WITHOUT_VK();
    const glm::dvec3 light = glm::normalize(glm::dvec3(0.5, 0.4, 0.77));
    const Rig rig = quadRig(2);
    auto render = [&](const Scene& scene, Shading shading, const char* method) {
        RenderSettings s = small(shading);
        s.width = s.height = 64;
        auto r = backend().render(scene, rig, s, method);
        EXPECT_TRUE(r) << method << ": " << r.status().message();
        std::vector<Rgba8> centres;
        if (r)
            for (const Image& im : r->color) centres.push_back(im.at(32, 32));
        return centres;
    };
    for (const Rgba8 texel : {Rgba8{255, 128, 128, 255}, Rgba8{128, 255, 128, 255},
                              Rgba8{40, 90, 200, 255}, Rgba8{128, 128, 255, 255}}) {
        for (const bool mirrored : {false, true}) {
            Scene scene = quadScene(glm::vec4(1.0f), false);
            Mesh& mesh = scene.meshes[0];
            mesh.colors.clear();
            mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
            Texture t;
            t.name = "uniform normal";
            t.linear = true;
            t.image = Image(4, 4, texel);
            scene.textures = {t};
            Material& m = scene.instances[0].material;
            m.normalTexture = 0;
            m.normalScale = 0.8f;
            if (mirrored)
                scene.instances[0].worldFromModel = glm::scale(glm::mat4(1.0f), {-1, 1, 1});
            Light l;
            l.towardLight = glm::vec3(light);
            scene.lights = {l};
            scene.ambient = glm::vec3(0.0f);
            const glm::dvec3 n = mappedNormal(texel, 0.8, {mirrored ? -1.0 : 1.0, 0, 0}, {0, 1, 0},
                                              {0, 0, 1});
            const double want = std::max(0.0, glm::dot(n, light)) * 255.0;
            const double flat = glm::dot(glm::dvec3(0, 0, 1), light) * 255.0;
            for (const char* method : {"multipass", "multiview", "instanced-layer", "auto"}) {
                const std::string where =
                    fmt::format("texel {},{},{} mirrored {} {}", int(texel.r), int(texel.g),
                                int(texel.b), mirrored, method);
                const auto px = render(scene, Shading::Pixel, method);
                ASSERT_EQ(px.size(), 2u) << where;
                for (const Rgba8 p : px) {
                    EXPECT_NEAR(p.r, want, 1.0) << where;
                    EXPECT_EQ(p.r, p.g) << where;
                    EXPECT_EQ(p.r, p.b) << where;
                }
                // Per vertex and flat: the surface's own normal (flat: the face's winding,
                // which the mirror turns to −z, so only unmirrored).
                for (Shading shading : {Shading::Vertex, Shading::Flat}) {
                    if (shading == Shading::Flat && mirrored) continue;
                    for (const Rgba8 p : render(scene, shading, method))
                        EXPECT_NEAR(p.r, flat, 1.0) << where << " shading " << int(shading);
                }
            }
            // A mesh without tangents (the (0, 0, 0, 1) binding): the surface's own normal.
            scene.meshes[0].tangents.clear();
            for (const Rgba8 p : render(scene, Shading::Pixel, "multipass"))
                EXPECT_NEAR(p.r, flat, 1.0) << "no tangents, mirrored " << mirrored;
        }
    }
}

// ---- Image lighting (issue 39 item 2; environment.h, lighting.h environmentTerms) ----

/// A 64×32 radiance map: a warm upper half, a cool lower half, a bright patch up and to the
/// right of −z (the default camera's back), so diffuse, glossy and mirror-like lobes all see
/// structure.
RadianceMap syntheticMap() {
    RadianceMap map;
    map.width = 64;
    map.height = 32;
    map.name = "synthetic (test)";
    map.texels.resize(std::size_t(map.width) * std::size_t(map.height));
    for (int y = 0; y < map.height; ++y) {
        for (int x = 0; x < map.width; ++x) {
            glm::vec3 c = y < map.height / 2 ? glm::vec3(0.9f, 0.7f, 0.5f)
                                             : glm::vec3(0.15f, 0.25f, 0.4f);
            // a horizontal gradient, so u matters away from the patch
            c *= 0.75f + 0.5f * float(x) / float(map.width - 1);
            if (x >= 36 && x < 44 && y >= 8 && y < 13) c = glm::vec3(6.0f, 5.5f, 4.5f);
            map.texels[std::size_t(y) * std::size_t(map.width) + std::size_t(x)] = c;
        }
    }
    return map;
}

std::shared_ptr<const Environment> syntheticEnvironment() {
    static const auto env = std::make_shared<const Environment>(buildEnvironment(syntheticMap()));
    return env;
}

/// `scene` lit by `env` as the session lights it (ambient 0: the map is the ambient light),
/// every other instance double-sided.
Scene litBy(Scene scene, std::shared_ptr<const Environment> env) {
    scene.environment = std::move(env);
    scene.ambient = glm::vec3(0.0f);
    for (std::size_t i = 0; i < scene.instances.size(); i += 2)
        scene.instances[i].material.doubleSided = true;
    return scene;
}

/// The worst view's share of pixels more than 2/255 and 8/255 apart, and its largest delta.
struct EnvDiff {
    double over2 = 0.0, over8 = 0.0;
    int maxDelta = 0;
    void add(const Image& a, const Image& b) {
        over2 = std::max(over2, offShare(a, b, 2));
        over8 = std::max(over8, offShare(a, b, 8));
        maxDelta = std::max(maxDelta, compareImages(a, b, 0).maxDelta);
    }
};

// Every vk method in every shading against soft:multipass on scenes lit by a map: Blinn-Phong
// (untextured; textured), metallic-roughness (with a point light), the texture maps (occlusion
// on the environment's light, normal maps, metallic-roughness maps) and vertex colours, every
// other instance double-sided, plus --specular per-view in pixel shading. Every vk method equal
// to vk:multipass. Measured on lavapipe (Mesa 22.3.6), 160×120, 3 views: see src/vk/README.md.
TEST(VkBackend, EnvironmentLightsEveryMethodAsSoft) {
    MVR_SKIP_WITHOUT_VK();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    const auto env = syntheticEnvironment();
    struct Case {
        const char* name;
        Scene scene;
        double over2, over8;  // bounds vs soft (the worst view)
    };
    const Case cases[] = {
        {"blinn-phong", litBy(defaultScene(), env), 0.01, 0.001},
        {"textured", litBy(makeTexturedScene(), env), 0.02, 0.005},
        {"metallic-roughness", litBy(::mvr::test::pbrScene(), env), 0.01, 0.001},
        {"mapped", litBy(::mvr::test::mappedScene(), env), 0.03, 0.01},
        {"coloured", litBy(::mvr::test::coloredScene(), env), 0.01, 0.001},
    };
    for (const Case& c : cases) {
        const Rig rig = rigFor(c.scene, 3, 1, 4.0f / 3.0f);
        for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
            for (const bool perView : {false, true}) {
                if (perView && sh != Shading::Pixel) continue;
                RenderSettings s = small(sh);
                s.width = 160;
                s.height = 120;
                if (perView) s.specular = SpecularEye::PerView;
                auto ref = (*soft)->render(c.scene, rig, s, "multipass");
                ASSERT_TRUE(ref) << ref.status().message();
                std::optional<RenderOutput> first;
                EnvDiff vsSoft, vsMultipass;
                for (const char* m : {"multipass", "multiview", "instanced-layer", "auto"}) {
                    const std::string where = fmt::format("{} vk:{} {}{}", c.name, m,
                                                          shadingName(sh),
                                                          perView ? " per-view" : "");
                    SCOPED_TRACE(where);
                    if (Status st = backend().supports(m); !st) {
                        ASSERT_EQ(st.code(), ErrorCode::Unsupported) << st.message();
                        continue;
                    }
                    auto out = backend().render(c.scene, rig, s, m);
                    ASSERT_TRUE(out) << out.status().message();
                    ASSERT_EQ(out->color.size(), 3u);
                    EnvDiff one;
                    for (int v = 0; v < 3; ++v) {
                        one.add(out->color[std::size_t(v)], ref->color[std::size_t(v)]);
                        vsSoft.add(out->color[std::size_t(v)], ref->color[std::size_t(v)]);
                        if (first) {
                            vsMultipass.add(out->color[std::size_t(v)],
                                            first->color[std::size_t(v)]);
                            // The methods run the same shaders on the same images.
                            EXPECT_LE(offShare(out->color[std::size_t(v)],
                                               first->color[std::size_t(v)], 2),
                                      0.002)
                                << "view " << v << " vs vk:multipass";
                        }
                    }
                    EXPECT_LE(one.over2, c.over2);
                    EXPECT_LE(one.over8, c.over8);
                    if (!first) first = std::move(*out);
                }
                std::printf("[ env ] %-18s %-6s%-9s vs soft: %.3f %% > 2/255, %.3f %% > 8/255, "
                            "max %d/255; methods vs vk:multipass max %d/255\n",
                            c.name, shadingName(sh), perView ? " per-view" : "",
                            100.0 * vsSoft.over2, 100.0 * vsSoft.over8, vsSoft.maxDelta,
                            vsMultipass.maxDelta);
            }
        }
    }
}

/// The quad of quadScene, white, Lambertian (Blinn-Phong, specular 0), no light, ambient 0,
/// vertex colours off, lit by `env`.
Scene lambertianQuad(std::shared_ptr<const Environment> env) {
    Scene scene = quadScene(glm::vec4(1.0f), false);
    scene.meshes[0].colors.clear();
    scene.ambient = glm::vec3(0.0f);
    scene.environment = std::move(env);
    return scene;
}

// Known values: a map of uniform radiance c lights a white Lambertian surface to c
// (environment.h: diffuseLight of a uniform map is c), whichever way it faces; a map lit in
// its upper half only to (1 + n.y) / 2 · c, c / 2 on the quad facing +z. Every method and
// shading, within 1/255 of the value computed here.
TEST(VkBackend, EnvironmentOfUniformRadianceLightsALambertianSurfaceToIt) {
    MVR_SKIP_WITHOUT_VK();
    const glm::vec3 c(0.3f, 0.55f, 0.8f);
    RadianceMap uniform;
    uniform.width = 64;
    uniform.height = 32;
    uniform.name = "uniform (test)";
    uniform.texels.assign(64 * 32, c);
    RadianceMap upper = uniform;
    upper.name = "upper half (test)";
    for (int y = 16; y < 32; ++y)
        for (int x = 0; x < 64; ++x) upper.texels[std::size_t(y * 64 + x)] = glm::vec3(0.0f);
    const struct {
        const RadianceMap* map;
        glm::vec3 want;
    } cases[] = {{&uniform, c}, {&upper, c * 0.5f}};
    const Rig rig = quadRig(2);
    for (const auto& k : cases) {
        const Scene scene =
            lambertianQuad(std::make_shared<const Environment>(buildEnvironment(*k.map)));
        for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
            for (const char* m : {"multipass", "multiview", "instanced-layer"}) {
                RenderSettings s = small(sh);
                s.width = s.height = 64;
                auto r = backend().render(scene, rig, s, m);
                ASSERT_TRUE(r) << m << ": " << r.status().message();
                for (const Image& im : r->color) {
                    for (const auto& [x, y] : {std::pair{32, 32}, std::pair{8, 8},
                                               std::pair{56, 50}}) {
                        const Rgba8 p = im.at(x, y);
                        const std::string where =
                            fmt::format("{} {} {} at {},{}", k.map->name, m, shadingName(sh), x, y);
                        EXPECT_NEAR(p.r, k.want.x * 255.0f, 1.0f) << where;
                        EXPECT_NEAR(p.g, k.want.y * 255.0f, 1.0f) << where;
                        EXPECT_NEAR(p.b, k.want.z * 255.0f, 1.0f) << where;
                    }
                }
            }
        }
    }
}

// The environment's images on the device: the same object again is the same image (a
// sequence); another object, or the same object with other content, lights as a fresh upload
// would; without an environment the pixels are those of before (the 1x1 image bound, unread).
TEST(VkBackend, EnvironmentIsUploadedByObjectAndContent) {
    MVR_SKIP_WITHOUT_VK();
    const Scene plain = ::mvr::test::withMetallicRoughness(defaultScene());
    const Rig rig = rigFor(plain, 2, 1, float(kW) / kH);
    const RenderSettings s = small(Shading::Pixel);
    auto render = [&](const Scene& scene) {
        auto r = backend().render(scene, rig, s, "multipass");
        EXPECT_TRUE(r) << r.status().message();
        return r ? std::vector<std::uint8_t>(r->color[1].rgba.begin(), r->color[1].rgba.end())
                 : std::vector<std::uint8_t>{};
    };
    const auto before = render(plain);
    auto env = std::make_shared<Environment>(buildEnvironment(syntheticMap()));
    Scene lit = plain;
    lit.environment = env;
    const auto a = render(lit);
    EXPECT_NE(a, before);
    EXPECT_EQ(render(lit), a);
    // Another map, then the first again.
    RadianceMap dim = syntheticMap();
    for (glm::vec3& t : dim.texels) t *= 0.25f;
    Scene other = plain;
    other.environment = std::make_shared<const Environment>(buildEnvironment(dim));
    const auto b = render(other);
    EXPECT_NE(b, a);
    EXPECT_EQ(render(lit), a);
    // The same object with the dim map's content: as the dim map's own object.
    *env = *std::static_pointer_cast<const Environment>(other.environment);
    EXPECT_EQ(render(lit), b);
    EXPECT_EQ(render(plain), before);
}

}  // namespace
}  // namespace mvr::vk::test
