// mvr/session/surfaces.h — a recipe's surfaces drawn after the scene (library mvr::session;
// mvr/core/stereo_surfaces.h): --sky, --floating-window, --letterbox, --label, --label-anchor.
#pragma once

#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"
#include "mvr/core/stereo_surfaces.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// The surfaces of a recipe, parsed (the sky map loaded, the labels parsed). A high-dynamic-
/// range sky (.hdr, .exr) is shown at `hdrScale` (2^EV) through `tonemap`, as lit colours are
/// (loadSky). "environment" is the RenderRecipe overload's (a SurfaceRecipe has no map): here
/// it is a file name like any other.
Result<StereoSurfaces> buildSurfaces(const SurfaceRecipe& recipe, float hdrScale = 1.0f,
                                     Tonemap tonemap = Tonemap::None);
/// The same, with the recipe's --background transparent (refused beside the surfaces that paint
/// the background: --sky, --letterbox, --floating-window, labels). `--sky environment` shows the
/// recipe's --environment map (an error without one).
Result<StereoSurfaces> buildSurfaces(const RenderRecipe& recipe, float hdrScale = 1.0f,
                                     Tonemap tonemap = Tonemap::None);
/// The same, with the prepared render's angular anti-aliasing (Prepared::angularAA, applied by
/// applySurfaces() after the sky: mvr/core/angular_aa.h). Every render of a recipe builds its
/// surfaces this way, so that every backend's views are filtered alike. An HDR sky is exposed
/// and tone mapped as the prepared scene is (Prepared::exposureScale, Scene::tonemap).
Result<StereoSurfaces> buildSurfaces(const RenderRecipe& recipe, const Prepared& prepared);

/// Whether a --background value asks for a transparent background ("transparent").
bool isTransparentBackground(const std::string& background);
/// applyStereoSurfaces() without the strips; nothing asked: nothing done.
Status applySurfaces(const StereoSurfaces& surfaces, const Rig& rig, RenderOutput& out);

}  // namespace mvr::session
