// glTF's metallic-roughness, occlusion and emissive maps in the soft backend (issue 39 item 1;
// lighting.h SurfaceMaps): a full-screen quad's colour under uniform maps against the values
// the glTF specification gives, computed here (occlusion = 1 + strength · (R − 1) on the
// ambient term; emissive × the sRGB-decoded texel; metallic × B and roughness × G, which must
// be the image of those factors without a map), and unified == multipass bit for bit on the
// mapped scene in every shading.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <cstring>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/core/lighting.h"
#include "mvr/raster/soft_backend.h"
#include "exactness.h"
#include "test_scenes.h"
#include "../support/test_scenes.h"

namespace mvr::raster {
namespace {

Texture uniformTexture(Rgba8 c, bool linear) {
    Texture t;
    t.name = "uniform";
    t.linear = linear;
    t.image = Image(4, 4, c);
    return t;
}

/// A full-screen quad (identity rig) with a metallic-roughness material: base colour `albedo`,
/// metallic 0, roughness 1, ambient `ambient`, no light unless `lit`.
Scene mapQuad(glm::vec3 albedo, float ambient, bool lit) {
    Scene scene = test::quadScene({-1, -1, 0.5f}, {1, 1, 0.5f});
    scene.meshes[0].texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    Material& m = scene.instances[0].material;
    m.model = MaterialModel::MetallicRoughness;
    m.albedo = albedo;
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    scene.lights.clear();
    if (lit) {
        Light l;
        l.towardLight = glm::normalize(glm::vec3(0.3f, 0.2f, 1.0f));
        l.color = glm::vec3(0.9f);
        scene.lights = {l};
    }
    scene.ambient = glm::vec3(ambient);
    return scene;
}

Rgba8 centre(Backend& backend, const Scene& scene, Shading shading, const char* method) {
    RenderSettings s;
    s.width = s.height = 32;
    s.shading = shading;
    auto out = backend.render(scene, test::identityRig(1), s, method);
    EXPECT_TRUE(out) << out.status().message();
    return out ? out->color[0].at(16, 16) : Rgba8{};
}

/// The IEC 61966-2-1 decoding, written out.
double srgbDecoded(int byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

TEST(SurfaceMaps, OcclusionDarkensTheAmbientTermByItsStrength) {
    auto backend = makeSoftBackend();
    for (const int r : {0, 64, 255}) {
        for (const float strength : {1.0f, 0.5f}) {
            Scene scene = mapQuad({0.8f, 0.6f, 0.4f}, 0.5f, false);
            scene.textures = {uniformTexture({std::uint8_t(r), 255, 255, 255}, true)};
            scene.instances[0].material.occlusionTexture = 0;
            scene.instances[0].material.occlusionStrength = strength;
            const double occlusion = 1.0 + strength * (r / 255.0 - 1.0);
            for (int mode = 0; mode < 3; ++mode) {
                const Rgba8 px = centre(*backend, scene, Shading(mode), "multipass");
                const std::uint8_t got[3] = {px.r, px.g, px.b};
                for (int c = 0; c < 3; ++c) {
                    const double want = scene.instances[0].material.albedo[c] * 0.5 * occlusion;
                    EXPECT_NEAR(got[c], want * 255.0, 0.6)
                        << "R " << r << " strength " << strength << " shading " << mode;
                }
            }
        }
    }
}

TEST(SurfaceMaps, EmissiveMapScalesTheEmissiveByTheDecodedTexel) {
    auto backend = makeSoftBackend();
    Scene scene = mapQuad(glm::vec3(0.5f), 0.0f, false);
    scene.textures = {uniformTexture({255, 128, 40, 255}, false)};
    scene.instances[0].material.emissiveTexture = 0;
    scene.instances[0].material.emissive = {0.5f, 1.0f, 2.0f};
    const double want[3] = {0.5 * srgbDecoded(255), 1.0 * srgbDecoded(128),
                            std::min(1.0, 2.0 * srgbDecoded(40))};
    for (int mode = 0; mode < 3; ++mode) {
        const Rgba8 px = centre(*backend, scene, Shading(mode), "multipass");
        const std::uint8_t got[3] = {px.r, px.g, px.b};
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], want[c] * 255.0, 0.6) << "channel " << c << " shading " << mode;
    }
    // Unlit ignores the maps: its base colour as it is.
    scene.instances[0].material.model = MaterialModel::Unlit;
    const Rgba8 unlit = centre(*backend, scene, Shading::Pixel, "multipass");
    EXPECT_EQ(unlit.r, 128);
    EXPECT_EQ(unlit.g, 128);
}

TEST(SurfaceMaps, MetallicRoughnessMapIsItsFactorsPerPixel) {
    auto backend = makeSoftBackend();
    for (const Rgba8 texel : {Rgba8{0, 128, 255, 255}, Rgba8{0, 255, 0, 255},
                              Rgba8{0, 40, 200, 255}}) {
        Scene mapped = mapQuad({0.9f, 0.6f, 0.3f}, 0.05f, true);
        mapped.textures = {uniformTexture(texel, true)};
        Material& m = mapped.instances[0].material;
        m.metallic = 1.0f, m.roughness = 1.0f;
        m.metallicRoughnessTexture = 0;
        // The same quad without the map, its factors the texel's (× 1): B metallic, G roughness.
        Scene factors = mapped;
        Material& f = factors.instances[0].material;
        f.metallicRoughnessTexture = -1;
        f.metallic = float(texel.b) / 255.0f;
        f.roughness = float(texel.g) / 255.0f;
        for (const char* method : {"multipass", "unified"}) {
            const Rgba8 a = centre(*backend, mapped, Shading::Pixel, method);
            const Rgba8 b = centre(*backend, factors, Shading::Pixel, method);
            EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0)
                << "texel G " << int(texel.g) << " B " << int(texel.b) << " " << method << ": "
                << int(a.r) << "," << int(a.g) << "," << int(a.b) << " vs " << int(b.r) << ","
                << int(b.g) << "," << int(b.b);
        }
        // Per vertex the map is not applied (lighting.h): the factors alone.
        Scene alone = mapped;
        alone.instances[0].material.metallicRoughnessTexture = -1;
        const Rgba8 v = centre(*backend, mapped, Shading::Vertex, "multipass");
        const Rgba8 w = centre(*backend, alone, Shading::Vertex, "multipass");
        EXPECT_EQ(std::memcmp(&v, &w, sizeof v), 0);
    }
    // The map changes the image (a glossy metal is not a rough dielectric).
    Scene a = mapQuad({0.9f, 0.6f, 0.3f}, 0.05f, true), b = a;
    a.textures = b.textures = {uniformTexture({0, 40, 255, 255}, true)};
    a.instances[0].material.metallic = b.instances[0].material.metallic = 1.0f;
    a.instances[0].material.metallicRoughnessTexture = 0;
    const Rgba8 pa = centre(*backend, a, Shading::Pixel, "multipass");
    const Rgba8 pb = centre(*backend, b, Shading::Pixel, "multipass");
    EXPECT_NE(std::memcmp(&pa, &pb, sizeof pa), 0);
}

