// screen.cpp — `--rig screen`'s options (mvr/session/screen.h).
#include "mvr/session/screen.h"

#include <algorithm>
#include <cmath>
#include <regex>
#include <vector>

#include <fmt/core.h>

#include "mvr/session/camera.h"

namespace mvr::session {
namespace {

/// "A;B;C" as `count` points, each "X,Y,Z".
Result<std::vector<glm::vec3>> pointsOf(const std::string& value, const std::string& option,
                                        std::size_t count, const char* form) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (;;) {
        const std::size_t semi = value.find(';', start);
        parts.push_back(value.substr(start, semi - start));
        if (semi == std::string::npos) break;
        start = semi + 1;
    }
    if (parts.size() != count) {
        return usageError(fmt::format("{} {}: expected {} ({} points X,Y,Z separated by ';')",
                                      option, value, form, count));
    }
    std::vector<glm::vec3> out;
    for (const std::string& p : parts) {
        auto v = vec3Of(p, option);
        if (!v) return usageError(fmt::format("{} {}: '{}' is not X,Y,Z (three numbers)", option, value, p));
        out.push_back(*v);
    }
    return out;
}

}  // namespace

std::optional<std::string> screenStretchNote(const ScreenCorners& screen, int width, int height) {
    const float viewAspect = float(width) / float(height);
    const float screenAspect = screen.width() / screen.height();
    if (std::abs(screenAspect / viewAspect - 1.0f) <= 0.01f) return std::nullopt;
    return fmt::format(
        "warning: the views are {}x{} (aspect {:.4g}) but the screen is {:.4g} x {:.4g} mm (aspect "
        "{:.4g}): each view fills the screen, stretched; --size {}x{} keeps the pixels square",
        width, height, viewAspect, screen.width(), screen.height(), screenAspect, width,
        std::max(1, int(std::lround(width / screenAspect))));
}

Status checkScreenOptions(const RenderRecipe& r, int views) {
    if (r.rig != "screen") {
        if (r.screen.given()) {
            return usageError(
                "--screen-mm, --screen-corners, --eyes, --ipd-mm and --head need --rig screen");
        }
        return {};
    }
    if (!r.viewGrid.empty())
        return usageError(fmt::format("--rig screen excludes --view-grid {} (two eyes, two views)", r.viewGrid));
    if (views != 2)
        return usageError(fmt::format("--rig screen renders two views (the eyes), not --views {}", views));
    if (r.viewCone) return usageError(fmt::format("--rig screen excludes --view-cone {}", *r.viewCone));
    if (r.interaxial) return usageError(fmt::format("--rig screen excludes --interaxial {} (--eyes or --ipd-mm give the spacing)", *r.interaxial));
    if (r.separation) return usageError(fmt::format("--rig screen excludes --separation {} (--eyes or --ipd-mm give the spacing)", *r.separation));
    if (r.separationAuto) return usageError("--rig screen excludes --separation auto (--eyes or --ipd-mm give the spacing)");
    return {};
}

Result<ScreenEyes> screenEyesOf(const RenderRecipe& r, float viewAspect) {
    const ScreenRecipe& s = r.screen;
    ScreenCorners screen;
    if (!s.corners.empty()) {
        if (!s.size.empty()) return usageError(fmt::format("--screen-corners excludes --screen-mm {}", s.size));
        auto p = pointsOf(s.corners, "--screen-corners", 3, "lower-left;lower-right;upper-left");
        if (!p) return p.status();
        screen = {(*p)[0], (*p)[1], (*p)[2]};
        if (Status st = validateScreen(screen, "--screen-corners " + s.corners); !st) return st;
    } else if (!s.size.empty()) {
        static const std::regex kSize(R"(\s*([0-9.eE+-]+)\s*[xX]\s*([0-9.eE+-]+)\s*)");
        std::smatch m;
        double w = 0.0, h = 0.0;
        bool ok = std::regex_match(s.size, m, kSize);
        if (ok) {
            try {
                std::size_t uw = 0, uh = 0;
                w = std::stod(m[1].str(), &uw);
                h = std::stod(m[2].str(), &uh);
                ok = uw == m[1].str().size() && uh == m[2].str().size();
            } catch (const std::exception&) {
                ok = false;
            }
        }
        if (!ok) return usageError(fmt::format("--screen-mm {}: expected WxH in millimetres (e.g. 597.9x336.3)", s.size));
        if (!(w >= 1.0 && h >= 1.0 && w <= 1e5 && h <= 1e5))
            return usageError(fmt::format("--screen-mm {}: out of range (expected 1 .. 100000 mm a side)", s.size));
        screen = screenOfSize(float(w), float(h));
    } else if (r.screenWidthCm) {
        const float w = float(*r.screenWidthCm) * 10.0f;
        screen = screenOfSize(w, w / viewAspect);
    } else {
        screen = screenOfSize(597.9f, 336.3f);
    }
    ScreenEyes eyes;
    if (!s.eyes.empty()) {
        if (s.ipdMm || !s.head.empty())
            return usageError(fmt::format("--eyes excludes {}", s.ipdMm ? "--ipd-mm" : "--head"));
        auto p = pointsOf(s.eyes, "--eyes", 2, "left;right");
        if (!p) return p.status();
        eyes.screen = screen;
        eyes.leftEye = (*p)[0];
        eyes.rightEye = (*p)[1];
    } else {
        const double ipd = s.ipdMm.value_or(63.0);
        if (!std::isfinite(ipd) || ipd < 0.0 || ipd > 1000.0)
            return usageError(fmt::format("--ipd-mm {} is out of range (expected 0 .. 1000 mm)", ipd));
        glm::vec3 head = screen.centre() +
                         screen.normal() * float(r.viewingDistanceCm ? *r.viewingDistanceCm * 10.0 : 600.0);
        if (!s.head.empty()) {
            auto h = vec3Of(s.head, "--head");
            if (!h) return h.status();
            head = *h;
        }
        if (ipd < 1e-3) return usageError(fmt::format("--ipd-mm {}: the eyes would be at one point (expected > 0)", ipd));
        eyes = eyesAtHead(screen, head, float(ipd));
    }
    const std::string what = !s.eyes.empty()  ? "--eyes " + s.eyes
                             : !s.head.empty() ? "--head " + s.head
                                               : "--rig screen";
    if (Status st = validateScreenEyes(eyes, what); !st) return st;
    return eyes;
}

}  // namespace mvr::session
