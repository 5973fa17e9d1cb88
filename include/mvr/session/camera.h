// mvr/session/camera.h — a recipe's viewpoint, focal length and background (library
// mvr::session; the CameraRecipe of mvr/session/recipe.h).
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "mvr/core/framing.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// The centre camera's viewpoint the recipe gives, or nullopt when it gives none.
/// Orbit-style: the eye at `distance` (default: fitDistance()) from the target (default: the
/// bounds' centre) in the direction (sin az cos el, sin el, cos az cos el): azimuth 0 looks
/// from +Z as the default framing does, 90 from +X; straight above or below, up is away from
/// the azimuth's side. Matrix: the eye its translation, the view along its -Z, up its +Y, the
/// target at the bounds' centre's depth. Errors: Usage naming the option and the value; a
/// matrix file that is not one: Input.
Result<std::optional<Viewpoint>> viewpointOf(const CameraRecipe& camera, const Scene& scene,
                                             float fovYDegrees, float aspect);

/// The vertical field of view (degrees) of a lens of focalLengthMm on a sensor sensorWidthMm
/// wide (the horizontal field of view), at `aspect`; nullopt without a focal length.
Result<std::optional<double>> fovFromFocalLength(const CameraRecipe& camera, double aspect);

/// "X,Y,Z" (commas or spaces; |each| ≤ 1e15). Errors: Usage naming `option` and the value.
Result<glm::vec3> vec3Of(const std::string& value, const std::string& option);

/// "R,G,B" in [0, 1] or "#RRGGBB" as a linear colour; nullopt for "".
Result<std::optional<glm::vec3>> backgroundOf(const std::string& text);

}  // namespace mvr::session
