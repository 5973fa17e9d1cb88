// src/session/report.cpp — the display side of a session (docs/displays.md): a display preset's
// outputs, the views that see nothing of the scene, the depth pre-pass of --convergence auto /
// --separation auto, and the reports after a render (parallax, screen comfort, their JSON,
// the warnings of "no silent nonsense").
#include <algorithm>
#include <cmath>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "mvr/backends.h"
#include "mvr/session/prepare.h"

namespace mvr::session {

std::optional<ComfortReport> comfortReport(const Rig& rig, const RenderOutput& out) {
    if (rig.columns <= 1) return std::nullopt;
    const std::optional<DepthRange> depth = depthRangeOf(out, 0);
    if (!depth || !depth->drew()) return std::nullopt;
    const float dMin = depth->nearest, dMax = depth->farthest;
    ComfortReport report;
    report.range =
        parallaxRange(rig, distanceFromWindowDepth(dMin, rig.camera.near, rig.camera.far),
                      distanceFromWindowDepth(dMax, rig.camera.near, rig.camera.far));
    const ParallaxRange& r = report.range;
    const std::string adjacent = rig.columns > 2
                                     ? fmt::format(", between adjacent views {:+.2f}% .. {:+.2f}%",
                                                   100.0 * r.minParallax / (rig.columns - 1),
                                                   100.0 * r.maxParallax / (rig.columns - 1))
                                     : std::string();
    report.line = fmt::format(
        "parallax between outer views: {:+.2f}% .. {:+.2f}% of screen width{} ({})",
        100.0 * r.minParallax, 100.0 * r.maxParallax, adjacent,
        r.comfortable ? std::string("comfortable: all within [convergence/2, 100 x convergence]")
                      : "uncomfortable: " + r.why);
    return report;
}

void displayOutputs(const DisplayPreset& d, bool calibrationGiven, bool quiltGiven,
                    float cameraAspect, std::vector<std::string>& formats,
                    composite::ComposeOptions& compose) {
    auto want = [&](std::string_view f) {
        if (std::find(formats.begin(), formats.end(), f) == formats.end()) formats.emplace_back(f);
    };
    want(d.format);
    if (d.format == "quilt" && !quiltGiven) {
        compose.quiltColumns = d.quiltColumns;
        compose.quiltRows = d.quiltRows;
    }
    if (d.format == "quilt" && compose.quiltAspect <= 0.0) compose.quiltAspect = cameraAspect;
    if (calibrationGiven && d.quiltColumns > 0) {
        want("lenticular");
        if (compose.lenticular.screenWidth == 0 || compose.lenticular.screenHeight == 0) {
            compose.lenticular.screenWidth = d.panelWidth;
            compose.lenticular.screenHeight = d.panelHeight;
        }
    }
}

namespace {

/// The Gribb–Hartmann planes of one view's clip volume (inside: n·p + d ≥ 0, n unit).
bool sphereOutsideView(const View& v, const glm::vec3& c, float r) {
    const glm::mat4 m = v.clipFromWorld();
    auto row = [&](int i) { return glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
    const glm::vec4 planes[6] = {row(3) + row(0), row(3) - row(0), row(3) + row(1),
                                 row(3) - row(1), row(3) + row(2), row(3) - row(2)};
    for (const glm::vec4& p : planes) {
        const float len = glm::length(glm::vec3(p));
        if (len <= 0.0f || !std::isfinite(len)) continue;
        if ((glm::dot(glm::vec3(p), c) + p.w) / len < -r) return true;
    }
    return false;
}

}  // namespace

std::vector<int> viewsMissingScene(const Scene& scene, const Rig& rig) {
    const Bounds b = scene.bounds();
    const glm::vec3 c = b.center();
    const float r = std::max(b.radius(), 1e-6f);
    std::vector<int> out;
    for (int v = 0; v < rig.viewCount(); ++v) {
        if (sphereOutsideView(rig.views[v], c, r)) out.push_back(v);
    }
    return out;
}

Result<std::optional<DepthPercentiles>> centreDepthPrepass(const Scene& scene, const Camera& camera,
                                                           const RenderSettings& settings) {
    // The centre camera alone, at most 256 pixels across (the histogram needs no more), on the
    // registry's first backend (the CPU reference): its depth image.
    RigParams one;
    one.columns = 1;
    one.rows = 1;
    one.interaxial = 0.0f;
    one.convergence = std::max(glm::length(camera.target - camera.position), camera.near * 1.01f);
    auto rig = makeRig(camera, one);
    if (!rig) return rig.status();
    RenderSettings small = settings;
    const float scale = std::min(1.0f, 256.0f / float(std::max(settings.width, settings.height)));
    small.width = std::max(1, int(std::lround(settings.width * scale)));
    small.height = std::max(1, int(std::lround(settings.height * scale)));
    auto backend = makeBackend(backendNames().front());
    if (!backend) return backend.status();
    auto out = (*backend)->render(scene, *rig, small, (*backend)->defaultMethod());
    if (!out) return out.status();
    if (out->depth.empty()) return std::optional<DepthPercentiles>{};
    return depthPercentiles(out->depth[0].depth, camera.near, camera.far);
}

std::optional<ScreenComfortReport> screenComfortReport(const Prepared& p,
                                                       const std::optional<ComfortReport>& range) {
    if (!p.screen || !range) return std::nullopt;
    ScreenComfortReport r;
    const int pair = eyePairViews(p.rig, p.viewConeDegrees, *p.screen);
    r.comfort = screenComfort(p.rig, range->range, pair, *p.screen, p.viewConeDegrees);
    const ScreenComfort& c = r.comfort;
    std::string where = fmt::format("on a {:.4g} cm screen", p.screen->widthCm);
    if (p.screen->viewingDistanceCm > 0.0f)
        where += fmt::format(" at {:.4g} cm", p.screen->viewingDistanceCm);
    std::string vergence;
    if (p.screen->viewingDistanceCm > 0.0f) {
        vergence = fmt::format(", vergence {:.2f} .. {:.2f} deg (screen {:.2f} deg)",
                               c.nearestVergenceDeg, c.farthestVergenceDeg, c.screenVergenceDeg);
    }
    const std::string infinity =
        c.separationRule ? fmt::format(", at infinity {:+.2f} cm", c.infinityParallaxCm) : "";
    r.line = fmt::format(
        "{}: parallax between the eyes' views ({} apart) {:+.2f} .. {:+.2f} cm = {:+.2f}% .. "
        "{:+.2f}%{}{}; budget {:.2f} cm ({} {:.3g} cm eye separation) ({})",
        where, c.pairViews, c.minParallaxCm, c.maxParallaxCm, 100.0 * c.minParallax,
        100.0 * c.maxParallax, infinity, vergence, c.budget.fraction * p.screen->widthCm,
        c.budget.desktop ? "desktop: half the" : "the", p.screen->interocularCm,
        c.comfortable ? std::string("comfortable") : "uncomfortable: " + c.why);
    return r;
}

namespace {

using Json = nlohmann::ordered_json;  // the fields in the order docs/displays.md lists them

/// A number, or null when it is not finite.
Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

}  // namespace

std::string comfortJson(const Prepared& p, const std::optional<ComfortReport>& range,
                        const std::optional<ScreenComfortReport>& screen) {
    const Rig& rig = p.rig;
    Json j;
    j["rig"] = {{"kind", std::string(rigKindName(rig.kind))},
                {"views", rig.viewCount()},
                {"columns", rig.columns},
                {"rows", rig.rows},
                {"interaxial", number(rig.interaxial)},
                {"convergence", number(rig.convergence)},
                {"separation", number(rig.separation())},
                {"view_cone", number(p.viewConeDegrees)}};
    if (p.viewRange) j["rig"]["view_range"] = {p.viewRange->first, p.viewRange->second};
    j["display"] = p.display ? Json(std::string(p.display->name)) : Json(nullptr);
    bool comfortable = true;
    std::string why;
    if (range) {
        const ParallaxRange& r = range->range;
        j["parallax"] = {{"between", "outer views"},
                         {"min", number(r.minParallax)},
                         {"max", number(r.maxParallax)},
                         {"min_percent", number(100.0 * r.minParallax)},
                         {"max_percent", number(100.0 * r.maxParallax)},
                         {"nearest_distance", number(r.nearestDistance)},
                         {"farthest_distance", number(r.farthestDistance)},
                         {"comfortable", r.comfortable},
                         {"why", r.why},
                         {"text", range->line}};
        comfortable = r.comfortable;
        why = r.why;
    } else {
        j["parallax"] = nullptr;
    }
    if (screen) {
        const ScreenComfort& c = screen->comfort;
        j["screen"] = {
            {"width_cm", number(c.screen.widthCm)},
            {"viewing_distance_cm",
             c.screen.viewingDistanceCm > 0.0f ? number(c.screen.viewingDistanceCm) : Json(nullptr)},
            {"interocular_cm", number(c.screen.interocularCm)},
            {"desktop", c.budget.desktop},
            {"eye_separation", number(c.budget.eyeSeparation)},
            {"budget", number(c.budget.fraction)},
            {"budget_cm", number(c.budget.fraction * c.screen.widthCm)},
            {"pair_views", c.pairViews},
            {"min_parallax", number(c.minParallax)},
            {"max_parallax", number(c.maxParallax)},
            {"min_parallax_cm", number(c.minParallaxCm)},
            {"max_parallax_cm", number(c.maxParallaxCm)},
            {"infinity_parallax", number(c.infinityParallax)},
            {"infinity_parallax_cm", number(c.infinityParallaxCm)},
            {"separation_rule", c.separationRule},
            {"nearest_vergence_deg", number(c.nearestVergenceDeg)},
            {"farthest_vergence_deg", number(c.farthestVergenceDeg)},
            {"screen_vergence_deg", number(c.screenVergenceDeg)},
            {"comfortable", c.comfortable},
            {"why", c.why},
            {"text", screen->line}};
        comfortable = comfortable && c.comfortable;
        if (!c.why.empty()) why += (why.empty() ? "" : "; ") + c.why;
    } else {
        j["screen"] = nullptr;
    }
    j["notes"] = p.notes;
    j["comfortable"] = range ? Json(comfortable) : Json(nullptr);
    j["why"] = why;
    // Invalid UTF-8 in a note or a file name is replaced, not an exception.
    return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::vector<std::string> renderWarnings(const Prepared& p, const RenderOutput& out,
                                        const std::optional<ComfortReport>& range,
                                        const std::optional<ScreenComfortReport>& screen) {
    std::vector<std::string> w;
    // Known only where every view has a depth image or a measured range.
    bool known = true, any = false;
    for (int v = 0; v < p.rig.viewCount() && known && !any; ++v) {
        const std::optional<DepthRange> r = depthRangeOf(out, v);
        known = r.has_value();
        any = r && r->drew();
    }
    if (known && !any) w.push_back("warning: no view drew anything of the scene (empty images)");
    if (screen) {
        const ScreenComfort& c = screen->comfort;
        const float budgetCm = c.budget.fraction * c.screen.widthCm;
        const float worst = std::max(std::abs(c.minParallaxCm), std::abs(c.maxParallaxCm));
        if (worst > 2.0f * budgetCm) {
            w.push_back(fmt::format(
                "warning: separation {:.2f}% is far above the budget: parallax up to {:.2f} cm "
                "between the eyes' views, {:.1f} x the {:.2f} cm budget (try --separation auto)",
                100.0 * p.rig.separation(), worst, worst / budgetCm, budgetCm));
        }
    } else if (range && range->range.why.find("beyond one screen width") != std::string::npos) {
        w.push_back(fmt::format(
            "warning: separation {:.2f}% is far too large: parallax beyond one screen width "
            "between {} (give --screen-width for the budget, or --separation auto)",
            100.0 * p.rig.separation(), p.rig.columns > 2 ? "adjacent views" : "the two views"));
    }
    return w;
}

}  // namespace mvr::session
