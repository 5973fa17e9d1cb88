// glTF's other texture slots on the gl backend (issue 39; lighting.h SurfaceMaps): the
// occlusion map (linear data, not sRGB-decoded) scaling the ambient term, the emissive map
// (sRGB) scaling a metallic-roughness material's emissive, in every shading and exact method,
// on a material without a base colour texture; one image used as colour and as data (two GL
// textures, not one cached upload); the metallic-roughness map per pixel only. Texels at known
// coordinates against values computed here; the normal map's bent normal against the
// tangent-frame formula written out; each exact method against gl:multipass on the mapped
// scene of the conformance suite (kGlExact).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "gl_test_util.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

constexpr int kW = 160, kH = 120;

RenderSettings settings(Shading shading) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = shading;
    s.cullBackFaces = false;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

// The IEC 61966-2-1 decode, computed independently of texture_sampling.h.
double srgbDecode(int b) {
    const double c = b / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// A unit quad in the XY plane facing +Z (toward a camera on +Z), texture coordinates (0, 0)
// at the top-left corner.
// A 2x2 image of four distinct opaque colours; its R channel as linear data (200, 30, 20, 128
// / 255) is far from its sRGB decode (0.58, 0.013, 0.007, 0.22).
Image quadImage() {
    Image img(2, 2);
    img.set(0, 0, {200, 40, 30, 255});
    img.set(1, 0, {30, 180, 60, 255});
    img.set(0, 1, {20, 50, 210, 255});
    img.set(1, 1, {128, 128, 128, 255});
    return img;
}

mvr::Texture texture(const Image& img, bool linear, const std::string& name) {
    mvr::Texture t;
    t.name = name;
    t.image = img;
    t.linear = linear;
    return t;
}

// The quad, white, lit by ambient 1 only; nearest sampling without mipmaps, so each quarter of
// the quad is one texel. No texture slot set (the tests set theirs).
Scene quadScene() {
    Scene s;
    s.meshes.push_back(quadMesh());
    Instance inst;
    inst.material.albedo = glm::vec3(1.0f);
    inst.material.sampler.magFilter = TextureFilter::Nearest;
    inst.material.sampler.minFilter = TextureFilter::Nearest;
    inst.material.sampler.mipmaps = false;
    s.instances.push_back(inst);
    s.ambient = glm::vec3(1.0f);
    s.background = glm::vec3(0.0f);
    return s;
}

/// One probe per quarter of the quad: pixel (x, y) shows texel (tx, ty).
struct Probe {
    int x, y, tx, ty;
};
std::vector<Probe> quarterProbes() {
    // The quad spans ±1 at distance 2 with a 60° vertical field: ±0.577 of the half-height.
    const int cx = kW / 2, cy = kH / 2, d = int(0.25 * kH / 2 / std::tan(glm::radians(30.0f)));
    return {{cx - d, cy - d, 0, 0}, {cx + d, cy - d, 1, 0}, {cx - d, cy + d, 0, 1},
            {cx + d, cy + d, 1, 1}};
}

/// Every probe of `img` within 1 of want(texel) · 255 per channel.
template <class Want>
void expectQuarters(const Image& img, const Image& texels, Want want, const std::string& what) {
    for (const Probe& p : quarterProbes()) {
        const glm::dvec3 w = want(texels.at(p.tx, p.ty));
        const Rgba8 got = img.at(p.x, p.y);
        const int have[3] = {got.r, got.g, got.b};
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(have[c], std::clamp(w[c], 0.0, 1.0) * 255.0, 1.0)
                << what << ": texel (" << p.tx << "," << p.ty << ") channel " << c;
        }
    }
}

// The occlusion map is data: R / 255 as stored (GL_RGBA8, no sRGB decode), occlusion = 1 +
// strength · (R − 1) scaling the ambient term, with no base colour texture (the material is
// still textured: hasTexture), in every shading and exact method.
TEST(GlSurfaceMaps, OcclusionIsLinearAndScalesTheAmbient) {
    MVR_SKIP_WITHOUT_GL();
    Scene scene = quadScene();
    scene.textures.push_back(texture(quadImage(), true, "occlusion"));
    scene.instances[0].material.occlusionTexture = 0;
    scene.instances[0].material.occlusionStrength = 0.5f;
    const auto want = [](Rgba8 t) { return glm::dvec3(1.0 + 0.5 * (t.r / 255.0 - 1.0)); };
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        for (const std::string& m : exactMethods()) {
            if (!backend().supports(m)) continue;
            auto out = backend().render(scene, monoRig(), settings(sh), m);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            expectQuarters(out->color[0], scene.textures[0].image, want,
                           m + " " + shadingName(sh));
        }
    }
}

