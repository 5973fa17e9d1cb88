// glTF metallic-roughness materials (issue 39 item 1; lighting.h): the BRDF at known normal /
// light / view angles against glTF 2.0's Appendix B written out here in double precision (the
// specification's functions by their names: D_GGX, V_GGX, conductor_fresnel, fresnel_mix), the
// D / S split textured surfaces use against the same formula, unlit, and what the glTF reader
// takes from a file laid out as Blender's exporter writes materials.
#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/core/lighting.h"
#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"
#include "gltf_maps_fixture.h"
#include "test_files.h"
#include "tonemap_reference.h"

namespace mvr {
namespace {

using dvec3 = glm::dvec3;
constexpr double kPi = 3.14159265358979323846;

// ---- glTF 2.0 Appendix B, as the specification writes it ------------------------------------
double heaviside(double x) { return x > 0.0 ? 1.0 : 0.0; }
double dGgx(double alpha, double nh) {
    const double a2 = alpha * alpha;
    const double k = nh * nh * (a2 - 1.0) + 1.0;
    return a2 * heaviside(nh) / (kPi * k * k);
}
double vGgx(double alpha, double nl, double nv, double hl, double hv) {
    const double a2 = alpha * alpha;
    return heaviside(hl) * heaviside(hv) /
           ((std::abs(nl) + std::sqrt(a2 + (1.0 - a2) * nl * nl)) *
            (std::abs(nv) + std::sqrt(a2 + (1.0 - a2) * nv * nv)));
}
/// f(l, v) of the metallic-roughness material (Appendix B.3.5's "complete model").
dvec3 brdf(dvec3 base, double metallic, double roughness, dvec3 n, dvec3 l, dvec3 v) {
    const dvec3 h = glm::normalize(l + v);
    const double alpha = roughness * roughness;
    const double specular = vGgx(alpha, glm::dot(n, l), glm::dot(n, v), glm::dot(h, l),
                                 glm::dot(h, v)) *
                            dGgx(alpha, glm::dot(n, h));
    const double vh5 = std::pow(1.0 - std::abs(glm::dot(v, h)), 5.0);
    const dvec3 metal = specular * (base + (dvec3(1.0) - base) * vh5);   // conductor_fresnel
    const double f0 = std::pow((1.0 - 1.5) / (1.0 + 1.5), 2.0);          // ior 1.5: 0.04
    const double fr = f0 + (1.0 - f0) * vh5;
    const dvec3 dielectric = glm::mix(base / kPi, dvec3(specular), fr);  // fresnel_mix
    return glm::mix(dielectric, metal, metallic);
}

glm::vec3 fromAngles(double theta, double phi) {  // about +z
    return glm::vec3(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                     float(std::cos(theta)));
}

struct Surface {
    Light light;
    ShadingContext ctx;
    glm::vec3 n, l, v;
};

/// A surface at the origin with normal n, a directional light from l, the centre eye 10 along
/// v; ambient 0.05; light colour (0.9, 0.8, 0.7).
Surface surface(glm::vec3 n, glm::vec3 l, glm::vec3 v) {
    Surface s;
    s.n = n, s.l = l, s.v = v;
    s.light.towardLight = l;
    s.light.color = glm::vec3(0.9f, 0.8f, 0.7f);
    s.ctx.ambient = glm::vec3(0.05f);
    s.ctx.centerEye = 10.0f * v;
    return s;
}

TEST(MetallicRoughness, BrdfAtKnownAnglesIsTheSpecifications) {
    const glm::vec3 n(0, 0, 1);
    struct Angles {
        double lTheta, lPhi, vTheta, vPhi;
    };
    // Near the mirror direction (the highlight), off it, grazing, and head-on.
    const Angles angles[] = {{0.5, 0.0, 0.5, kPi}, {0.6, 0.3, 0.2, 2.0}, {1.3, 0.0, 0.4, 1.0},
                             {0.0, 0.0, 0.0, 0.0}};
    const glm::vec3 base(0.6f, 0.3f, 0.15f);
    int checked = 0;
    for (const Angles& a : angles) {
        Surface s = surface(n, fromAngles(a.lTheta, a.lPhi), fromAngles(a.vTheta, a.vPhi));
        s.ctx.lights = std::span<const Light>(&s.light, 1);
        for (float metallic : {0.0f, 0.5f, 1.0f}) {
            for (float roughness : {0.3f, 0.6f, 1.0f}) {
                Material m(base);
                m.model = MaterialModel::MetallicRoughness;
                m.metallic = metallic;
                m.roughness = roughness;
                const dvec3 f = brdf(dvec3(base), metallic, roughness, dvec3(n), dvec3(s.l),
                                     dvec3(s.v));
                // The light dimmed where the highlight would clip (so the formula is seen).
                const dvec3 unit = kPi * f * double(glm::dot(n, s.l)) * dvec3(0.9, 0.8, 0.7);
                const double peak = std::max({unit.x, unit.y, unit.z});
                s.light.color = glm::vec3(0.9f, 0.8f, 0.7f) * float(peak > 0.8 ? 0.8 / peak : 1.0);
                // mvr's light convention (lighting.h): radiance = π · f · n·l · colour.
                const dvec3 want = dvec3(s.ctx.ambient) * dvec3(base) +
                                   kPi * f * double(glm::dot(n, s.l)) * dvec3(s.light.color);
                const glm::vec3 got = shadeBlinnPhong(s.ctx, m, n, glm::vec3(0.0f));
                const std::string what = fmt::format("l ({}, {}), v ({}, {}), metallic {}, "
                                                     "roughness {}",
                                                     a.lTheta, a.lPhi, a.vTheta, a.vPhi, metallic,
                                                     roughness);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_LT(want[k], 1.0) << what;  // not clamped: the formula is seen
                    EXPECT_NEAR(got[k], want[k], 2e-6 + 2e-5 * want[k]) << what << ", channel " << k;
                }
                // The textured split: base ⊙ D + S with the base colour in the texel.
                Material white = m;
                white.albedo = glm::vec3(1.0f);
                const LightTerms t = blinnPhongTerms(s.ctx, white, n, glm::vec3(0.0f));
                const glm::vec3 split = shadeTextured(base, t);
                for (int k = 0; k < 3; ++k)
                    EXPECT_NEAR(split[k], want[k], 2e-6 + 2e-5 * want[k]) << what << " (split)";
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 36);
}

TEST(MetallicRoughness, HighlightSharpensWithLowRoughnessAndMetalsTintIt) {
    // Mirror configuration: a smoother surface's highlight is brighter; a metal's specular
    // takes the base colour, a dielectric's stays white (its R = G = B apart from the diffuse).
    Surface s = surface(glm::vec3(0, 0, 1), fromAngles(0.4, 0.0), fromAngles(0.4, kPi));
    s.ctx.lights = std::span<const Light>(&s.light, 1);
    s.light.color = glm::vec3(0.2f);
    s.ctx.ambient = glm::vec3(0.0f);
    Material m(glm::vec3(0.9f, 0.5f, 0.1f));
    m.model = MaterialModel::MetallicRoughness;
    m.metallic = 1.0f;
    float last = 0.0f;
    for (float r : {1.0f, 0.7f, 0.5f, 0.35f}) {
        m.roughness = r;
        const float g = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f)).y;
        EXPECT_GT(g, last) << "roughness " << r;
        last = g;
    }
    // At the mirror angle w ≈ 0: a metal's highlight is its base colour (0.9, 0.5, 0.1), the
    // tint riding on D (× base). The light dimmed so that nothing clips.
    s.light.color = glm::vec3(0.02f);
    const glm::vec3 metal = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f));
    EXPECT_NEAR(metal.x / metal.z, 9.0f, 0.05f);
    EXPECT_NEAR(metal.y / metal.z, 5.0f, 0.05f);
    m.metallic = 0.0f;
    const LightTerms dielectric = blinnPhongTerms(s.ctx, m, s.n, glm::vec3(0.0f));
    EXPECT_FLOAT_EQ(dielectric.specular.x, dielectric.specular.y);
    EXPECT_FLOAT_EQ(dielectric.specular.y, dielectric.specular.z);
    // A mirror (roughness 0) stays finite.
    m.roughness = 0.0f;
    const glm::vec3 mirror = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f));
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(mirror[k]));
}

