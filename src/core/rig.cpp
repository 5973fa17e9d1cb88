#include "mvr/core/rig.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

namespace mvr {

glm::mat4 Camera::viewFromWorld() const { return glm::lookAt(position, target, up); }

glm::mat4 Camera::clipFromView() const {
    return glm::perspective(glm::radians(fovYDegrees), aspect, near, far);
}

bool Frustum::contains(const glm::vec3& p, float eps) const {
    for (const Plane& plane : planes) {
        if (plane.distance(p) < -eps) return false;
    }
    return true;
}

float Rig::screenWidth() const {
    return 2.0f * convergence * camera.aspect * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
}

float Rig::separation() const { return interaxial / screenWidth(); }

float separationFromInteraxial(const Camera& camera, float interaxial, float convergence) {
    const float width =
        2.0f * convergence * camera.aspect * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    return interaxial / width;
}

float interaxialFromSeparation(const Camera& camera, float separation, float convergence) {
    const float width =
        2.0f * convergence * camera.aspect * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    return separation * width;
}

glm::vec4 applyClipSpaceStereo(glm::vec4 monoClip, float eyeSign, float separation,
                               float convergence) {
    monoClip.x += eyeSign * separation * (monoClip.w - convergence);
    return monoClip;
}

namespace {

bool finite(float v) { return std::isfinite(v); }
bool finite(const glm::vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }

/// glFrustum: an off-center perspective projection.
glm::mat4 frustumMatrix(float left, float right, float bottom, float top, float near, float far) {
    return glm::frustum(left, right, bottom, top, near, far);
}

/// The camera's orthonormal frame in world space: right, up, back (= −forward).
struct Frame {
    glm::vec3 right, up, back;
};
Frame cameraFrame(const Camera& c) {
    const glm::mat4 worldFromView = glm::inverse(c.viewFromWorld());
    return {glm::vec3(worldFromView[0]), glm::vec3(worldFromView[1]), glm::vec3(worldFromView[2])};
}

}  // namespace

Status validateRigParams(const Camera& c, const RigParams& p) {
    if (!finite(c.position) || !finite(c.target) || !finite(c.up)) {
        return usageError("camera position, target and up must be finite");
    }
    if (glm::length(c.target - c.position) <= 0.0f)
        return usageError("camera target equals its position");
    if (glm::length(glm::cross(glm::normalize(c.target - c.position), c.up)) < 1e-6f) {
        return usageError("camera up vector is parallel to the viewing direction");
    }
    if (!finite(c.fovYDegrees) || c.fovYDegrees <= 0.0f || c.fovYDegrees >= 180.0f) {
        return usageError(fmt::format(
            "field of view {} is out of range (expected 0 < fov < 180 degrees)", c.fovYDegrees));
    }
    if (!finite(c.aspect) || c.aspect <= 0.0f) {
        return usageError(fmt::format("aspect {} is out of range (expected > 0)", c.aspect));
    }
    if (!finite(c.near) || !finite(c.far) || c.near <= 0.0f || c.far <= c.near) {
        return usageError(fmt::format("near {} / far {} are out of range (expected 0 < near < far)",
                                      c.near, c.far));
    }
    if (p.columns < 1 || p.rows < 1 || p.columns * p.rows > kMaxViews) {
        return usageError(fmt::format("view count {}x{} is out of range (expected 1..{} views)",
                                      p.columns, p.rows, kMaxViews));
    }
    if (!finite(p.interaxial) || p.interaxial < 0.0f) {
        return usageError(fmt::format(
            "interaxial {} is out of range (expected a finite value >= 0)", p.interaxial));
    }
    if (!finite(p.interaxialY)) return usageError("vertical interaxial is not finite");
    if (!finite(p.convergence) || p.convergence <= c.near) {
        return usageError(
            fmt::format("convergence {} is out of range (expected a finite distance > near = {})",
                        p.convergence, c.near));
    }
    return {};
}

Result<Rig> makeRig(const Camera& camera, const RigParams& p) {
    if (Status s = validateRigParams(camera, p); !s) return s;
    Rig rig;
    rig.kind = p.kind;
    rig.camera = camera;
    rig.columns = p.columns;
    rig.rows = p.rows;
    rig.interaxial = p.interaxial;
    rig.interaxialY = p.interaxialY < 0.0f ? p.interaxial : p.interaxialY;
    rig.convergence = p.convergence;
    const bool cone =
        p.viewConeDegrees > 0.0f && p.kind == RigKind::OffAxis && p.rows == 1 && p.columns > 1;
    if (p.viewConeDegrees != 0.0f && (!std::isfinite(p.viewConeDegrees) ||
                                      p.viewConeDegrees < 0.0f || p.viewConeDegrees >= 180.0f))
        return usageError("view cone must be in [0, 180) degrees");
    if (!(p.coneSpread >= 0.0f && p.coneSpread <= 2.0f))
        return usageError(fmt::format("view cone spread {} is out of range (expected 0 .. 2)", p.coneSpread));
    if (cone) {
        // Mean spacing of the outer views, for the separation and the comfort report.
        rig.interaxial = p.coneSpread * 2.0f * p.convergence *
                         std::tan(glm::radians(p.viewConeDegrees) * 0.5f) /
                         static_cast<float>(p.columns - 1);
        rig.interaxialY = rig.interaxial;
    }

    const Frame frame = cameraFrame(camera);
    const glm::mat4 monoView = camera.viewFromWorld();
    const float tanHalf = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    const float top = camera.near * tanHalf;
    const float halfWidthNear = top * camera.aspect;
    // Half extents of the window on the convergence plane.
    const float a = p.convergence * camera.aspect * tanHalf;
    const float b = p.convergence * tanHalf;
    const float nearOverConv = camera.near / p.convergence;

    for (int row = 0; row < p.rows; ++row) {
        for (int col = 0; col < p.columns; ++col) {
            // Views numbered left to right, then top to bottom: row 0 is the top row.
            const float ox =
                cone
                    ? p.coneSpread * p.convergence *
                          std::tan(glm::radians(p.viewConeDegrees *
                                                (static_cast<float>(col) / (p.columns - 1) - 0.5f)))
                    : (col - (p.columns - 1) * 0.5f) * rig.interaxial;
            const float oy = ((p.rows - 1) * 0.5f - row) * rig.interaxialY;
            View v;
            v.eyeWorld = camera.position + ox * frame.right + oy * frame.up;
            switch (p.kind) {
                case RigKind::OffAxis: {
                    // Translate the world by −offset in eye space; shift the frustum so that
                    // all views share the window on the convergence plane.
                    v.viewFromWorld =
                        glm::translate(glm::mat4(1.0f), glm::vec3(-ox, -oy, 0.0f)) * monoView;
                    v.clipFromView = frustumMatrix(
                        -(a + ox) * nearOverConv, (a - ox) * nearOverConv, -(b + oy) * nearOverConv,
                        (b - oy) * nearOverConv, camera.near, camera.far);
                    v.clipShear = glm::vec2(ox / a, oy / b);
                    break;
                }
                case RigKind::Parallel: {
                    v.viewFromWorld =
                        glm::translate(glm::mat4(1.0f), glm::vec3(-ox, -oy, 0.0f)) * monoView;
                    v.clipFromView = frustumMatrix(-halfWidthNear, halfWidthNear, -top, top,
                                                   camera.near, camera.far);
                    break;
                }
                case RigKind::ToeIn: {
                    const glm::vec3 forward = -frame.back;
                    const glm::vec3 focus = camera.position + p.convergence * forward;
                    v.viewFromWorld = glm::lookAt(v.eyeWorld, focus, frame.up);
                    v.clipFromView = frustumMatrix(-halfWidthNear, halfWidthNear, -top, top,
                                                   camera.near, camera.far);
                    break;
                }
                case RigKind::List:
                    return usageError("makeRig(): use makeListRig() for an explicit list of views");
            }
            rig.views.push_back(v);
        }
    }
    rig.cullingFrustum = enclosingFrustum(camera, rig.views);
    return rig;
}

Result<Rig> makeListRig(const Camera& camera, std::vector<View> views) {
    if (views.empty() || views.size() > std::size_t(kMaxViews)) {
        return usageError(
            fmt::format("view list has {} views (expected 1..{})", views.size(), kMaxViews));
    }
    Rig rig;
    rig.kind = RigKind::List;
    rig.camera = camera;
    rig.columns = static_cast<int>(views.size());
    rig.rows = 1;
    rig.convergence = glm::length(camera.target - camera.position);
    rig.views = std::move(views);
    for (View& v : rig.views) {
        v.clipShear.reset();
        v.eyeWorld = glm::vec3(glm::inverse(v.viewFromWorld)[3]);
    }
    rig.cullingFrustum = enclosingFrustum(camera, rig.views);
    return rig;
}

std::array<glm::vec3, 8> frustumCorners(const View& view) {
    const glm::mat4 worldFromClip = glm::inverse(view.clipFromWorld());
    static const glm::vec2 kNdc[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    std::array<glm::vec3, 8> corners{};
    for (int z = 0; z < 2; ++z) {
        for (int i = 0; i < 4; ++i) {
            const glm::vec4 p = worldFromClip * glm::vec4(kNdc[i], z == 0 ? -1.0f : 1.0f, 1.0f);
            corners[z * 4 + i] = glm::vec3(p) / p.w;
        }
    }
    return corners;
}

Frustum enclosingFrustum(const Camera& camera, std::span<const View> views) {
    // Work in the camera's frame: x right, y up, depth d = distance along the viewing axis.
    const Frame f = cameraFrame(camera);
    const glm::vec3 forward = -f.back;
    struct Local {
        float x, y, d;
    };
    std::vector<Local> pts;
    for (const View& v : views) {
        for (const glm::vec3& c : frustumCorners(v)) {
            const glm::vec3 r = c - camera.position;
            pts.push_back({glm::dot(r, f.right), glm::dot(r, f.up), glm::dot(r, forward)});
        }
    }
    Frustum out;
    if (pts.empty()) return out;
    float dMin = std::numeric_limits<float>::max(), dMax = -dMin;
    for (const Local& p : pts) {
        dMin = std::min(dMin, p.d);
        dMax = std::max(dMax, p.d);
    }
    // A supporting line s = s0 + k·(d − d0) below every point in the (d, s) plane, where s is the
    // coordinate (x or y) times `sign` (+1 for the left/bottom side, −1 for right/top): start at
    // the smallest s among the nearest points and take the smallest slope to any other point.
    // Every corner then lies on the inner side, hence the convex hull of all frustums does too.
    auto sidePlane = [&](auto coord, float sign, const glm::vec3& axis) {
        float d0 = dMin, s0 = std::numeric_limits<float>::max();
        const float tol = 1e-6f * std::max(1.0f, std::abs(dMin));
        for (const Local& p : pts) {
            if (p.d <= dMin + tol) s0 = std::min(s0, sign * coord(p));
        }
        float k = std::numeric_limits<float>::max();
        for (const Local& p : pts) {
            if (p.d > d0 + tol) k = std::min(k, (sign * coord(p) - s0) / (p.d - d0));
        }
        if (k == std::numeric_limits<float>::max()) k = 0.0f;
        // Inside: sign·coord − s0 − k·(d − d0) ≥ 0, with coord = dot(r, axis), d = dot(r, forward).
        glm::vec3 n = sign * axis - k * forward;
        float d = -(s0 - k * d0);
        const float len = glm::length(n);
        n /= len;
        d /= len;
        // Shift from camera-relative to world coordinates: n·(p − eye) + d = n·p + (d − n·eye).
        return Plane{n, d - glm::dot(n, camera.position)};
    };
    auto getX = [](const Local& p) { return p.x; };
    auto getY = [](const Local& p) { return p.y; };
    out.planes[0] = sidePlane(getX, 1.0f, f.right);                              // left
    out.planes[1] = sidePlane(getX, -1.0f, f.right);                             // right
    out.planes[2] = sidePlane(getY, 1.0f, f.up);                                 // bottom
    out.planes[3] = sidePlane(getY, -1.0f, f.up);                                // top
    out.planes[4] = Plane{forward, -dMin - glm::dot(forward, camera.position)};  // near
    out.planes[5] = Plane{-forward, dMax + glm::dot(forward, camera.position)};  // far
    return out;
}

float parallax(const Rig& rig, const glm::vec3& p, int a, int b) {
    const glm::vec4 ca = rig.views.at(a).clipFromWorld() * glm::vec4(p, 1.0f);
    const glm::vec4 cb = rig.views.at(b).clipFromWorld() * glm::vec4(p, 1.0f);
    return (cb.x / cb.w - ca.x / ca.w) * 0.5f;
}

ParallaxRange parallaxRange(const Rig& rig, float nearestW, float farthestW) {
    ParallaxRange r;
    // Between the outermost views of a row: their offset is (columns − 1) · interaxial.
    const float sep = (rig.columns - 1) * rig.separation();
    const float halfBaseline = 0.5f * (rig.columns - 1) * rig.interaxial;
    const float tanHalfX =
        rig.camera.aspect * std::tan(glm::radians(rig.camera.fovYDegrees) * 0.5f);
    // The parallax of a point on the axis at distance w, each rig its own formula:
    auto parallaxAt = [&](float w) {
        switch (rig.kind) {
            case RigKind::Parallel:
                // Symmetric frustums, eyes ±h: ndc.x = (x ∓ h) / (w·tanHalfX), so the parallax
                // is −2h / (2·w·tanHalfX) = −sep·convergence / w: negative everywhere, zero only
                // at infinity (the off-axis formula minus sep).
                return -sep * rig.convergence / w;
            case RigKind::ToeIn:
                // Each outer eye at ±h turned by atan(h/C) towards the axis point at C: the point
                // at w is seen atan(h/C) − atan(h/w) off its axis.
                return std::tan(std::atan(halfBaseline / rig.convergence) -
                                std::atan(halfBaseline / w)) /
                       tanHalfX;
            default: return sep * (1.0f - rig.convergence / w);
        }
    };
    r.nearestDistance = nearestW;
    r.farthestDistance = farthestW;
    r.minParallax = parallaxAt(nearestW);
    r.maxParallax = parallaxAt(farthestW);
    if (rig.kind == RigKind::Parallel) {
        // No convergence plane: the [convergence/2, 100 x convergence] rule does not apply.
    } else if (nearestW < rig.convergence * 0.5f) {
        r.why = "scene reaches closer than convergence/2";
    } else if (farthestW > rig.convergence * 100.0f) {
        r.why = "scene reaches beyond 100 x convergence";
    }
    // Beyond one screen width between views two eyes can see together no display shows it. A
    // stereo pair: the outer views; a row of N > 2 views (a light field: the eyes see views k
    // apart, never the outermost pair): adjacent views, 1 / (N − 1) of the outer parallax.
    const float pairShare = rig.columns > 2 ? 1.0f / float(rig.columns - 1) : 1.0f;
    if (std::max(std::abs(r.minParallax), std::abs(r.maxParallax)) * pairShare > 1.0f) {
        r.why += std::string(r.why.empty() ? "" : "; ") +
                 (rig.columns > 2 ? "parallax beyond one screen width between adjacent views "
                                    "(the spacing is far too large)"
                                  : "parallax beyond one screen width (the separation is far too "
                                    "large)");
    }
    r.comfortable = r.why.empty();
    return r;
}

Result<RigKind> parseRigKind(const std::string& name) {
    if (name == "offaxis") return RigKind::OffAxis;
    if (name == "toein") return RigKind::ToeIn;
    if (name == "parallel") return RigKind::Parallel;
    return usageError(fmt::format("unknown rig '{}' (expected offaxis, toein or parallel)", name));
}

const char* rigKindName(RigKind kind) {
    switch (kind) {
        case RigKind::OffAxis: return "offaxis";
        case RigKind::ToeIn: return "toein";
        case RigKind::Parallel: return "parallel";
        case RigKind::List: return "list";
    }
    return "?";
}

}  // namespace mvr
