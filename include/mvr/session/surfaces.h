// mvr/session/surfaces.h — a recipe's surfaces drawn after the scene (library mvr::session;
// mvr/core/stereo_surfaces.h): --sky, --floating-window, --letterbox, --label, --label-anchor.
#pragma once

#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// The surfaces of a recipe, parsed (the sky map loaded, the labels parsed).
Result<StereoSurfaces> buildSurfaces(const SurfaceRecipe& recipe);
/// applyStereoSurfaces() without the strips; nothing asked: nothing done.
Status applySurfaces(const StereoSurfaces& surfaces, const Rig& rig, RenderOutput& out);

}  // namespace mvr::session