TEST(MetallicRoughness, EmissiveIsAddedOnceAndUnlitIsTheBaseColour) {
    Surface s = surface(glm::vec3(0, 0, 1), fromAngles(0.3, 0.0), fromAngles(0.2, 1.0));
    s.ctx.lights = std::span<const Light>(&s.light, 1);
    Material m(glm::vec3(0.2f, 0.1f, 0.1f));
    m.model = MaterialModel::MetallicRoughness;
    m.metallic = 0.0f;
    m.roughness = 0.8f;
    const glm::vec3 dark = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f));
    m.emissive = glm::vec3(0.25f, 0.0f, 0.5f);
    const glm::vec3 lit = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f));
    EXPECT_NEAR(lit.x - dark.x, 0.25f, 1e-6f);
    EXPECT_NEAR(lit.y - dark.y, 0.0f, 1e-6f);
    EXPECT_NEAR(lit.z - dark.z, 0.5f, 1e-6f);
    // Flat: Lambert of the base colour (ambient + n·l · light), plus the emissive, once.
    {
        const glm::vec3 p(0.0f);
        const double nl = std::max(0.0, double(glm::dot(s.n, s.light.towardLight)));
        const glm::dvec3 lambert = glm::dvec3(m.albedo) *
                                   (glm::dvec3(s.ctx.ambient) + nl * glm::dvec3(s.light.color));
        const glm::vec3 flat = shadeFlat(s.ctx, m, s.n, p);
        EXPECT_NEAR(flat.x, lambert.x + 0.25, 1e-5);
        EXPECT_NEAR(flat.y, lambert.y, 1e-5);
        EXPECT_NEAR(flat.z, lambert.z + 0.5, 1e-5);
        const LightTerms t = flatTerms(s.ctx, m, s.n, p);
        EXPECT_EQ(t.specular, m.emissive);
        const glm::vec3 textured = shadeTextured(m.albedo, t);  // textured flat agrees
        EXPECT_NEAR(textured.x, flat.x, 1e-6f);
        EXPECT_NEAR(textured.y, flat.y, 1e-6f);
        EXPECT_NEAR(textured.z, flat.z, 1e-6f);
        Material bp(m.albedo);  // Blinn-Phong has no emissive
        EXPECT_EQ(flatTerms(s.ctx, bp, s.n, p).specular, glm::vec3(0.0f));
    }

    Material u(glm::vec3(0.3f, 0.6f, 0.9f));
    u.model = MaterialModel::Unlit;
    const glm::vec3 p(0.0f);
    EXPECT_EQ(shadeBlinnPhong(s.ctx, u, s.n, p), u.albedo);
    EXPECT_EQ(shadeFlat(s.ctx, u, s.n, p), u.albedo);
    EXPECT_EQ(shadeTextured(u.albedo, blinnPhongTerms(s.ctx, u, s.n, p)), u.albedo);
    EXPECT_EQ(shadeTextured(u.albedo, flatTerms(s.ctx, u, s.n, p)), u.albedo);
    // Facing away from the light too: unlit ignores lights.
    EXPECT_EQ(shadeBlinnPhong(s.ctx, u, -s.n, p), u.albedo);
}

