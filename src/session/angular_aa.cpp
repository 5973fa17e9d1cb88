// src/session/angular_aa.cpp — --angular-aa: resolveAngularAA() (mvr/session/prepare.h) and the
// surfaces that carry it (mvr/session/surfaces.h); the filter is mvr/core/angular_aa.h.
#include <charconv>
#include <cmath>
#include <string>

#include <fmt/core.h>

#include "mvr/session/prepare.h"
#include "mvr/session/surfaces.h"

namespace mvr::session {

namespace {

constexpr double kMaxScale = 100.0;

// "auto", "off" or a scale 0 < S <= kMaxScale: the scale (0: off, -1: auto).
Result<double> parseScale(const std::string& text) {
    if (text == "off") return 0.0;
    if (text == "auto") return -1.0;
    double scale = 0.0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, scale);
    if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(scale) || scale <= 0.0 ||
        scale > kMaxScale) {
        return usageError(fmt::format(
            "--angular-aa {}: expected auto, off or a scale 0 < S <= {:g}", text, kMaxScale));
    }
    return scale;
}

}  // namespace

Status resolveAngularAA(const RenderRecipe& r, Prepared& p) {
    const std::string& text = r.surfaces.angularAA;
    p.angularAA = 0.0f;
    p.angularAAShears.clear();
    auto scale = parseScale(text);
    if (!scale) return scale.status();
    if (*scale == 0.0) return {};
    const Rig& rig = p.rig;
    const bool severalViews = rig.columns * rig.rows > 1;
    const bool sheared = !rig.views.empty() && rig.views.front().clipShear.has_value();
    if (*scale < 0.0) {  // auto: a multi-view display's render only
        const bool display =
            (p.display && p.display->viewConeDegrees > 0.0f) || p.viewConeDegrees > 0.0f;
        if (!display || !severalViews || !sheared) return {};
        *scale = 1.0;
    }
    if (!severalViews) {
        return usageError(fmt::format(
            "--angular-aa {}: needs more than one view (the kernel is the parallax step between "
            "adjacent views)",
            text));
    }
    if (!sheared) {
        return usageError(fmt::format(
            "--angular-aa {}: needs an off-axis rig (--rig {} has no clip shears to take the "
            "step between adjacent views from)",
            text, rig.screen ? "screen" : rigKindName(rig.kind)));
    }
    p.angularAA = float(*scale);
    p.settings.depth = true;
    for (const View& v : rig.views) p.angularAAShears.push_back(*v.clipShear);
    return {};
}

Result<StereoSurfaces> buildSurfaces(const RenderRecipe& recipe, const Prepared& prepared) {
    auto s = buildSurfaces(recipe, prepared.exposureScale, prepared.scene.tonemap);
    if (!s) return s;
    s->angularAA = prepared.angularAA;
    s->angularAAOptional = recipe.surfaces.angularAA == "auto";
    s->angularAAShears = prepared.angularAAShears;
    return s;
}

}  // namespace mvr::session
