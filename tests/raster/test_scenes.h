// Small scenes and rigs for the raster tests.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr::raster::test {

/// An axis-aligned quad in the plane z = lo.z, counter-clockwise seen from +z.
inline Mesh quadMesh(glm::vec3 lo, glm::vec3 hi) {
    Mesh m;
    m.name = "quad";
    m.positions = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}};
    m.normals.assign(4, {0, 0, 1});
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

inline Scene sceneOf(Mesh mesh) {
    Scene s;
    s.lights = defaultLights();
    s.meshes = {std::move(mesh)};
    s.instances = {Instance{}};
    return s;
}

inline Scene quadScene(glm::vec3 lo, glm::vec3 hi) { return sceneOf(quadMesh(lo, hi)); }

/// Triangles from consecutive triples of positions (normals +z).
inline Scene triangleScene(const std::vector<glm::vec3>& positions) {
    Mesh m;
    m.name = "triangles";
    m.positions = positions;
    m.normals.assign(positions.size(), {0, 0, 1});
    for (std::uint32_t i = 0; i < positions.size(); ++i) m.indices.push_back(i);
    return sceneOf(std::move(m));
}

/// `views` views whose clip space is world space (w = 1): NDC = world x, y, z.
inline Rig identityRig(int views) {
    auto rig = makeListRig(Camera{}, std::vector<View>(std::size_t(views), View{}));
    return std::move(rig).value();
}

}  // namespace mvr::raster::test
