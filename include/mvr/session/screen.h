// mvr/session/screen.h — `--rig screen`'s options (RenderRecipe::screen) as the screen and eyes
// of mvr/core/screen_rig.h, and the rig placed around a framed scene.
#pragma once

#include <optional>
#include <string>

#include "mvr/core/screen_rig.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// The screen and eyes `r.screen` gives (defaults in ScreenRecipe), for views of `viewAspect`
/// (width / height). Errors: Usage naming the option and its value (a malformed or
/// out-of-range number, both --eyes and --head / --ipd-mm, corners that are no rectangle, an
/// eye behind the screen).
Result<ScreenEyes> screenEyesOf(const RenderRecipe& r, float viewAspect);

/// The warning that views of `width` x `height` pixels stretch onto `screen` (their aspect is
/// not the screen's, by more than 1 %), with the --size that keeps the pixels square; none
/// when the aspects agree.
std::optional<std::string> screenStretchNote(const ScreenCorners& screen, int width, int height);

/// Refuses what `--rig screen` cannot take: other than two views, --view-grid, --view-cone,
/// --interaxial / --separation (auto or not; the eyes give the spacing), and screen options
/// without `--rig screen`. Usage errors naming the option.
Status checkScreenOptions(const RenderRecipe& r, int views);

}  // namespace mvr::session
