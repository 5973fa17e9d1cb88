// sampling.cpp — `--aa N` (mvr/session/sampling.h).
#include "mvr/session/sampling.h"

#include <fmt/core.h>

#include "mvr/core/antialias.h"

namespace mvr::session {

Status applySampling(const RenderRecipe& r, Prepared& p) {
    if (r.aa) {
        if (!validSampleCount(*r.aa)) {
            return usageError(fmt::format(
                "--aa {}: expected 1, 2, 4 or 8 samples a pixel", *r.aa));
        }
        p.settings.samples = *r.aa;
        return {};
    }
    const bool lightField = p.display && p.display->viewConeDegrees > 0.0f;
    p.settings.samples = lightField ? kDisplaySamples : 1;
    return {};
}

}  // namespace mvr::session
