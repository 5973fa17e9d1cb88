// mvr/session/sampling.h — `--aa N` (Python aa=): the samples a pixel a render takes (issue 38;
// mvr/core/antialias.h renders and resolves them) (library mvr::session).
//
// 1, 2, 4 or 8. Default: 4 for the light-field display presets (a --display with a view cone:
// their small views alias, and edges away from the focal plane flicker between views), 1
// otherwise — plain renders and the papers' benches keep one sample unless asked.
#pragma once

#include "mvr/core/status.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// The default of a light-field display preset.
inline constexpr int kDisplaySamples = 4;

/// Sets prepared.settings.samples from recipe.aa, else the default above (prepared.display
/// known). Errors (ErrorCode::Usage, one line): a count other than 1, 2, 4, 8.
Status applySampling(const RenderRecipe& recipe, Prepared& prepared);

}  // namespace mvr::session