// ---- tone mapping (issue 39 item 2) ----------------------------------------------------------

TEST(Tonemap, CurvesAreTheirSourcesAtKnownColours) {
    const glm::vec3 colours[] = {{0.5f, 0.3f, 0.1f}, {2.0f, 1.0f, 0.5f}, {10.0f, 10.0f, 10.0f},
                                 {0.02f, 0.5f, 0.9f}, {0.0f, 0.0f, 0.0f}, {0.7f, 0.75f, 0.8f}};
    ShadingContext neutral, aces, none;
    neutral.tonemap = Tonemap::KhrNeutral;
    aces.tonemap = Tonemap::Aces;
    for (const glm::vec3& c : colours) {
        const glm::dvec3 n = glm::clamp(test::khrPbrNeutralReference(glm::dvec3(c)), 0.0, 1.0);
        const glm::dvec3 a = test::acesNarkowiczReference(glm::dvec3(c));
        const glm::vec3 gotN = finishColor(neutral, c), gotA = finishColor(aces, c);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(gotN[k], n[k], 1e-6) << c.x << " " << c.y << " " << c.z;
            EXPECT_NEAR(gotA[k], a[k], 1e-6) << c.x << " " << c.y << " " << c.z;
            EXPECT_LE(gotN[k], 1.0f);
        }
        // none is the clamp, bit for bit.
        EXPECT_EQ(finishColor(none, c), glm::clamp(c, 0.0f, 1.0f));
    }
    // Neutral keeps colours under its knee apart from the small offset: 0.5 → 0.46.
    EXPECT_NEAR(finishColor(neutral, glm::vec3(0.5f)).x, 0.46f, 1e-6f);
    // ACES: 1 → 2.54 / 3.16.
    EXPECT_NEAR(finishColor(aces, glm::vec3(1.0f)).x, 2.54f / 3.16f, 1e-6f);
}

