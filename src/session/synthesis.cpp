// src/session/synthesis.cpp — --synthesize K: resolveSynthesis() and renderViews()
// (mvr/session/prepare.h); the warp is mvr/core/synthesize.h.
#include <fmt/core.h>

#include "mvr/core/synthesize.h"
#include "mvr/session/prepare.h"

namespace mvr::session {

Status resolveSynthesis(const RenderRecipe& r, Prepared& p) {
    p.synthesize = 1;
    const int k = r.synthesize;
    if (k < 1 || k > kMaxSynthesisStep) {
        return usageError(fmt::format("--synthesize {} is out of range (expected 1..{}; 1: every "
                                      "view exact)",
                                      k, kMaxSynthesisStep));
    }
    if (k == 1) return {};
    if (Status s = checkSynthesisRig(p.rig, fmt::format("--synthesize {}", k)); !s) return s;
    p.synthesize = k;
    if (p.settings.specular == SpecularEye::PerView) {
        p.notes.push_back(fmt::format(
            "note: --synthesize {}: the warped views carry their sources' highlights "
            "(--specular per-view shades the exact views from their eyes)",
            k));
    }
    return {};
}

Result<RenderOutput> renderViews(Backend& backend, const Prepared& p, const Scene& scene,
                                 const Rig& rig, const RenderSettings& settings,
                                 const std::string& method) {
    return renderSynthesized(backend, scene, rig, settings, method, p.synthesize);
}

}  // namespace mvr::session
