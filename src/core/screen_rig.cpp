// screen_rig.cpp — a rig from a physical screen and tracked eyes (mvr/core/screen_rig.h).
#include "mvr/core/screen_rig.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

namespace mvr {

ScreenCorners screenOfSize(float widthMm, float heightMm, float tiltDegrees) {
    const float w = 0.5f * widthMm, h = 0.5f * heightMm;
    const float c = std::cos(glm::radians(tiltDegrees)), s = std::sin(glm::radians(tiltDegrees));
    // The up axis leans back (toward −Z) by the tilt: (0, cos, −sin).
    return {{-w, -h * c, h * s}, {w, -h * c, h * s}, {-w, h * c, -h * s}};
}

ScreenEyes eyesAtHead(const ScreenCorners& screen, glm::vec3 head, float ipdMm) {
    ScreenEyes s;
    s.screen = screen;
    const glm::vec3 half = 0.5f * ipdMm * screen.right();
    s.leftEye = head - half;
    s.rightEye = head + half;
    return s;
}

namespace {
bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
std::string mm(const glm::vec3& v) { return fmt::format("({:g}, {:g}, {:g}) mm", v.x, v.y, v.z); }
constexpr float kMaxMm = 100000.0f;  // 100 m
}  // namespace

Status validateScreen(const ScreenCorners& c, const std::string& what) {
    if (!finite(c.lowerLeft) || !finite(c.lowerRight) || !finite(c.upperLeft))
        return usageError(what + ": a screen corner is not finite");
    const float w = c.width(), h = c.height();
    if (!(w >= 1.0f && h >= 1.0f && w <= kMaxMm && h <= kMaxMm)) {
        return usageError(fmt::format(
            "{}: a screen of {:g} x {:g} mm (expected 1 mm .. 100 m a side)", what, w, h));
    }
    const float cosAngle = glm::dot(c.right(), c.up());
    if (std::abs(cosAngle) > std::sin(glm::radians(0.1f))) {
        return usageError(fmt::format(
            "{}: the screen's corners make an angle of {:.2f} degrees at the lower-left corner "
            "(expected a rectangle: lower-left, lower-right, upper-left)",
            what, glm::degrees(std::acos(std::clamp(cosAngle, -1.0f, 1.0f)))));
    }
    return {};
}

Status validateScreenEyes(const ScreenEyes& s, const std::string& what) {
    if (Status st = validateScreen(s.screen, what); !st) return st;
    const ScreenCorners& c = s.screen;
    const glm::vec3 n = c.normal();
    for (const auto& [name, eye] : {std::pair{"left", s.leftEye}, std::pair{"right", s.rightEye}}) {
        if (!finite(eye)) return usageError(fmt::format("{}: the {} eye is not finite", what, name));
        const float d = glm::dot(eye - c.lowerLeft, n);
        if (!(d >= 1.0f)) {
            return usageError(fmt::format(
                "{}: the {} eye at {} is {:g} mm from the screen's plane (expected in front of "
                "it, at +Z of a screen facing +Z, by at least 1 mm)",
                what, name, mm(eye), d));
        }
        if (glm::length(eye - c.centre()) > kMaxMm) {
            return usageError(fmt::format("{}: the {} eye at {} is more than 100 m from the screen",
                                          what, name, mm(eye)));
        }
    }
    if (glm::length(s.rightEye - s.leftEye) < 1e-3f)
        return usageError(what + ": the two eyes are at the same point");
    return {};
}

View kooimaView(const glm::vec3& pa, const glm::vec3& pb, const glm::vec3& pc,
                const glm::vec3& pe, float near, float far) {
    const glm::vec3 vr = glm::normalize(pb - pa), vu = glm::normalize(pc - pa);
    const glm::vec3 vn = glm::normalize(glm::cross(vr, vu));
    const glm::vec3 va = pa - pe, vb = pb - pe, vc = pc - pe;
    const float d = -glm::dot(va, vn);  // the eye's distance to the screen's plane
    const float k = near / d;
    const float l = glm::dot(vr, va) * k, r = glm::dot(vr, vb) * k;
    const float b = glm::dot(vu, va) * k, t = glm::dot(vu, vc) * k;
    View v;
    v.clipFromView = glm::frustum(l, r, b, t, near, far);
    v.viewFromWorld = glm::lookAt(pe, pe - vn, vu);
    v.eyeWorld = pe;
    return v;
}

glm::vec3 screenToWorld(const Camera& framing, float convergence, const ScreenCorners& screen,
                        const glm::vec3& p) {
    const glm::vec3 f = glm::normalize(framing.target - framing.position);
    const glm::vec3 r = glm::normalize(glm::cross(f, framing.up));
    const glm::vec3 u = glm::cross(r, f);
    const float halfWidth =
        convergence * std::tan(glm::radians(framing.fovYDegrees) * 0.5f) * framing.aspect;
    const float scale = 2.0f * halfWidth / screen.width();  // world units per mm
    const glm::vec3 q = p - screen.centre();
    const glm::vec3 centre = framing.position + f * convergence;
    return centre + scale * (r * q.x + u * q.y - f * q.z);
}

Result<Rig> makeScreenRig(const Camera& framing, float convergence, const ScreenEyes& eyes) {
    if (Status s = validateScreenEyes(eyes); !s) return s;
    if (!(convergence > 0.0f) || !std::isfinite(convergence))
        return usageError(fmt::format("--rig screen: convergence {} (expected > 0)", convergence));
    const ScreenCorners& sc = eyes.screen;
    auto world = [&](const glm::vec3& p) { return screenToWorld(framing, convergence, sc, p); };
    const glm::vec3 pa = world(sc.lowerLeft), pb = world(sc.lowerRight), pc = world(sc.upperLeft);
    const glm::vec3 n = glm::normalize(glm::cross(pb - pa, pc - pa));
    // The framing camera's near and far planes as world planes parallel to the screen: an eye
    // D from the screen puts them at D − (convergence − near) and D + (far − convergence).
    const float before = convergence - framing.near, beyond = framing.far - convergence;
    std::vector<View> views;
    for (const glm::vec3& eyeMm : {eyes.leftEye, eyes.rightEye}) {
        const glm::vec3 e = world(eyeMm);
        const float d = glm::dot(e - pa, n);
        const float near = std::max(d - before, 1e-3f * d);
        const float far = std::max(d + beyond, near * 1.01f);
        views.push_back(kooimaView(pa, pb, pc, e, near, far));
    }
    // The shading's centre eye and the culling frustum's camera: the eyes' midpoint, looking
    // at the screen along its normal, its field of view the screen's height seen from there.
    const glm::vec3 mid = world(0.5f * (eyes.leftEye + eyes.rightEye));
    const float dMid = glm::dot(mid - pa, n);
    Camera centre = framing;
    centre.position = mid;
    centre.target = mid - n * dMid;
    centre.up = glm::normalize(pc - pa);
    const float halfH = 0.5f * glm::length(pc - pa);
    centre.fovYDegrees = glm::degrees(2.0f * std::atan(halfH / dMid));
    centre.aspect = sc.width() / sc.height();
    centre.near = std::max(dMid - before, 1e-3f * dMid);
    centre.far = std::max(dMid + beyond, centre.near * 1.01f);
    auto rig = makeListRig(centre, std::move(views));
    if (!rig) return rig.status();
    rig->columns = 2;
    rig->convergence = dMid;
    rig->interaxial = glm::length(world(eyes.rightEye) - world(eyes.leftEye));
    rig->screen = std::make_shared<const ScreenEyes>(eyes);
    rig->screenConvergence = convergence;
    rig->screenFraming = framing;
    return rig;
}

}  // namespace mvr
