// tests/support/test_scenes.h — the scenes, rigs and image measures the cross-backend tests
// share (the conformance suite here, tests/gl through gl_test_util.h). Backend-neutral: core
// headers only. Models come from MVR_SHARED_DIR/models (ctest sets it; the build's
// MVR_SHARED_DIR otherwise).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/core/environment.h"
#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/io/mesh_io.h"
#include "mvr_test_support.h"

namespace mvr::test {

// sharedDir(), modelsDir(): tests/support/mvr_test_support.h

inline std::filesystem::path modelPath(const std::string& file) {
    return sharedDir() / "models" / file;
}

/// The procedural default scene (no files needed): spheres, torus, boxes, ground.
inline const Scene& defaultScene() {
    static const Scene s = makeDefaultScene();
    return s;
}

/// Issue 39: `scene` with glTF metallic-roughness materials (lighting.h): instance i has
/// metallic (i mod 3) / 2 and roughness 0.2 + 0.25 · (i mod 4), the second a faint emissive, the
/// fourth unlit; base colours as they were. Every shading path of the model, glossy to rough,
/// dielectric to metal.
inline Scene withMetallicRoughness(Scene s) {
    for (std::size_t i = 0; i < s.instances.size(); ++i) {
        Material& m = s.instances[i].material;
        m.model = i == 3 ? MaterialModel::Unlit : MaterialModel::MetallicRoughness;
        m.metallic = float(i % 3) * 0.5f;
        m.roughness = 0.2f + 0.25f * float(i % 4);
        if (i == 1) m.emissive = glm::vec3(0.15f, 0.05f, 0.0f);
    }
    return s;
}
/// `scene` tone mapped with `t` under its lights made `gain` times brighter (issue 39 item 2).
inline Scene toneMapped(Scene s, Tonemap t, float gain) {
    for (Light& l : s.lights) l.color *= gain;
    s.tonemap = t;
    return s;
}
/// withMetallicRoughness(the default scene) with a fourth light, a point light with a range,
/// so that the model's point-light path is compared across backends too.
inline const Scene& pbrScene() {
    static const Scene s = [] {
        Scene p = withMetallicRoughness(makeDefaultScene());
        Light point;
        point.type = LightType::Point;
        point.position = glm::vec3(1.5f, 2.0f, 2.5f);
        point.color = glm::vec3(4.0f, 3.5f, 3.0f);
        point.range = 12.0f;
        if (p.lights.size() < std::size_t(kMaxLights)) p.lights.push_back(point);
        return p;
    }();
    return s;
}

/// Every mesh with texture coordinates given tangents (Mesh::tangents: along +u, handedness
/// toward image-up), accumulated per vertex from its triangles' uv gradients (Lengyel's
/// method), as a test fixture: files get theirs from the file or assimp.
inline Scene withTangents(Scene s) {
    for (Mesh& m : s.meshes) {
        if (m.texcoords.size() != m.positions.size()) continue;
        std::vector<glm::vec3> t(m.positions.size(), glm::vec3(0.0f)), b = t;
        for (std::size_t k = 0; k + 2 < m.indices.size(); k += 3) {
            const std::uint32_t i0 = m.indices[k], i1 = m.indices[k + 1], i2 = m.indices[k + 2];
            const glm::vec3 e1 = m.positions[i1] - m.positions[i0];
            const glm::vec3 e2 = m.positions[i2] - m.positions[i0];
            const glm::vec2 d1 = m.texcoords[i1] - m.texcoords[i0];
            const glm::vec2 d2 = m.texcoords[i2] - m.texcoords[i0];
            const float det = d1.x * d2.y - d2.x * d1.y;
            if (std::abs(det) < 1e-12f) continue;
            // texcoords are v down: image-up is −v
            const glm::vec3 du = (e1 * d2.y - e2 * d1.y) / det;
            const glm::vec3 dv = (e2 * d1.x - e1 * d2.x) / det;
            for (std::uint32_t i : {i0, i1, i2}) t[i] += du, b[i] -= dv;
        }
        m.tangents.resize(m.positions.size());
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            const glm::vec3 n = m.normals[i];
            glm::vec3 u = t[i] - n * glm::dot(n, t[i]);
            const float len = glm::length(u);
            u = len > 1e-12f ? u / len : glm::vec3(1.0f, 0.0f, 0.0f);
            const float w = glm::dot(glm::cross(n, u), b[i]) < 0.0f ? -1.0f : 1.0f;
            m.tangents[i] = glm::vec4(u, w);
        }
    }
    return s;
}