// One image as the base colour (sRGB) and as the occlusion (linear): two uploads, each sampled
// as its slot says, whichever of the two the scene lists first (one cached texture for both
// would decode the occlusion, or not the colour).
TEST(GlSurfaceMaps, OneImageAsColourAndAsDataIsTwoTextures) {
    MVR_SKIP_WITHOUT_GL();
    for (bool linearFirst : {false, true}) {
        Scene scene = quadScene();
        const int colour = linearFirst ? 1 : 0, data = 1 - colour;
        scene.textures.resize(2);
        scene.textures[std::size_t(colour)] = texture(quadImage(), false, "colour");
        scene.textures[std::size_t(data)] = texture(quadImage(), true, "data");
        scene.instances[0].material.baseColorTexture = colour;
        scene.instances[0].material.occlusionTexture = data;
        const auto want = [](Rgba8 t) {
            return glm::dvec3(srgbDecode(t.r), srgbDecode(t.g), srgbDecode(t.b)) * (t.r / 255.0);
        };
        auto out = backend().render(scene, monoRig(), settings(Shading::Pixel), "multipass");
        ASSERT_TRUE(out) << out.status().message();
        expectQuarters(out->color[0], quadImage(), want,
                       linearFirst ? "linear listed first" : "sRGB listed first");
    }
}

// The emissive map (sRGB, decoded) scales a metallic-roughness material's emissive in every
// shading (flat's S is the emissive too); unlit, dark, so the colour is emissive × texel.
TEST(GlSurfaceMaps, EmissiveMapScalesTheEmissive) {
    MVR_SKIP_WITHOUT_GL();
    Scene scene = quadScene();
    scene.ambient = glm::vec3(0.0f);
    scene.textures.push_back(texture(quadImage(), false, "emissive"));
    Material& m = scene.instances[0].material;
    m.model = MaterialModel::MetallicRoughness;
    m.emissive = glm::vec3(1.0f, 0.5f, 0.8f);
    m.emissiveTexture = 0;
    const auto want = [](Rgba8 t) {
        return glm::dvec3(1.0, 0.5, 0.8) *
               glm::dvec3(srgbDecode(t.r), srgbDecode(t.g), srgbDecode(t.b));
    };
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        for (const std::string& method : exactMethods()) {
            if (!backend().supports(method)) continue;
            auto out = backend().render(scene, monoRig(), settings(sh), method);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << method << ": " << out.status().message();
            expectQuarters(out->color[0], scene.textures[0].image, want,
                           method + " " + shadingName(sh));
        }
    }
    // Blinn-Phong has no emissive for the map to scale.
    m.model = MaterialModel::BlinnPhong;
    auto out = backend().render(scene, monoRig(), settings(Shading::Pixel), "multipass");
    ASSERT_TRUE(out) << out.status().message();
    expectQuarters(out->color[0], scene.textures[0].image,
                   [](Rgba8) { return glm::dvec3(0.0); }, "Blinn-Phong");
}

