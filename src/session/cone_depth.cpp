// cone_depth.cpp — --depthiness and --focus on the view-cone rig (mvr/session/cone_depth.h).
#include "mvr/session/cone_depth.h"

#include <algorithm>

#include <fmt/core.h>

namespace mvr::session {

Status applyConeDepth(const RenderRecipe& r, const Scene& scene, double cone,
                      FramingParams& params, std::vector<std::string>& notes) {
    auto given = [&](const char* name) { return r.gave(name); };
    const bool rgbd = std::find(r.outputs.formats.begin(), r.outputs.formats.end(), "rgbd") !=
                      r.outputs.formats.end();
    const double depthiness = r.outputs.compose.depthiness, focus = r.outputs.compose.focus;
    if (given("--depthiness") && rgbd && depthiness < 0.1) {
        return usageError(fmt::format(
            "--depthiness {}: the RGB-D sidecar takes Bridge's 0.1 .. 2 (0 .. 2 on a view cone "
            "without --format rgbd)", depthiness));
    }
    params.viewConeDegrees = float(cone);
    for (const char* name : {"--depthiness", "--focus"}) {
        if (given(name) && cone <= 0.0 && !rgbd) {
            notes.push_back(fmt::format(
                "warning: {} is ignored without an RGB-D image (--format rgbd) or a view cone "
                "(--view-cone, a light-field --display)", name));
        }
    }
    if (cone <= 0.0) return {};
    if (given("--depthiness")) params.coneSpread = float(depthiness);
    if (given("--focus")) params.focusShift = float(focus * 2.0 * scene.bounds().radius());
    return {};
}

}  // namespace mvr::session
