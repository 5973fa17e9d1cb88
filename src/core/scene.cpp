#include "mvr/core/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

namespace mvr {

std::size_t Scene::triangleCount() const {
    std::size_t n = 0;
    for (const Instance& inst : instances) {
        if (inst.mesh >= 0 && std::size_t(inst.mesh) < meshes.size())
            n += meshes[inst.mesh].triangleCount();
    }
    return n;
}

Bounds Scene::bounds() const {
    Bounds b;
    for (const Instance& inst : instances) {
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= meshes.size()) continue;
        const Bounds mb = meshes[inst.mesh].bounds();
        if (mb.empty()) continue;
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner((c & 1) ? mb.max.x : mb.min.x, (c & 2) ? mb.max.y : mb.min.y,
                                   (c & 4) ? mb.max.z : mb.min.z);
            b.extend(glm::vec3(inst.worldFromModel * glm::vec4(corner, 1.0f)));
        }
    }
    return b;
}

std::vector<DirectionalLight> defaultLights() {
    return {
        {glm::normalize(glm::vec3(0.4f, 0.8f, 0.6f)), glm::vec3(0.75f)},   // key
        {glm::normalize(glm::vec3(-0.7f, 0.2f, 0.4f)), glm::vec3(0.30f)},  // fill
        {glm::normalize(glm::vec3(0.0f, 0.3f, -1.0f)), glm::vec3(0.25f)},  // rim
    };
}

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

Mesh makeSphere(int slices, int stacks) {
    Mesh m;
    m.name = "sphere";
    for (int j = 0; j <= stacks; ++j) {
        const float v = float(j) / stacks, phi = v * kPi;
        for (int i = 0; i <= slices; ++i) {
            const float u = float(i) / slices, theta = u * 2.0f * kPi;
            const glm::vec3 n(std::sin(phi) * std::cos(theta), std::cos(phi),
                              -std::sin(phi) * std::sin(theta));
            m.positions.push_back(n);
            m.normals.push_back(n);
            m.texcoords.emplace_back(u, 1.0f - v);
        }
    }
    for (int j = 0; j < stacks; ++j) {
        for (int i = 0; i < slices; ++i) {
            const std::uint32_t a = j * (slices + 1) + i, b = a + slices + 1;
            if (j != 0) m.indices.insert(m.indices.end(), {a, b, a + 1});
            if (j != stacks - 1) m.indices.insert(m.indices.end(), {a + 1, b, b + 1});
        }
    }
    return m;
}

Mesh makeTorus(float major, float minor, int rings, int sides) {
    Mesh m;
    m.name = "torus";
    for (int j = 0; j <= rings; ++j) {
        const float u = float(j) / rings * 2.0f * kPi;
        const glm::vec3 center(major * std::cos(u), 0.0f, -major * std::sin(u));
        for (int i = 0; i <= sides; ++i) {
            const float v = float(i) / sides * 2.0f * kPi;
            const glm::vec3 n(std::cos(v) * std::cos(u), std::sin(v), -std::cos(v) * std::sin(u));
            m.positions.push_back(center + minor * n);
            m.normals.push_back(n);
            m.texcoords.emplace_back(float(j) / rings, float(i) / sides);
        }
    }
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < sides; ++i) {
            const std::uint32_t a = j * (sides + 1) + i, b = a + sides + 1;
            m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    }
    return m;
}

