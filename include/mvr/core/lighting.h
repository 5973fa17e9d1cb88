// mvr/core/lighting.h — the one shading model every backend implements (the soft backend
// calls these functions; the gl backend's GLSL mirrors them line by line), so that images
// from different backends and methods are comparable.
//
// Shading modes, after sorbier2008 Table 1:
//   Flat   — one color per triangle: ambient + Σ lights diffuse (Lambert) with the face
//            normal (normalize(cross(p1 - p0, p2 - p0)) in world space). No specular.
//   Vertex — Blinn-Phong evaluated at each vertex (smooth normal), colors interpolated
//            perspective-correctly ("vertex lighting", Gouraud).
//   Pixel  — the same Blinn-Phong evaluated per fragment with the interpolated, renormalized
//            normal and world position ("shader lighting").
// The view vector for the specular term points from the surface to the rig's CENTER eye
// (Rig::centerEye), not to each view's eye: shading is view-independent, so it can be done
// once for all views (kalaiah2007's view-independent attributes) and every method, single
// pass or multipass, produces the same colors.
// Output is linear [0, 1] per channel, clamped, alpha 1; quantized to 8 bits as
// uint8(clamp(c, 0, 1) * 255 + 0.5).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "mvr/core/scene.h"

namespace mvr {

enum class Shading { Flat, Vertex, Pixel };

/// Everything shading needs that does not depend on the view.
struct ShadingContext {
    std::span<const DirectionalLight> lights;
    glm::vec3 ambient{0.12f};
    glm::vec3 centerEye{0.0f};  ///< world-space eye used for the specular view vector
};

/// Flat: ambient + Σ max(dot(n, l), 0) · albedo · lightColor. `faceNormal` unit, world space.
inline glm::vec3 shadeFlat(const ShadingContext& ctx, const Material& m, glm::vec3 faceNormal) {
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        c += std::max(glm::dot(faceNormal, l.towardLight), 0.0f) * m.albedo * l.color;
    }
    return glm::clamp(c, 0.0f, 1.0f);
}

/// Blinn-Phong: ambient + Σ [max(n·l, 0) · albedo + specular · max(n·h, 0)^shininess (only
/// where n·l > 0)] · lightColor, with h = normalize(l + v), v = normalize(centerEye − p).
/// `normal` need not be unit (it is normalized here).
inline glm::vec3 shadeBlinnPhong(const ShadingContext& ctx, const Material& m, glm::vec3 normal,
                                 glm::vec3 worldPos) {
    const glm::vec3 n = glm::normalize(normal);
    const glm::vec3 v = glm::normalize(ctx.centerEye - worldPos);
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        const float nl = glm::dot(n, l.towardLight);
        if (nl > 0.0f) {
            const glm::vec3 h = glm::normalize(l.towardLight + v);
            const float spec = m.specular * std::pow(std::max(glm::dot(n, h), 0.0f), m.shininess);
            c += (nl * m.albedo + glm::vec3(spec)) * l.color;
        }
    }
    return glm::clamp(c, 0.0f, 1.0f);
}

inline std::uint8_t quantizeUnorm8(float c) {
    return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f);
}

}  // namespace mvr
