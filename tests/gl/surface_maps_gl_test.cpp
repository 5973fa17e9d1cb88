// glTF's other texture slots on the gl backend (issue 39; lighting.h SurfaceMaps): the
// occlusion map (linear data, not sRGB-decoded) scaling the ambient term, the emissive map
// (sRGB) scaling a metallic-roughness material's emissive, in every shading and exact method,
// on a material without a base colour texture; one image used as colour and as data (two GL
// textures, not one cached upload); the metallic-roughness map per pixel only. Texels at known
// coordinates against values computed here; each exact method against gl:multipass on the
// mapped scene of the conformance suite (kGlExact).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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
Mesh quadMesh() {
    Mesh m;
    m.name = "quad";
    m.positions = {{-1, 1, 0}, {1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
    m.normals.assign(4, glm::vec3(0, 0, 1));
    m.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.indices = {0, 3, 2, 0, 2, 1};
    return m;
}

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

Rig monoRig() {
    Camera cam;
    cam.position = {0, 0, 2.0f};
    cam.target = {0, 0, 0};
    cam.fovYDegrees = 60.0f;
    cam.aspect = float(kW) / kH;
    RigParams p;
    p.columns = 1;
    p.rows = 1;
    p.convergence = 2.0f;
    p.interaxial = 0.0f;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

std::vector<std::string> exactMethods() {
    std::vector<std::string> out;
    for (const std::string& m : backend().methods()) {
        if (m != "auto" && m != "gs-mrt" && m != "gs-depthmap") out.push_back(m);
    }
    return out;
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

}  // namespace
}  // namespace mvr::gl::test