TEST(Tonemap, ShadingToneMapsWhereItClamped) {
    Surface s = surface(glm::vec3(0, 0, 1), fromAngles(0.4, 0.0), fromAngles(0.4, kPi));
    s.ctx.lights = std::span<const Light>(&s.light, 1);
    s.light.color = glm::vec3(6.0f);  // a bright highlight: clamped, it would be white
    s.ctx.tonemap = Tonemap::KhrNeutral;
    Material m(glm::vec3(0.8f, 0.4f, 0.2f));
    m.model = MaterialModel::MetallicRoughness;
    m.metallic = 0.0f;
    m.roughness = 0.4f;
    const LightTerms t = blinnPhongTerms(s.ctx, m, s.n, glm::vec3(0.0f));
    const glm::dvec3 lit = glm::dvec3(m.albedo) * glm::dvec3(t.diffuse) + glm::dvec3(t.specular);
    ASSERT_GT(lit.x, 1.0);
    const glm::dvec3 want = glm::clamp(test::khrPbrNeutralReference(lit), 0.0, 1.0);
    const glm::vec3 got = shadeBlinnPhong(s.ctx, m, s.n, glm::vec3(0.0f));
    const glm::vec3 split = shadeTextured(s.ctx, m.albedo, t);
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(got[k], want[k], 1e-5);
        EXPECT_NEAR(split[k], want[k], 1e-5);
    }
    EXPECT_LT(got.x, 1.0f);  // the highlight keeps a gradient
    // Blinn-Phong and flat are tone mapped too.
    Material bp(glm::vec3(0.5f));
    const glm::vec3 flat = shadeFlat(s.ctx, bp, s.n, glm::vec3(0.0f));
    ShadingContext clampOnly = s.ctx;
    clampOnly.tonemap = Tonemap::None;
    EXPECT_EQ(shadeFlat(clampOnly, bp, s.n, glm::vec3(0.0f)), glm::vec3(1.0f));
    EXPECT_LT(flat.x, 1.0f);
}

// ---- the reader ----------------------------------------------------------------------------