/// Issue 39: withMetallicRoughness(makeTexturedScene()) with glTF's other texture slots,
/// generated: a metallic-roughness map (linear; G roughness and B metallic in 8×8 checks of
/// 0.1 / 1.0 and 1.0 / 0.0, so rough and glossy, metal and dielectric neighbours), an occlusion
/// map (linear R: dark rings, strength 0.8) and an emissive map (sRGB: orange stripes under an
/// emissive factor of 0.6) and a normal map (linear: a grid of round bumps). Instance i has the
/// metallic-roughness map when i is even, the occlusion map when i mod 3 ≠ 2, the emissive map
/// when i is 1 or 4, the normal map (scale 0.9) when i < 3 or i = 5; the unlit one (3) keeps
/// its maps, which unlit ignores; instance 5 has the maps and no base colour texture. Every
/// mesh gets tangents (withTangents).
inline Scene withSurfaceMaps(Scene s) {
    const int first = int(s.textures.size());
    auto add = [&](int size, bool linear, const std::string& name, auto texel) {
        Texture t;
        t.name = name;
        t.linear = linear;
        t.image = Image(size, size);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) t.image.set(x, y, texel(x, y, size));
        s.textures.push_back(std::move(t));
    };
    add(64, true, "metallic-roughness (generated)", [](int x, int y, int n) {
        const bool a = ((x * 8 / n) + (y * 8 / n)) & 1;
        return Rgba8{0, std::uint8_t(a ? 26 : 255), std::uint8_t(a ? 255 : 0), 255};
    });
    add(64, true, "occlusion (generated)", [](int x, int y, int n) {
        const float dx = float(x) / float(n) - 0.5f, dy = float(y) / float(n) - 0.5f;
        const float r = std::sqrt(dx * dx + dy * dy);
        const float occ = 0.5f + 0.5f * std::cos(r * 40.0f);
        return Rgba8{std::uint8_t(occ * 255.0f + 0.5f), 255, 255, 255};
    });
    add(32, false, "emissive (generated)", [](int x, int y, int n) {
        const bool on = ((x + y) * 6 / n) % 2 == 0;
        return on ? Rgba8{255, 150, 40, 255} : Rgba8{0, 0, 0, 255};
    });
    add(64, true, "bumps (generated)", [](int x, int y, int n) {
        // 4 × 4 round bumps, smooth: over each cell the height 0.5 (1 + cos(π r / 0.9)) inside
        // r < 0.9 (cell units), flat outside; the normal from its slope (image-up is +y). No
        // crease, so the GPUs' per-quad level of detail is not measured as a shading error.
        const int cell = n / 4;
        const float cx = (float(x % cell) + 0.5f) / float(cell) * 2.0f - 1.0f;
        const float cy = (float(y % cell) + 0.5f) / float(cell) * 2.0f - 1.0f;
        const float r = std::sqrt(cx * cx + cy * cy);
        glm::vec3 nrm(0.0f, 0.0f, 1.0f);
        if (r > 0.0f && r < 0.9f) {
            const float slope = 0.35f * 0.5f * 3.14159265f / 0.9f * std::sin(3.14159265f * r / 0.9f);
            nrm = glm::normalize(glm::vec3(slope * cx / r, -slope * cy / r, 1.0f));
        }
        auto enc = [](float v) { return std::uint8_t(std::lround((v * 0.5f + 0.5f) * 255.0f)); };
        return Rgba8{enc(nrm.x), enc(nrm.y), enc(nrm.z), 255};
    });
    for (std::size_t i = 0; i < s.instances.size(); ++i) {
        Material& m = s.instances[i].material;
        if (i % 2 == 0) m.metallicRoughnessTexture = first;
        if (i % 3 != 2) {
            m.occlusionTexture = first + 1;
            m.occlusionStrength = 0.8f;
        }
        if (i == 1 || i == 4) {
            m.emissiveTexture = first + 2;
            m.emissive = glm::vec3(0.6f);
        }
        if (i < 3 || i == 5) {
            m.normalTexture = first + 3;
            m.normalScale = 0.9f;
        }
        if (i == 5) m.baseColorTexture = -1;
    }
    return withTangents(std::move(s));
}
inline const Scene& mappedScene() {
    static const Scene s = withSurfaceMaps(withMetallicRoughness(makeTexturedScene()));
    return s;
}