Mesh makeBox() {
    Mesh m;
    m.name = "box";
    // Per face: its normal n and two axes with cross(u, v) = n, so the corners below run
    // counter-clockwise seen from outside.
    struct Face {
        glm::vec3 n, u, v;
    };
    const Face faces[6] = {{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                           {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                           {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}}};
    const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (const Face& f : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec2& c : corners) {
            m.positions.push_back(f.n + c.x * f.u + c.y * f.v);
            m.normals.push_back(f.n);
            m.texcoords.emplace_back(c * 0.5f + 0.5f);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

Mesh makeGroundPlane(int cells) {
    Mesh m;
    m.name = "ground";
    for (int j = 0; j <= cells; ++j) {
        for (int i = 0; i <= cells; ++i) {
            const float x = -1.0f + 2.0f * i / cells, z = -1.0f + 2.0f * j / cells;
            m.positions.emplace_back(x, 0.0f, z);
            m.normals.emplace_back(0.0f, 1.0f, 0.0f);
            m.texcoords.emplace_back(float(i) / cells, float(j) / cells);
        }
    }
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const std::uint32_t a = j * (cells + 1) + i, b = a + cells + 1;
            m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    }
    return m;
}

glm::mat4 placed(glm::vec3 at, float scale, float yawDegrees = 0.0f,
                 glm::vec3 stretch = glm::vec3(1.0f)) {
    glm::mat4 m = glm::translate(glm::mat4(1.0f), at);
    m = glm::rotate(m, glm::radians(yawDegrees), glm::vec3(0, 1, 0));
    return glm::scale(m, scale * stretch);
}

}  // namespace

Scene makeDefaultScene() {
    Scene s;
    s.meshes = {makeGroundPlane(16), makeSphere(48, 24), makeTorus(1.0f, 0.3f, 48, 24), makeBox()};
    s.lights = defaultLights();
    s.background = glm::vec3(0.06f, 0.07f, 0.1f);
    s.viewpoint = SceneViewpoint{{0.0f, 1.2f, 6.0f}, {0.0f, -0.2f, 0.0f}};
    auto add = [&](int mesh, glm::mat4 xf, glm::vec3 albedo) {
        s.instances.push_back({mesh, xf, Material{albedo, 0.35f, 48.0f}});
    };
    add(0, placed({0, -1.0f, -1.0f}, 1.0f, 0, {6.0f, 1.0f, 6.0f}), {0.55f, 0.55f, 0.6f});
    add(1, placed({0.0f, -0.1f, 0.0f}, 0.9f), {0.85f, 0.25f, 0.2f});  // on the convergence plane
    add(2, placed({-1.9f, -0.4f, -2.2f}, 0.8f, 30.0f), {0.2f, 0.7f, 0.3f});  // behind
    add(3, placed({1.8f, -0.55f, -1.5f}, 0.45f, 25.0f), {0.25f, 0.4f, 0.9f});
    add(1, placed({0.9f, -0.55f, 1.6f}, 0.42f), {0.95f, 0.8f, 0.2f});  // in front
    add(3, placed({-1.1f, -0.7f, 1.4f}, 0.3f, -20.0f), {0.8f, 0.3f, 0.8f});
    return s;
}

Texture makeCheckerTexture(int size, int checks, Rgba8 a, Rgba8 b, const std::string& name) {
    Texture t;
    t.name = name;
    t.image = Image(size, size);
    const int cell = std::max(1, size / std::max(1, checks));
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const int cx = x / cell, cy = y / cell;
            Rgba8 c = ((cx + cy) & 1) ? b : a;
            // A border on the square's top and left edges, red-ish top, blue-ish left: the
            // image's orientation (and a flipped v) is visible in renders.
            if (y % cell < std::max(1, cell / 16)) c = {230, 60, 40, 255};
            if (x % cell < std::max(1, cell / 16)) c = {40, 80, 230, 255};
            t.image.set(x, y, c);
        }
    }
    return t;
}

Scene makeTexturedScene() {
    Scene s = makeDefaultScene();
    s.textures.push_back(
        makeCheckerTexture(256, 8, {235, 235, 225, 255}, {60, 60, 70, 255}, "checker (generated)"));
    s.textures.push_back(
        makeCheckerTexture(128, 4, {250, 200, 60, 255}, {40, 140, 90, 255}, "tiles (generated)"));
    // Ground: the texture repeats 4 times across (texcoords scaled), minified toward the back.
    for (glm::vec2& uv : s.meshes[0].texcoords) uv *= 4.0f;
    for (std::size_t i = 0; i < s.instances.size(); ++i) {
        Material& m = s.instances[i].material;
        m.albedo = glm::vec3(1.0f);
        m.baseColorTexture = (i == 0 || i == 2) ? 0 : 1;
        m.name = fmt::format("textured {}", i);
    }
    return s;
}

