// village_scene.cpp — adelson1991's village as an mvr::Scene (`mvr render --scene village`).
#include <map>
#include <tuple>

#include "mvr/adelson/village_scene.h"

#include "mvr/adelson/adelson.h"

namespace mvr::adelson {

Scene makeVillageScene(int buildings) {
    // The paper's space is left-handed (+z away from the viewer); mvr's is right-handed:
    // z -> -z, and each polygon's vertex order reversed so front faces stay counter-clockwise.
    // One mesh per albedo (flat normals, a polygon fanned into triangles), one instance each.
    std::map<std::tuple<float, float, float>, int> meshOf;
    Scene scene;
    for (const Polygon3& p : makeVillage(buildings)) {
        if (p.v.size() < 3) continue;
        const auto key = std::make_tuple(p.albedo.r, p.albedo.g, p.albedo.b);
        auto [it, inserted] = meshOf.try_emplace(key, int(scene.meshes.size()));
        if (inserted) {
            scene.meshes.push_back({});
            scene.meshes.back().name = "village";
            Instance inst;
            inst.mesh = it->second;
            inst.material.albedo = {p.albedo.r, p.albedo.g, p.albedo.b};
            scene.instances.push_back(inst);
        }
        Mesh& m = scene.meshes[it->second];
        std::vector<glm::vec3> v;
        for (auto k = p.v.size(); k-- > 0;)
            v.push_back({float(p.v[k].x), float(p.v[k].y), -float(p.v[k].z)});
        glm::vec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
        const float len = glm::length(n);
        n = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
        const auto base = std::uint32_t(m.positions.size());
        for (const glm::vec3& q : v) {
            m.positions.push_back(q);
            m.normals.push_back(n);
        }
        for (std::uint32_t k = 1; k + 1 < v.size(); ++k)
            m.indices.insert(m.indices.end(), {base, base + k, base + k + 1});
    }
    scene.lights = defaultLights();
    // The paper's viewer sits at the origin looking down +z (mvr: -z) at the village.
    scene.viewpoint = SceneViewpoint{{0.0f, 0.0f, 0.0f}, {0.0f, -0.5f, -7.0f}};
    return scene;
}

}  // namespace mvr::adelson