/// Six triangles, one a material, as Blender's exporter writes them: a glossy, partly
/// metallic, emissive one with KHR_materials_emissive_strength (Blender writes it for
/// strength > 1), an unlit one (KHR_materials_unlit, "Background" shader), one with an
/// empty pbrMetallicRoughness (glTF's defaults: metallic 1, roughness 1), one with a packed
/// metallic-roughness texture and the factors 1 / 1 beside it, one with an emission texture and
/// emissiveFactor [1, 1, 1] beside it, and a KHR_materials_pbrSpecularGlossiness one.
std::filesystem::path writeMaterials(const std::filesystem::path& dir) {
    std::string bin;
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(pos), sizeof pos);
    const std::string json = fmt::format(
        R"({{"asset":{{"version":"2.0","generator":"Khronos glTF Blender I/O v3.6.27"}},
"extensionsUsed":["KHR_materials_emissive_strength","KHR_materials_unlit","KHR_materials_pbrSpecularGlossiness"],
"scene":0,"scenes":[{{"name":"Scene","nodes":[0]}}],
"nodes":[{{"mesh":0,"name":"Tris"}}],
"materials":[
 {{"name":"Brass","emissiveFactor":[1,0.5,0],
   "extensions":{{"KHR_materials_emissive_strength":{{"emissiveStrength":4}}}},
   "pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.6,0.2,1],"metallicFactor":0.75,"roughnessFactor":0.3}}}},
 {{"name":"Flat","extensions":{{"KHR_materials_unlit":{{}}}},
   "pbrMetallicRoughness":{{"baseColorFactor":[0.1,0.7,0.3,1],"metallicFactor":0,"roughnessFactor":0.9}}}},
 {{"name":"Default","pbrMetallicRoughness":{{}}}},
 {{"name":"Packed","pbrMetallicRoughness":{{"metallicRoughnessTexture":{{"index":0}}}}}},
 {{"name":"Glow","emissiveFactor":[1,1,1],"emissiveTexture":{{"index":0}},"pbrMetallicRoughness":{{"metallicFactor":0}}}},
 {{"name":"Gloss","extensions":{{"KHR_materials_pbrSpecularGlossiness":{{"diffuseFactor":[0.5,0.5,0.5,1],"glossinessFactor":0.8}}}}}}],
"textures":[{{"source":0}}],"images":[{{"uri":"maps.png"}}],
"meshes":[{{"name":"Tris","primitives":[
 {{"attributes":{{"POSITION":0}},"material":0}},
 {{"attributes":{{"POSITION":0}},"material":1}},
 {{"attributes":{{"POSITION":0}},"material":2}},
 {{"attributes":{{"POSITION":0}},"material":3}},
 {{"attributes":{{"POSITION":0}},"material":4}},
 {{"attributes":{{"POSITION":0}},"material":5}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}}],
"buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{}"}}]}})",
        test::base64(bin));
    EXPECT_TRUE(writePng(dir / "maps.png", Image(4, 4, Rgba8{0, 128, 255, 255})));
    const auto path = dir / "materials.gltf";
    std::ofstream(path) << json;
    return path;
}

const Material* named(const Scene& s, const std::string& name) {
    for (const Instance& i : s.instances)
        if (i.material.name == name) return &i.material;
    return nullptr;
}