/// The normal a normal map's texel gives a surface whose normal, tangent and bitangent are the
/// unit vectors n, t, b: glTF's tangent-space normal (2·rgb − 1, x and y × scale) in that frame,
/// written out in double.
glm::dvec3 mappedNormal(Rgba8 texel, double scale, glm::dvec3 t, glm::dvec3 b, glm::dvec3 n) {
    const glm::dvec3 c((2.0 * texel.r / 255.0 - 1.0) * scale,
                       (2.0 * texel.g / 255.0 - 1.0) * scale, 2.0 * texel.b / 255.0 - 1.0);
    return glm::normalize(t * c.x + b * c.y + n * c.z);
}

TEST(SurfaceMaps, NormalMapBendsTheNormalInTheTangentFrame) {
    auto backend = makeSoftBackend();
    const glm::dvec3 light = glm::normalize(glm::dvec3(0.5, 0.4, 0.77));
    for (const Rgba8 texel : {Rgba8{255, 128, 128, 255}, Rgba8{128, 255, 128, 255},
                              Rgba8{40, 90, 200, 255}, Rgba8{128, 128, 255, 255}}) {
        for (const bool mirrored : {false, true}) {
            // A full-screen quad facing +z, u along +x and the image's top at +y (tangent +x,
            // handedness +1: bitangent cross(n, t) = +y); mirrored in x, u runs along −x.
            Scene scene = test::quadScene({-1, -1, 0.5f}, {1, 1, 0.5f});
            Mesh& mesh = scene.meshes[0];
            mesh.texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
            mesh.tangents.assign(4, glm::vec4(1, 0, 0, 1));
            Material& m = scene.instances[0].material;
            m.albedo = glm::vec3(1.0f);
            m.specular = 0.0f;
            m.normalScale = 0.8f;
            m.normalTexture = 0;
            if (mirrored)
                scene.instances[0].worldFromModel = glm::scale(glm::mat4(1.0f), {-1, 1, 1});
            scene.textures = {uniformTexture(texel, true)};
            Light l;
            l.towardLight = glm::vec3(light);
            scene.lights = {l};
            scene.ambient = glm::vec3(0.0f);
            const glm::dvec3 n = mappedNormal(texel, 0.8, {mirrored ? -1.0 : 1.0, 0, 0}, {0, 1, 0},
                                              {0, 0, 1});
            const double want = std::max(0.0, glm::dot(n, light)) * 255.0;
            for (const char* method : {"multipass", "unified"}) {
                const Rgba8 px = centre(*backend, scene, Shading::Pixel, method);
                EXPECT_NEAR(px.r, want, 0.6) << "texel " << int(texel.r) << "," << int(texel.g)
                                             << "," << int(texel.b) << " mirrored " << mirrored
                                             << " " << method;
            }
            // Without tangents, or per vertex, the surface's own normal.
            const double flat = glm::dot(glm::dvec3(0, 0, 1), light) * 255.0;
            EXPECT_NEAR(centre(*backend, scene, Shading::Vertex, "multipass").r, flat, 0.6);
            scene.meshes[0].tangents.clear();
            EXPECT_NEAR(centre(*backend, scene, Shading::Pixel, "multipass").r, flat, 0.6);
        }
    }
}

TEST(SurfaceMaps, UnifiedEqualsMultipassOnTheMappedScene) {
    auto backend = makeSoftBackend();
    test::expectUnifiedEqualsMultipass(*backend, mvr::test::mappedScene(),
                                       {{2, 1}, {5, 1}, {16, 1}, {45, 1}, {3, 2}, {4, 3}}, 72, 54,
                                       true);
}

}  // namespace
}  // namespace mvr::raster
