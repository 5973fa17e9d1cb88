#include "mvr/core/framing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>

#include "mvr/core/lighting.h"

namespace mvr {

namespace {

/// near / far around the scene's bounding sphere seen from camera.position, within the limits:
/// outside the sphere, frameCamera()'s margins (room for an orbit); inside it (an interior),
/// nearLimit.
void hugBounds(Camera& camera, const Bounds& bounds, float nearLimit, float farLimit) {
    const float radius = std::max(bounds.radius(), 1e-4f);
    const float centre = glm::length(bounds.center() - camera.position);
    camera.near = nearLimit;
    if (centre > radius) {
        const float floor = std::min(0.02f * centre, 0.5f * (centre - radius));
        camera.near = std::max(nearLimit, std::max(centre - 2.5f * radius, floor));
    }
    camera.far = std::min(farLimit, centre + 3.0f * radius);
    if (!(camera.far > camera.near * 1.001f)) camera.far = std::max(farLimit, camera.near * 2.0f);
}

}  // namespace

float fitDistance(const Scene& scene, float fovYDegrees, float aspect) {
    const float radius = std::max(scene.bounds().radius(), 1e-4f);
    const float halfFov = glm::radians(fovYDegrees) * 0.5f;
    const float halfFovX = std::atan(std::tan(halfFov) * aspect);
    return 1.05f * radius / std::sin(std::min(halfFov, halfFovX));
}

Camera cameraFromViewpoint(const Viewpoint& viewpoint, const Scene& scene, float fovYDegrees,
                           float aspect) {
    Camera camera;
    camera.position = viewpoint.position;
    camera.target = viewpoint.target;
    camera.up = viewpoint.up;
    camera.fovYDegrees = fovYDegrees;
    camera.aspect = aspect;
    const Bounds bounds = scene.bounds();
    hugBounds(camera, bounds, 1e-3f * std::max(bounds.radius(), 1e-4f),
              std::numeric_limits<float>::max());
    return camera;
}

Camera frameCamera(const Scene& scene, float fovYDegrees, float aspect) {
    const Bounds bounds = scene.bounds();
    const glm::vec3 center = bounds.center();
    const float radius = std::max(bounds.radius(), 1e-4f);
    Camera camera;
    camera.fovYDegrees = fovYDegrees;
    camera.aspect = aspect;
    const float halfFov = glm::radians(camera.fovYDegrees) * 0.5f;
    const float halfFovX = std::atan(std::tan(halfFov) * camera.aspect);
    const float fit = radius / std::sin(std::min(halfFov, halfFovX));
    if (scene.viewpoint) {
        camera.position = scene.viewpoint->position;
        camera.target = scene.viewpoint->target;
    } else {
        camera.target = center;
        camera.position = center + glm::vec3(0.0f, 0.0f, fit * 1.05f);
    }
    const float distance = glm::length(camera.position - camera.target);
    camera.near = std::max(distance - radius * 2.5f, distance * 0.02f);
    camera.far = distance + radius * 3.0f;
    return camera;
}

float fitFileFov(float yfovRadians, float fileAspect, float aspect) {
    if (!(fileAspect > 0.0f) || !(aspect > 0.0f) || aspect >= fileAspect) return yfovRadians;
    // Narrower than the file's frame: its horizontal field of view kept, the vertical widened.
    const float widened = 2.0f * std::atan(std::tan(yfovRadians * 0.5f) * fileAspect / aspect);
    return std::min(widened, glm::radians(kMaxFittedFovDegrees));
}

Camera cameraFromScene(const SceneCamera& file, const Scene& scene,
                       std::optional<float> fovYDegrees, float aspect) {
    Camera camera;
    const glm::mat3 axes(file.worldFromCamera);
    camera.position = glm::vec3(file.worldFromCamera[3]);
    glm::vec3 forward = axes * glm::vec3(0.0f, 0.0f, -1.0f);
    glm::vec3 up = axes * glm::vec3(0.0f, 1.0f, 0.0f);
    forward = glm::length(forward) > 0.0f ? glm::normalize(forward) : glm::vec3(0, 0, -1);
    up = glm::length(up) > 0.0f ? glm::normalize(up) : glm::vec3(0, 1, 0);
    camera.up = up;
    camera.aspect = aspect;
    camera.fovYDegrees =
        fovYDegrees.value_or(glm::degrees(fitFileFov(file.yfovRadians, file.aspect, aspect)));
    const Bounds bounds = scene.bounds();
    const float radius = std::max(bounds.radius(), 1e-4f);
    float depth = glm::dot(bounds.center() - camera.position, forward);
    if (!(depth > file.znear)) depth = std::max(radius, file.znear * 2.0f);  // behind: ahead
    camera.target = camera.position + forward * depth;
    // The file's planes are limits, not the depth range: a camera with znear 0.05 and zfar 1e6
    // over a scene a few units deep would leave a few hundred depth values to the whole scene
    // (z-fighting). Outside the bounding sphere the planes hug it with frameCamera()'s margins
    // (room for an orbit); inside it (an interior), the file's znear stays.
    hugBounds(camera, bounds, file.znear,
              file.zfar > file.znear ? file.zfar : std::numeric_limits<float>::max());
    return camera;
}

Camera centreCamera(const Scene& scene, const FramingParams& params, float aspect) {
    if (params.viewpoint) return cameraFromViewpoint(*params.viewpoint, scene, params.fovYDegrees, aspect);
    if (params.useSceneCamera && scene.camera) {
        return cameraFromScene(*scene.camera, scene,
                               params.fovOverridesSceneCamera
                                   ? std::optional<float>(params.fovYDegrees)
                                   : std::nullopt,
                               aspect);
    }
    return frameCamera(scene, params.fovYDegrees, aspect);
}

Result<RenderRequest> frameScene(const Scene& scene, const FramingParams& params,
                                 RenderSettings settings) {
    if (!std::isfinite(params.fovYDegrees) || params.fovYDegrees <= 0.0f ||
        params.fovYDegrees >= 180.0f) {
        return usageError(fmt::format("fov {} is out of range (expected 0 < fov < 180 degrees)",
                                      params.fovYDegrees));
    }
    if (params.columns < 1 || params.rows < 1 || params.columns * params.rows > kMaxViews) {
        return usageError(fmt::format("{}x{} views is out of range (expected 1..{} views)",
                                      params.columns, params.rows, kMaxViews));
    }
    for (const auto& [name, value] :
         {std::pair{"interaxial", params.interaxial}, std::pair{"separation", params.separation},
          std::pair{"convergence", params.convergence}}) {
        if (value && (!std::isfinite(*value) || *value < 0.0f)) {
            return usageError(
                fmt::format("{} {} is out of range (expected a finite value >= 0)", name, *value));
        }
    }
    if (params.convergence && *params.convergence <= 0.0f) {
        return usageError("convergence 0 is out of range (expected a distance > 0)");
    }
    if (params.viewConeDegrees != 0.0f && (params.interaxial || params.separation)) {
        return usageError("view cone and interaxial/separation both given (expected one of them)");
    }
    if (params.interaxial && params.separation) {
        return usageError("interaxial and separation both given (expected one of them)");
    }
    if (Status s = validateSettings(settings); !s) return s;
    if (Status s = validateScene(scene); !s) return s;

    settings.clearColor = params.clearColor.value_or(scene.background);
    if (params.aspect && (!std::isfinite(*params.aspect) || *params.aspect <= 0.0f)) {
        return usageError(fmt::format("aspect {} is out of range (expected > 0)", *params.aspect));
    }
    const float aspect = params.aspect.value_or(float(settings.width) / float(settings.height));
    Camera camera = centreCamera(scene, params, aspect);
    const float distance = glm::length(camera.position - camera.target);
    RigParams rig;
    rig.kind = params.kind;
    rig.columns = params.columns;
    rig.rows = params.rows;
    rig.convergence = params.convergence.value_or(distance) - params.focusShift;
    if (!(rig.convergence > 0.0f)) {
        return usageError(fmt::format(
            "the focus moves the focal plane {} toward the camera, to {} (behind it; expected a "
            "distance > 0)", params.focusShift, rig.convergence));
    }
    if (rig.convergence <= camera.near) camera.near = rig.convergence * 0.5f;
    // Beyond the far plane the zero-parallax plane is outside the scene's depth: every point
    // of the scene is nearer than the screen, and the default spacing (convergence / 30) puts
    // the views so far apart that they see nothing of it — refused rather than black images.
    if (params.kind != RigKind::Parallel && rig.convergence > camera.far) {
        return usageError(fmt::format(
            "convergence {} is beyond the far plane ({}): the zero-parallax plane must lie "
            "within the scene's depth (expected 0 < convergence <= {})",
            rig.convergence, camera.far, camera.far));
    }
    if (params.separation) {
        rig.interaxial = interaxialFromSeparation(camera, *params.separation, rig.convergence);
    } else {
        rig.interaxial = params.interaxial.value_or(rig.convergence / 30.0f);
    }
    rig.viewConeDegrees = params.viewConeDegrees;
    rig.coneSpread = params.coneSpread;
    auto made = makeRig(camera, rig);
    if (!made) return made.status();
    RenderRequest out{std::move(made).value(), settings};
    if (Status s = validateRequest(scene, out.rig, out.settings); !s) return s;
    return out;
}

float brightestLightAt(const Scene& scene, glm::vec3 point) {
    float peak = 0.0f;
    for (const Light& l : scene.lights) {
        const float c = std::max({l.color.x, l.color.y, l.color.z});
        peak = std::max(peak, c * lightAt(l, point).attenuation);
    }
    return peak;
}

void exposeLights(Scene& scene, float ev) {
    const float factor = std::exp2(ev);
    for (Light& l : scene.lights) l.color *= factor;
}

}  // namespace mvr