TEST(MetallicRoughness, GltfMaterialsAreReadAsTheFileSays) {
    test::TempDir dir("mvr-pbr");
    auto scene = loadScene(writeMaterials(dir.path()));
    ASSERT_TRUE(scene) << scene.status().message();
    const Material* brass = named(*scene, "Brass");
    const Material* flat = named(*scene, "Flat");
    const Material* def = named(*scene, "Default");
    ASSERT_TRUE(brass && flat && def);
    EXPECT_EQ(brass->model, MaterialModel::MetallicRoughness);
    EXPECT_FLOAT_EQ(brass->metallic, 0.75f);
    EXPECT_FLOAT_EQ(brass->roughness, 0.3f);
    EXPECT_FLOAT_EQ(brass->emissive.x, 4.0f);
    EXPECT_FLOAT_EQ(brass->emissive.y, 2.0f);
    EXPECT_FLOAT_EQ(brass->emissive.z, 0.0f);
    EXPECT_FLOAT_EQ(brass->albedo.y, 0.6f);
    EXPECT_EQ(flat->model, MaterialModel::Unlit);
    EXPECT_FLOAT_EQ(flat->albedo.y, 0.7f);
    EXPECT_EQ(def->model, MaterialModel::MetallicRoughness);
    EXPECT_FLOAT_EQ(def->metallic, 1.0f);
    EXPECT_FLOAT_EQ(def->roughness, 1.0f);
    EXPECT_EQ(def->emissive, glm::vec3(0.0f));
    // The triangles have no texture coordinates, so the maps are not drawn, and the factors
    // alone would be a rough metal and a white glow: the first keeps Blinn-Phong and the
    // second has no emissive.
    const Material* packed = named(*scene, "Packed");
    const Material* glow = named(*scene, "Glow");
    const Material* gloss = named(*scene, "Gloss");
    ASSERT_TRUE(packed && glow && gloss);
    EXPECT_EQ(packed->model, MaterialModel::BlinnPhong);
    EXPECT_EQ(glow->model, MaterialModel::MetallicRoughness);
    EXPECT_EQ(glow->emissive, glm::vec3(0.0f));
    EXPECT_FLOAT_EQ(glow->metallic, 0.0f);
    EXPECT_EQ(gloss->model, MaterialModel::BlinnPhong);
}

