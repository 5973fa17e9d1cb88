#include "view_state.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "mvr/core/animation.h"
#include "mvr/core/stereo_surfaces.h"

namespace mvr::viewer {

StereoCamera StereoCamera::fromRig(const Rig& rig, float sceneRadius, float viewConeDegrees) {
    StereoCamera s;
    s.columns = rig.columns;
    s.viewConeDegrees = viewConeDegrees;
    s.camera = rig.camera;
    s.kind = rig.kind;
    s.interaxial = rig.interaxial;
    s.convergence = rig.convergence;
    s.sceneRadius = std::max(sceneRadius, 1e-4f);
    if (rig.screen) s.screenRig = rig;
    return s;
}

bool StereoCamera::moveHead(glm::vec3 deltaMm) {
    if (!screenRig) return false;
    const glm::vec3 before = headOffsetMm;
    headOffsetMm += deltaMm;
    if (rig()) return true;
    headOffsetMm = before;
    return false;
}

float StereoCamera::screenWidthMm() const {
    return screenRig && screenRig->screen ? screenRig->screen->screen.width() : 0.0f;
}

void StereoCamera::setEyes(const ScreenEyes& eyes) {
    if (screenRig) screenRig->screen = std::make_shared<const ScreenEyes>(eyes);
}

float StereoCamera::separation() const {
    return separationFromInteraxial(camera, interaxial, convergence);
}

void StereoCamera::setSeparation(float separation) {
    interaxial = interaxialFromSeparation(camera, std::clamp(separation, 0.0f, 0.25f), convergence);
}

void StereoCamera::setConvergence(float distance) {
    const float s = separation();
    convergence = std::clamp(distance, camera.near * 1.01f, camera.far);
    setSeparation(s);
}

void StereoCamera::setAspect(float aspect) {
    if (aspect == camera.aspect) return;
    const float s = separation();
    camera.aspect = aspect;
    setSeparation(s);
}

void StereoCamera::orbit(float yawRadians, float pitchRadians) {
    const glm::vec3 offset = camera.position - camera.target;
    const float d = glm::length(offset);
    if (d <= 0.0f) return;
    const glm::vec3 dir = offset / d;
    // Current pitch above the horizon and yaw around +Y; the new ones clamped short of the poles
    // so that lookAt's up vector (+Y) stays valid.
    const float pitch = std::asin(std::clamp(dir.y, -1.0f, 1.0f));
    const float yaw = std::atan2(dir.x, dir.z);
    const float limit = glm::radians(89.0f);
    const float p = std::clamp(pitch + pitchRadians, -limit, limit);
    const float y = yaw + yawRadians;
    camera.position = camera.target + d * glm::vec3(std::cos(p) * std::sin(y), std::sin(p),
                                                    std::cos(p) * std::cos(y));
}

void StereoCamera::pan(float dxFraction, float dyFraction) {
    const glm::mat4 viewFromWorld = camera.viewFromWorld();
    // Rows of the rotation are the camera's axes in world space.
    const glm::vec3 right(viewFromWorld[0][0], viewFromWorld[1][0], viewFromWorld[2][0]);
    const glm::vec3 up(viewFromWorld[0][1], viewFromWorld[1][1], viewFromWorld[2][1]);
    const float height = 2.0f * distance() * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    const glm::vec3 shift = (right * dxFraction + up * dyFraction) * height;
    camera.position += shift;
    camera.target += shift;
}

void StereoCamera::zoom(float factor) {
    const float d = distance();
    if (d <= 0.0f || !(factor > 0.0f)) return;
    const float newD = std::max(d * factor, sceneRadius * 0.01f);
    const float f = newD / d;
    const float s = separation();
    camera.position = camera.target + (camera.position - camera.target) * f;
    // near/far as `mvr render` chooses them for a camera at this distance.
    camera.near = std::max(newD - sceneRadius * 2.5f, newD * 0.02f);
    camera.far = newD + sceneRadius * 3.0f;
    convergence *= f;
    if (convergence <= camera.near) camera.near = convergence * 0.5f;
    setSeparation(s);
}

void StereoCamera::setViewCone(float degrees) {
    viewConeDegrees = std::clamp(degrees, kMinViewCone, kMaxViewCone);
}

Result<Rig> StereoCamera::rig() const {
    if (screenRig && screenRig->screen) {
        ScreenEyes eyes = *screenRig->screen;
        eyes.leftEye += headOffsetMm;
        eyes.rightEye += headOffsetMm;
        return rigAt(*screenRig, camera, &eyes);
    }
    RigParams params;
    params.kind = kind;
    params.columns = columns;
    params.viewConeDegrees = viewConeDegrees;
    params.rows = 1;
    params.interaxial = interaxial;
    params.convergence = convergence;
    return makeRig(camera, params);
}

float distanceFromWindowDepth(float d, float near, float far) {
    const float z = 2.0f * d - 1.0f;
    return 2.0f * near * far / ((far + near) - z * (far - near));
}

std::optional<ParallaxRange> frameParallaxRange(const Rig& rig, const DepthImage& depth) {
    float dMin = 1.0f, dMax = 0.0f;
    for (float d : depth.depth) {
        if (d < 1.0f) {
            dMin = std::min(dMin, d);
            dMax = std::max(dMax, d);
        }
    }
    if (dMin > dMax) return std::nullopt;
    return parallaxRange(rig, distanceFromWindowDepth(dMin, rig.camera.near, rig.camera.far),
                         distanceFromWindowDepth(dMax, rig.camera.near, rig.camera.far));
}

namespace {

/// The point at eye distance w on the centre camera's ray through view pixel `px`.
glm::vec3 pointOnRay(const Camera& camera, glm::vec2 ndc, float w) {
    const float tanY = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    const float tanX = tanY * camera.aspect;
    const glm::vec4 eye(ndc.x * w * tanX, ndc.y * w * tanY, -w, 1.0f);
    return glm::vec3(glm::inverse(camera.viewFromWorld()) * eye);
}

struct Projected {
    glm::vec2 ndc;
    float w;
};

Projected project(const View& view, const glm::vec3& world) {
    const glm::vec4 clip = view.clipFromWorld() * glm::vec4(world, 1.0f);
    return {glm::vec2(clip) / clip.w, clip.w};
}

glm::vec2 pixelFromNdc(glm::vec2 ndc, int width, int height) {
    return {(ndc.x * 0.5f + 0.5f) * float(width), (0.5f - ndc.y * 0.5f) * float(height)};
}

/// Window depth of view 0 at pixel position `px`, or nullopt outside / background.
std::optional<float> depthAt(const DepthImage& depth, glm::vec2 px) {
    const int x = int(std::floor(px.x));
    const int y = int(std::floor(px.y));
    if (x < 0 || y < 0 || x >= depth.width || y >= depth.height) return std::nullopt;
    const float d = depth.at(x, y);
    if (!(d < 1.0f)) return std::nullopt;
    return d;
}

}  // namespace

CursorPlacement placeCursor(const Rig& rig, const DepthImage& depth0, glm::vec2 screenPx, int width,
                            int height) {
    CursorPlacement out;
    const Camera& camera = rig.camera;
    const glm::vec2 ndc(screenPx.x / float(width) * 2.0f - 1.0f,
                        1.0f - screenPx.y / float(height) * 2.0f);
    float w = rig.convergence;
    if (!depth0.depth.empty() && depth0.width == width && depth0.height == height) {
        // Start from the depth straight under the mouse, then follow view 0's view of the ray.
        std::optional<float> d = depthAt(depth0, screenPx);
        for (int i = 0; d && i < 8; ++i) {
            const float next = distanceFromWindowDepth(*d, camera.near, camera.far);
            const bool settled = std::abs(next - w) <= 1e-5f * next;
            w = next;
            out.onSurface = true;
            if (settled) break;
            const Projected p0 = project(rig.views[0], pointOnRay(camera, ndc, w));
            std::optional<float> again = depthAt(depth0, pixelFromNdc(p0.ndc, width, height));
            if (!again) break;  // the ray's point leaves view 0's surface: keep the last w
            d = again;
        }
        if (!out.onSurface) w = rig.convergence;
    }
    out.distance = w;
    // The cursor is a 2D element at depth w (mvr/core/stereo_surfaces.h): the library's 2D-to-3D
    // conversion places it, and each eye draws it where the point projects there.
    Label at;
    at.screen = screenPx / glm::vec2(float(width), float(height));
    at.distance = w;
    out.world = labelPoint(rig, at);
    Projected p[2];
    for (int v = 0; v < 2 && v < rig.viewCount(); ++v) {
        p[v] = project(rig.views[v], out.world);
        if (auto px = projectToPixel(rig.views[v], out.world, width, height))
            out.viewPx[v] = glm::vec2(*px);
    }
    out.parallax = (p[1].ndc.x - p[0].ndc.x) * 0.5f;
    return out;
}

}  // namespace mvr::viewer