/// A synthetic environment map for image lighting (issue 39 item 2; environment.h), 128 × 64:
/// a blue sky brightening to the horizon, a warm ground, and a small bright sun up to the
/// right of the default view, so diffuse, glossy and mirror reflections all show structure.
inline RadianceMap testRadianceMap() {
    RadianceMap m;
    m.width = 128, m.height = 64, m.name = "test sky";
    m.texels.resize(std::size_t(m.width * m.height));
    const glm::vec3 sun = glm::normalize(glm::vec3(0.5f, 0.7f, 0.4f));
    for (int j = 0; j < m.height; ++j) {
        for (int i = 0; i < m.width; ++i) {
            const glm::vec3 d = equirectDirection((float(i) + 0.5f) / float(m.width),
                                                  (float(j) + 0.5f) / float(m.height));
            glm::vec3 c = d.y > 0.0f ? glm::mix(glm::vec3(0.9f, 0.95f, 1.0f),
                                                glm::vec3(0.25f, 0.45f, 0.9f), d.y)
                                     : glm::vec3(0.45f, 0.3f, 0.2f) * (1.0f + 0.3f * d.x);
            if (glm::dot(d, sun) > 0.985f) c = glm::vec3(12.0f, 11.0f, 9.0f);
            m.texels[std::size_t(j * m.width + i)] = c;
        }
    }
    return m;
}
inline std::shared_ptr<const Environment> testEnvironment() {
    static const auto env = std::make_shared<const Environment>(buildEnvironment(testRadianceMap()));
    return env;
}
/// `s` lit by testEnvironment() in place of its ambient (as `--environment` does).
inline Scene withEnvironment(Scene s) {
    s.environment = testEnvironment();
    s.ambient = glm::vec3(0.0f);
    return s;
}

/// One model from shared/models laid out as `mvr render MODEL` does (makeGridScene, 1 copy);
/// nullopt when the file cannot be loaded.
/// The default scene with vertex colours (Mesh::colors) on every mesh, a smooth function of
/// the position, alpha 1; white base colours, so the colours show as they are.
inline const Scene& coloredScene() {
    static const Scene scene = [] {
        Scene s = defaultScene();
        for (Mesh& m : s.meshes) {
            m.colors.clear();
            for (const glm::vec3& p : m.positions) {
                m.colors.emplace_back(0.5f + 0.5f * std::sin(3.0f * p.x),
                                      0.5f + 0.5f * std::cos(2.0f * p.y + p.z),
                                      0.5f + 0.5f * std::sin(2.5f * p.z - p.x), 1.0f);
            }
        }
        for (Instance& i : s.instances) i.material.albedo = glm::vec3(1.0f);
        return s;
    }();
    return scene;
}

inline std::optional<Scene> modelScene(const std::string& file) {
    auto m = loadMesh(modelPath(file));
    if (!m) return std::nullopt;
    std::vector<Mesh> meshes;
    meshes.push_back(std::move(m).value());
    return makeGridScene(std::move(meshes), 1);
}

/// Suzanne from shared/models, or nullptr when the file is not there.
inline const Scene* suzanneScene() {
    static const std::unique_ptr<Scene> s = []() -> std::unique_ptr<Scene> {
        auto scene = modelScene("suzanne.obj");
        return scene ? std::make_unique<Scene>(std::move(*scene)) : nullptr;
    }();
    return s.get();
}

/// Suzanne under a mirrored, non-uniformly scaled, rotated transform: flat normals computed
/// from world-space corners and from cofactor-mapped model-space cross products must agree
/// (cof(M)·(a×b) = (Ma)×(Mb), sign included, where the inverse transpose alone flips under a
/// mirror). nullptr when suzanne.obj is not there.
inline const Scene* mirroredSuzanneScene() {
    static const std::unique_ptr<Scene> s = []() -> std::unique_ptr<Scene> {
        const Scene* suz = suzanneScene();
        if (!suz) return nullptr;
        auto scene = std::make_unique<Scene>(*suz);
        glm::mat4 xf = glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0.3f, 1.0f, 0.2f));
        xf = glm::scale(xf, glm::vec3(-1.3f, 0.8f, 1.1f));
        scene->instances[0].worldFromModel = xf * scene->instances[0].worldFromModel;
        return scene;
    }();
    return s.get();
}