TEST(MetallicRoughness, GltfMapsAreReadWithTheirCoordinatesAndColourSpaces) {
    test::TempDir dir("mvr-pbr-maps");
    SceneLoadInfo info;
    auto scene = loadScene(test::writeMapsGltf(dir.path()), &info);
    ASSERT_TRUE(scene) << scene.status().message();
    auto texture = [&](int i) -> const Texture& { return scene->textures.at(std::size_t(i)); };
    const Material* full = named(*scene, "Full");
    ASSERT_TRUE(full);
    EXPECT_EQ(full->model, MaterialModel::MetallicRoughness);
    ASSERT_GE(full->metallicRoughnessTexture, 0);
    ASSERT_GE(full->occlusionTexture, 0);
    ASSERT_GE(full->emissiveTexture, 0);
    EXPECT_FALSE(texture(full->baseColorTexture).linear);
    EXPECT_TRUE(texture(full->metallicRoughnessTexture).linear);  // data: no sRGB decoding
    EXPECT_TRUE(texture(full->occlusionTexture).linear);
    EXPECT_FALSE(texture(full->emissiveTexture).linear);  // colour
    EXPECT_EQ(texture(full->metallicRoughnessTexture).image.at(0, 0).b, 255);
    EXPECT_FLOAT_EQ(full->occlusionStrength, 0.6f);
    EXPECT_EQ(full->emissive, glm::vec3(1.0f));  // the factor the texel multiplies
    // One image as colour and as data: two Textures.
    const Material* shared = named(*scene, "Shared");
    ASSERT_TRUE(shared && shared->baseColorTexture >= 0 && shared->occlusionTexture >= 0);
    EXPECT_NE(shared->baseColorTexture, shared->occlusionTexture);
    EXPECT_EQ(texture(shared->baseColorTexture).image.rgba,
              texture(shared->occlusionTexture).image.rgba);
    // Another transform than the base colour's: not drawn, said.
    const Material* moved = named(*scene, "Moved");
    ASSERT_TRUE(moved);
    EXPECT_GE(moved->baseColorTexture, 0);
    EXPECT_EQ(moved->occlusionTexture, -1);
    auto warned = [&](const std::string& a, const std::string& b) {
        return std::any_of(info.warnings.begin(), info.warnings.end(), [&](const std::string& w) {
            return w.find(a) != std::string::npos && w.find(b) != std::string::npos;
        });
    };
    EXPECT_TRUE(warned("material 'Moved': its occlusion texture reads other texture coordinates",
                       "not drawn"));
    // Set 1 from the first map on: the mesh holds set 1 (uv1), both maps drawn.
    const Material* second = named(*scene, "Second");
    ASSERT_TRUE(second);
    EXPECT_GE(second->metallicRoughnessTexture, 0);
    EXPECT_GE(second->emissiveTexture, 0);
    EXPECT_EQ(second->baseColorTexture, -1);
    for (const Instance& i : scene->instances) {
        if (i.material.name != "Second") continue;
        const Mesh& m = scene->meshes.at(std::size_t(i.mesh));
        ASSERT_EQ(m.texcoords.size(), 4u);
        for (const glm::vec2& t : m.texcoords) EXPECT_LE(std::max(t.x, t.y), 0.5f);
    }
    // A missing emission texture: a warning, and no white glow from the factor beside it.
    const Material* lost = named(*scene, "Lost");
    ASSERT_TRUE(lost);
    EXPECT_EQ(lost->emissiveTexture, -1);
    EXPECT_EQ(lost->emissive, glm::vec3(0.0f));
    EXPECT_TRUE(warned("texture 'gone.png': file not found", "the map is not drawn"));
    // Set 1 where the mesh's set 1 is its set 0: drawn; where they differ: not drawn, said.
    const Material* alike = named(*scene, "Alike");
    const Material* apart = named(*scene, "Apart");
    ASSERT_TRUE(alike && apart);
    EXPECT_GE(alike->occlusionTexture, 0);
    EXPECT_EQ(apart->occlusionTexture, -1);
    EXPECT_TRUE(warned("material 'Apart': its occlusion texture reads other texture coordinates",
                       "not drawn"));
    EXPECT_FALSE(warned("material 'Alike'", "not drawn"));
    // Normal maps: linear, with the scale; the file's tangents as written, else assimp's:
    // along +u (+x here), the bitangent cross(n, t) · w up the image (+y: the quad's v = 0 row
    // is at y = 1).
    EXPECT_TRUE(texture(full->normalTexture).linear);
    EXPECT_FLOAT_EQ(alike->normalScale, 0.5f);
    ASSERT_GE(alike->normalTexture, 0);
    for (const Instance& i : scene->instances) {
        const Mesh& m = scene->meshes.at(std::size_t(i.mesh));
        if (i.material.name == "Full") {
            // (optimizeMeshLocality may reorder the vertices: each tangent is one of the file's)
            ASSERT_EQ(m.tangents.size(), 4u);
            for (const glm::vec4& t : m.tangents) {
                EXPECT_TRUE(std::any_of(std::begin(test::kMapsTangents),
                                        std::end(test::kMapsTangents), [&](const float* w) {
                                            return glm::vec4(w[0], w[1], w[2], w[3]) == t;
                                        }))
                    << t.x << " " << t.y << " " << t.z << " " << t.w;
            }
        }
        if (i.material.name == "Alike") {
            ASSERT_EQ(m.tangents.size(), 4u);
            for (std::size_t v = 0; v < 4; ++v) {
                const glm::vec4& t = m.tangents[v];
                EXPECT_NEAR(t.x, 1.0f, 1e-5f);
                EXPECT_NEAR(std::abs(t.y) + std::abs(t.z), 0.0f, 1e-5f);
                const glm::vec3 b = t.w * glm::cross(m.normals[v], glm::vec3(t));
                EXPECT_NEAR(b.y, 1.0f, 1e-5f) << "vertex " << v;
            }
        }
    }
    // --strict makes it an error.
    SceneLoadInfo strict;
    strict.strict = true;
    auto refused = loadScene(dir.path() / "maps.gltf", &strict);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.status().message().find("gone.png"), std::string::npos);
}

TEST(MetallicRoughness, ObjKeepsBlinnPhong) {
    test::TempDir dir("mvr-pbr-obj");
    const auto path = dir.path() / "tri.obj";
    std::ofstream(path) << "# exported by another tool\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    auto scene = loadScene(path);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_FALSE(scene->instances.empty());
    for (const Instance& i : scene->instances)
        EXPECT_EQ(i.material.model, MaterialModel::BlinnPhong);
}

}  // namespace
}  // namespace mvr
