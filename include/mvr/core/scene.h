// mvr/core/scene.h — scenes: meshes placed by transforms, a material each, and lights.
//
// World space is right-handed, +Y up. Lights are directional, given in world space as the
// unit direction TOWARD the light. See lighting.h for the shading model every backend uses.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/mesh.h"

namespace mvr {

struct Material {
    glm::vec3 albedo{0.8f, 0.8f, 0.8f};  ///< diffuse color, linear [0, 1]
    float specular = 0.25f;              ///< specular intensity
    float shininess = 32.0f;             ///< Blinn-Phong exponent
};

struct Instance {
    int mesh = 0;  ///< index into Scene::meshes
    glm::mat4 worldFromModel{1.0f};
    Material material;
};

struct DirectionalLight {
    glm::vec3 towardLight{0.0f, 0.0f, 1.0f};  ///< unit, world space
    glm::vec3 color{1.0f};
};

inline constexpr int kMaxLights = 4;

/// Where a scene is meant to be seen from, when it says so (the default scene does).
struct SceneViewpoint {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
};

struct Scene {
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<DirectionalLight> lights;  ///< at most kMaxLights
    glm::vec3 ambient{0.12f};
    glm::vec3 background{0.08f};              ///< clear colour, linear [0, 1]
    std::optional<SceneViewpoint> viewpoint;  ///< absent: framing fits the bounds (framing.h)

    std::size_t triangleCount() const;  ///< over all instances
    Bounds bounds() const;              ///< world-space bounds of all instances
};

/// The three lights every built-in scene uses (key, fill, rim).
std::vector<DirectionalLight> defaultLights();

/// A procedural scene that needs no data files: a ground plane, spheres, a torus and boxes
/// spread in depth around the origin (some in front of, some behind a convergence plane
/// through the origin), lit by defaultLights().
Scene makeDefaultScene();

/// Lays out `copies` copies of the given meshes (all of them form one "model", placed side by
/// side) in a near-square grid on the XY plane, as sorbier2008 did with 1, 3, 5 and 9 bunnies.
/// Each copy gets its own color. Precondition: copies >= 1 and meshes not empty.
Scene makeGridScene(std::vector<Mesh> meshes, int copies);

/// Checks a scene before rendering (non-empty, mesh indices valid, <= kMaxLights lights).
Status validateScene(const Scene& scene);

}  // namespace mvr
