#include "mvr/core/billboards.h"

#include <random>

namespace mvr {

void appendBillboards(Scene& scene, std::span<const Billboard> billboards, const Camera& camera,
                      glm::vec3 albedo) {
    if (billboards.empty()) return;
    // The centre camera's axes in world space (lookAt's rows).
    const glm::mat4 v = camera.viewFromWorld();
    const glm::vec3 right(v[0][0], v[1][0], v[2][0]);
    const glm::vec3 up(v[0][1], v[1][1], v[2][1]);
    const glm::vec3 back(v[0][2], v[1][2], v[2][2]);  // toward the camera
    Mesh m;
    m.name = "billboards";
    for (const Billboard& b : billboards) {
        const float h = 0.5f * b.size;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const glm::vec3 corners[4] = {b.center - right * h - up * h, b.center + right * h - up * h,
                                      b.center + right * h + up * h, b.center - right * h + up * h};
        const glm::vec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(corners[k]);
            m.normals.push_back(back);
            m.texcoords.push_back(uv[k]);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    Instance inst;
    inst.mesh = static_cast<int>(scene.meshes.size());
    inst.material = Material(albedo, 0.0f, 1.0f);
    inst.material.doubleSided = true;
    inst.material.name = "billboards";
    if (!scene.textures.empty()) inst.material.baseColorTexture = 0;
    scene.meshes.push_back(std::move(m));
    scene.instances.push_back(inst);
}

std::vector<Billboard> scatterBillboards(const Bounds& bounds, int count, float size,
                                         std::uint32_t seed) {
    std::vector<Billboard> out;
    if (bounds.empty() || count <= 0) return out;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    out.reserve(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const glm::vec3 t(u(rng), u(rng), u(rng));
        out.push_back({bounds.min + t * (bounds.max - bounds.min), size});
    }
    return out;
}

}  // namespace mvr