Scene makeGridScene(std::vector<Mesh> meshes, int copies) {
    Scene s;
    s.lights = defaultLights();
    Bounds model;
    for (const Mesh& m : meshes) model.extend(m.bounds());
    s.meshes = std::move(meshes);
    if (copies < 1 || model.empty()) return s;
    const glm::vec3 size = model.max - model.min;
    const float spacing = std::max({size.x, size.y, 1e-6f}) * 1.1f;
    const int columns = static_cast<int>(std::ceil(std::sqrt(double(copies))));
    const int rows = (copies + columns - 1) / columns;
    static const glm::vec3 kPalette[] = {
        {0.85f, 0.75f, 0.6f}, {0.6f, 0.75f, 0.9f}, {0.9f, 0.55f, 0.5f},
        {0.6f, 0.85f, 0.6f},  {0.85f, 0.8f, 0.4f}, {0.75f, 0.6f, 0.9f},
        {0.5f, 0.8f, 0.8f},   {0.9f, 0.7f, 0.8f},  {0.7f, 0.7f, 0.7f}};
    for (int k = 0; k < copies; ++k) {
        const int col = k % columns, row = k / columns;
        const glm::vec3 offset((col - (columns - 1) * 0.5f) * spacing,
                               ((rows - 1) * 0.5f - row) * spacing, 0.0f);
        const glm::mat4 xf = glm::translate(glm::mat4(1.0f), offset - model.center());
        for (int m = 0; m < int(s.meshes.size()); ++m) {
            // A mesh with vertex colours shows them (white base colour), not the palette's.
            const glm::vec3 albedo =
                s.meshes[std::size_t(m)].colors.empty() ? kPalette[k % 9] : glm::vec3(1.0f);
            s.instances.push_back({m, xf, Material{albedo, 0.3f, 32.0f}});
        }
    }
    return s;
}

Status validateScene(const Scene& scene) {
    if (scene.instances.empty()) return inputError("scene has nothing to draw (no mesh instances)");
    if (scene.lights.size() > std::size_t(kMaxLights)) {
        return usageError(
            fmt::format("scene has {} lights (at most {})", scene.lights.size(), kMaxLights));
    }
    for (const Instance& inst : scene.instances) {
        if (inst.mesh < 0 || std::size_t(inst.mesh) >= scene.meshes.size()) {
            return inputError(fmt::format("scene instance refers to mesh {} of {}", inst.mesh,
                                          scene.meshes.size()));
        }
    }
    for (const Mesh& m : scene.meshes) {
        if (Status st = validateMesh(m, fmt::format("mesh '{}'", m.name)); !st) return st;
    }
    for (const Instance& inst : scene.instances) {
        const Material& m = inst.material;
        for (const int t : {m.baseColorTexture, m.metallicRoughnessTexture, m.occlusionTexture,
                            m.emissiveTexture, m.normalTexture}) {
            if (t < 0) continue;
            if (std::size_t(t) >= scene.textures.size()) {
                return inputError(fmt::format("material '{}' refers to texture {} of {}", m.name,
                                              t, scene.textures.size()));
            }
            if (scene.textures[t].image.empty()) {
                return inputError(fmt::format("texture '{}' of material '{}' is empty",
                                              scene.textures[t].name, m.name));
            }
            if (scene.meshes[inst.mesh].texcoords.size() !=
                scene.meshes[inst.mesh].positions.size()) {
                return inputError(
                    fmt::format("mesh '{}' has a texture (material '{}') but no texture "
                                "coordinates",
                                scene.meshes[inst.mesh].name, m.name));
            }
        }
    }
    return {};
}

}  // namespace mvr