// The metallic-roughness map multiplies the factors per pixel and is not applied in vertex
// shading: a map of G 255 (roughness × 1), B 0 (metallic × 0) on a metal looks like the
// dielectric of the same roughness in pixel shading and like the metal in vertex shading. The
// references carry a neutral occlusion map (R 255) so that they are textured too (the same
// split D / S path).
TEST(GlSurfaceMaps, MetallicRoughnessMapScalesTheFactorsPerPixel) {
    MVR_SKIP_WITHOUT_GL();
    Scene base = quadScene();
    base.ambient = glm::vec3(0.1f);
    Light light;
    light.towardLight = glm::normalize(glm::vec3(0.3f, 0.4f, 1.0f));
    light.color = glm::vec3(1.0f);
    base.lights = {light};
    base.textures.push_back(texture(Image(2, 2, {0, 255, 0, 255}), true, "metallic-roughness"));
    base.textures.push_back(texture(Image(2, 2, {255, 255, 255, 255}), true, "occlusion"));
    Material& bm = base.instances[0].material;
    bm.model = MaterialModel::MetallicRoughness;
    bm.albedo = glm::vec3(0.8f, 0.4f, 0.2f);
    bm.roughness = 0.4f;
    bm.metallic = 1.0f;
    Scene mapped = base, metal = base, dielectric = base;
    mapped.instances[0].material.metallicRoughnessTexture = 0;
    metal.instances[0].material.occlusionTexture = 1;
    dielectric.instances[0].material.occlusionTexture = 1;
    dielectric.instances[0].material.metallic = 0.0f;
    for (Shading sh : {Shading::Vertex, Shading::Pixel}) {
        auto a = backend().render(mapped, monoRig(), settings(sh), "multipass");
        auto m = backend().render(metal, monoRig(), settings(sh), "multipass");
        auto d = backend().render(dielectric, monoRig(), settings(sh), "multipass");
        ASSERT_TRUE(a && m && d);
        // The two references differ (the test can tell them apart).
        EXPECT_GT(compareImages(m->color[0], d->color[0], 8).differingPixels, kW * kH / 10)
            << shadingName(sh);
        const Image& want = sh == Shading::Pixel ? d->color[0] : m->color[0];
        const ImageDiff diff = compareImages(want, a->color[0], 1);
        EXPECT_EQ(diff.differingPixels, 0L) << shadingName(sh) << ": max " << diff.maxDelta;
    }
}

/// The normal a normal map's texel gives a surface whose normal, tangent and bitangent are the
/// unit vectors n, t, b: glTF's tangent-space normal (2·rgb − 1, x and y × scale) in that frame,
/// written out in double.
glm::dvec3 mappedNormal(Rgba8 texel, double scale, glm::dvec3 t, glm::dvec3 b, glm::dvec3 n) {
    const glm::dvec3 c((2.0 * texel.r / 255.0 - 1.0) * scale, (2.0 * texel.g / 255.0 - 1.0) * scale,
                       2.0 * texel.b / 255.0 - 1.0);
    return glm::normalize(t * c.x + b * c.y + n * c.z);
}

// The normal map bends the normal in the tangent frame, per pixel, in every exact method: a
// white Lambert quad under one light, a uniform normal map (linear data), its colour the
// tangent-frame normal's n · l; mirrored in x (u runs along −x, the handedness flips with the
// mirror, the bitangent stays +y). Per vertex, and on a mesh without tangents (also in a frame
// where another mesh has them), the quad's own normal.
TEST(GlSurfaceMaps, NormalMapBendsTheNormalInTheTangentFrame) {
    MVR_SKIP_WITHOUT_GL();
    const glm::dvec3 light = glm::normalize(glm::dvec3(0.5, 0.4, 0.77));
    const Probe centre{kW / 2, kH / 2, 0, 0};
    auto pixel = [&](const Scene& scene, Shading sh, const std::string& method) {
        auto out = backend().render(scene, monoRig(), settings(sh), method);
        if (!out && out.status().code() == ErrorCode::Unsupported) return -1;
        EXPECT_TRUE(out) << method << ": " << out.status().message();
        return out ? int(out->color[0].at(centre.x, centre.y).r) : -1;
    };
    const double flat = glm::dot(glm::dvec3(0, 0, 1), light) * 255.0;
    for (const Rgba8 texel : {Rgba8{255, 128, 128, 255}, Rgba8{128, 255, 128, 255},
                              Rgba8{40, 90, 200, 255}, Rgba8{128, 128, 255, 255}}) {
        for (const bool mirrored : {false, true}) {
            // The quad faces +z with u along +x and the image's top at +y: tangent +x,
            // handedness +1 (bitangent cross(n, t) = +y).
            Scene scene = quadScene();
            scene.meshes[0].tangents.assign(4, glm::vec4(1, 0, 0, 1));
            scene.ambient = glm::vec3(0.0f);
            Light l;
            l.towardLight = glm::vec3(light);
            l.color = glm::vec3(1.0f);
            scene.lights = {l};
            scene.textures.push_back(texture(Image(4, 4, texel), true, "normal"));
            Material& m = scene.instances[0].material;
            m.specular = 0.0f;
            m.normalTexture = 0;
            m.normalScale = 0.8f;
            if (mirrored)
                scene.instances[0].worldFromModel = glm::scale(glm::mat4(1.0f), {-1, 1, 1});
            const glm::dvec3 n =
                mappedNormal(texel, 0.8, {mirrored ? -1.0 : 1.0, 0, 0}, {0, 1, 0}, {0, 0, 1});
            const double want = std::max(0.0, glm::dot(n, light)) * 255.0;
            const std::string what = fmt::format("texel {},{},{} mirrored {}", int(texel.r),
                                                 int(texel.g), int(texel.b), mirrored);
            for (const std::string& method : exactMethods()) {
                if (!backend().supports(method)) continue;
                const int got = pixel(scene, Shading::Pixel, method);
                if (got < 0) continue;
                EXPECT_NEAR(got, want, 1.0) << what << " " << method;
                // Per vertex: the surface's own normal.
                EXPECT_NEAR(pixel(scene, Shading::Vertex, method), flat, 1.0)
                    << what << " " << method << " vertex";
            }
            // A mesh without tangents: the surface's own normal, alone and beside a mesh with
            // them (a frame drawn with the tangent, its attribute the constant (0, 0, 0, 1)):
            // a small normal-mapped quad with tangents in a corner.
            Scene bare = scene;
            bare.meshes[0].tangents.clear();
            Scene beside = bare;
            beside.meshes.push_back(scene.meshes[0]);
            Instance corner = scene.instances[0];
            corner.mesh = 1;
            corner.worldFromModel =
                glm::scale(glm::translate(glm::mat4(1.0f), {0.9f, 0.9f, 0.0f}), glm::vec3(0.05f));
            beside.instances.push_back(corner);
            for (const std::string& method : exactMethods()) {
                if (!backend().supports(method)) continue;
                for (const Scene* sc : {&bare, &beside}) {
                    const int got = pixel(*sc, Shading::Pixel, method);
                    if (got < 0) continue;
                    EXPECT_NEAR(got, flat, 1.0)
                        << what << " " << method << " without tangents"
                        << (sc == &beside ? " beside a mesh with them" : "");
                }
            }
        }
    }
}