/// Three convex octahedra at different depths, listed front to back (so that a back-to-front
/// sort has work to do): with back-face culling, painter's order between objects is exact.
inline const Scene& octahedraScene() {
    static const Scene s = [] {
        Scene scene;
        Mesh octahedron;
        octahedron.positions = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
        octahedron.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                              2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
        computeSmoothNormals(octahedron);
        scene.meshes.push_back(octahedron);
        for (int i = 0; i < 3; ++i) {
            const glm::mat4 xf = glm::translate(
                glm::mat4(1.0f), glm::vec3(0.6f * i - 0.6f, 0.1f * i, 1.5f - 1.5f * i));
            scene.instances.push_back(
                {0, xf, Material{{0.3f + 0.3f * i, 0.5f, 0.9f - 0.3f * i}, 0.3f, 16.0f}});
        }
        scene.lights = defaultLights();
        return scene;
    }();
    return s;
}

/// A scene shaped like Khronos's 2CylinderEngine sample (82 nodes, 34 primitives and materials):
/// 40 distinct meshes (more than the gl backend keeps on the GPU between renders, so a render
/// that evicted its own meshes would draw deleted vertex arrays), a material each, 84
/// instances scattered in depth on a 12 × 7 grid, each mesh scaled to about a unit.
inline const Scene& engineScene() {
    static const Scene s = [] {
        const Scene& d = defaultScene();
        Scene e;
        e.lights = d.lights;
        e.ambient = d.ambient;
        constexpr int kMeshes = 40, kColumns = 12, kRows = 7;
        for (int i = 0; i < kMeshes; ++i) {
            Mesh m = d.meshes[static_cast<std::size_t>(i) % d.meshes.size()];
            const Bounds b = m.bounds();
            const glm::vec3 size = b.max - b.min;
            // Each a little different in size, so that no two meshes have the same contents.
            const float k =
                (1.0f + 0.01f * static_cast<float>(i)) / std::max({size.x, size.y, size.z, 1e-6f});
            for (glm::vec3& p : m.positions) p = (p - b.center()) * k;
            m.name = "part " + std::to_string(i);
            e.meshes.push_back(std::move(m));
        }
        for (int i = 0; i < kColumns * kRows; ++i) {
            const int c = i % kColumns, r = i / kColumns;
            const glm::vec3 at(1.2f * (c - 0.5f * (kColumns - 1)), 1.2f * (r - 0.5f * (kRows - 1)),
                               -0.7f * static_cast<float>((i * 7) % 5));
            glm::mat4 xf = glm::translate(glm::mat4(1.0f), at);
            xf = glm::rotate(xf, 0.4f * static_cast<float>(i), glm::vec3(0.3f, 1.0f, 0.1f));
            Material mat{{0.2f + 0.6f * static_cast<float>(i % 5) / 4.0f,
                          0.2f + 0.6f * static_cast<float>(i % 7) / 6.0f,
                          0.2f + 0.6f * static_cast<float>(i % 3) / 2.0f},
                         0.3f,
                         24.0f};
            mat.name = "material " + std::to_string(i % 34);
            e.instances.push_back({i % kMeshes, xf, mat});
        }
        return e;
    }();
    return s;
}

/// A camera framing `scene`, looking down −Z at its centre (closer than frameScene(), so that
/// the pictures are full).
inline Camera cameraFor(const Scene& scene, float aspect) {
    const Bounds b = scene.bounds();
    Camera c;
    const float r = b.radius();
    c.target = b.center();
    c.position = b.center() + glm::vec3(0.0f, 0.25f * r, 2.6f * r);
    c.aspect = aspect;
    c.near = 0.05f * r;
    c.far = 10.0f * r;
    return c;
}

/// An off-axis rig of columns × rows views with exaggerated spacing (so the eyes really differ),
/// `spread` times wider still where asked.
inline Rig rigFor(const Scene& scene, int columns, int rows, float aspect = 4.0f / 3.0f,
                  float spread = 1.0f) {
    const Camera cam = cameraFor(scene, aspect);
    RigParams p;
    p.columns = columns;
    p.rows = rows;
    const float dist = glm::length(cam.position - cam.target);
    p.convergence = dist;
    p.interaxial = 0.06f * dist * spread;
    p.interaxialY = 0.03f * dist * spread;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

/// Fraction of depth pixels that differ by more than `eps`; the largest difference in *maxDiff.
inline double depthMismatch(const DepthImage& a, const DepthImage& b, float eps, float* maxDiff) {
    if (a.width != b.width || a.height != b.height) return 1.0;
    long bad = 0;
    float worst = 0.0f;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const float d = std::abs(a.depth[i] - b.depth[i]);
        worst = std::max(worst, d);
        if (d > eps) ++bad;
    }
    if (maxDiff) *maxDiff = worst;
    return static_cast<double>(bad) / static_cast<double>(a.depth.size());
}

}  // namespace mvr::test
