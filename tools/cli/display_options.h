// tools/cli/display_options.h — helpers of issue 13 used by SceneOptions::prepare(): the views
// that see nothing of the scene, and the depth pre-pass of --convergence/--separation auto.
#pragma once

#include <optional>
#include <vector>

#include "mvr/core/displays.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"

namespace mvr::cli {

/// The views whose frustum the scene's bounding sphere lies entirely outside of.
std::vector<int> viewsMissingScene(const Scene& scene, const Rig& rig);

/// Renders the depth of `camera` alone (at most 256 pixels across, on the registry's first
/// backend) and returns the 1st / 99th percentile distances of what it hit; none when it hit
/// nothing or the backend gives no depth.
Result<std::optional<DepthPercentiles>> centreDepthPrepass(const Scene& scene, const Camera& camera,
                                                           const RenderSettings& settings);

}  // namespace mvr::cli