// Every exact method on the mapped scene (the conformance suite's: every slot, some instances
// without a base colour texture) against gl:multipass in every shading (kGlExact).
TEST(GlSurfaceMaps, EveryExactMethodMatchesMultipass) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = ::mvr::test::mappedScene();
    const conformance::Bound& b = conformance::kGlExact;
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        const Rig rig = rigFor(scene, 3, 2);
        const RenderSettings s = settings(sh);
        auto ref = backend().render(scene, rig, s, "multipass");
        ASSERT_TRUE(ref) << ref.status().message();
        for (const std::string& m : exactMethods()) {
            if (!backend().supports(m)) continue;
            auto out = backend().render(scene, rig, s, m);
            if (!out && out.status().code() == ErrorCode::Unsupported) continue;
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            for (std::size_t v = 0; v < ref->color.size(); ++v) {
                const ImageDiff d = compareImages(ref->color[v], out->color[v], b.channel);
                const double share = double(d.differingPixels) / (kW * kH);
                EXPECT_TRUE(b.shareFor(int(v)).holds(share))
                    << m << " " << shadingName(sh) << " view " << v << ": " << 100 * share
                    << " % off by more than " << b.channel << "/255, max " << d.maxDelta;
            }
        }
    }
}

// Pixel shading with normal maps on more views than a geometry-shader pass takes with the
// tangent (its 4 components a vertex lower the views a pass: 22 on llvmpipe's 1024 components,
// 31 without): every method batches them and matches gl:multipass (kGlExact), view by view.
TEST(GlSurfaceMaps, NormalMappedViewsBatchOnEveryMethod) {
    MVR_SKIP_WITHOUT_GL();
    const Scene& scene = ::mvr::test::mappedScene();
    const conformance::Bound& b = conformance::kGlExact;
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
        const auto stats = backend().lastStats();
        ASSERT_TRUE(stats) << m;
        for (std::size_t v = 0; v < ref->color.size(); ++v) {
            const ImageDiff d = compareImages(ref->color[v], out->color[v], b.channel);
            const double share = double(d.differingPixels) / (kSmallW * kSmallH);
            EXPECT_TRUE(b.shareFor(int(v)).holds(share))
                << m << " (" << stats->passes << " passes) view " << v << ": " << 100 * share
                << " % off by more than " << b.channel << "/255, max " << d.maxDelta;
        }
    }
}

}  // namespace
}  // namespace mvr::gl::test
