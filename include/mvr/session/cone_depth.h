// mvr/session/cone_depth.h — `--depthiness` and `--focus` on the view-cone rig (issue 42;
// Python depthiness=, focus=) (library mvr::session).
//
// Looking Glass's tools give a light-field render two controls besides the cone. mvr takes
// them in the units and ranges of Bridge's RGB-D settings (docs/displays.md), which the same
// options also write to `--format rgbd`'s sidecar:
// - depthiness D (0 .. 2, default 1): the views' spread about the centre camera scaled by D
//   (RigParams::coneSpread), the "depth separation factor" of Looking Glass's WebXR library:
//   every parallax scales with D, 0 gives identical views. (The sidecar keeps Bridge's
//   0.1 .. 2: a 0 with --format rgbd is refused.)
// - focus F (−0.05 .. 0.05, default 0): the focal (zero-parallax) plane moved toward the
//   viewer by F of the scene's depth, taken as its bounding box's diagonal (2 · radius, the
//   span an RGB-D depth map normalises to at most): convergence − F · 2R.
// Without a view cone and without --format rgbd they are ignored with a warning.
#pragma once

#include <string>
#include <vector>

#include "mvr/core/framing.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// Sets params.viewConeDegrees to `cone` (0: none) and, where the recipe gave them, the
/// spread and the focus shift above; adds the warning to `notes`. Errors (ErrorCode::Usage,
/// one line): depthiness below 0.1 with --format rgbd.
Status applyConeDepth(const RenderRecipe& recipe, const Scene& scene, double cone,
                      FramingParams& params, std::vector<std::string>& notes);

}  // namespace mvr::session
