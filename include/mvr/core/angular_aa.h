// mvr/core/angular_aa.h — angular anti-aliasing for multi-view displays: a depth-dependent
// prefilter of each rendered view (Zwicker, Matusik, Durand, Pfister, "Antialiasing for
// Automultiscopic 3D Displays", EGSR 2006).
//
// A display that shows N views samples the light field in angle as well as in space: a point
// whose image moves by more than a pixel between adjacent views jumps from view to view
// (angular aliasing: edges behind or in front of the focal plane shimmer as the viewer moves).
// Zwicker et al. band-limit each point in proportion to its parallax step between adjacent
// views. mvr does that after rendering, on the CPU, per view:
//
//   for the pixel's eye-space distance w (its window depth through the view's projection,
//   eyeDistance(), stereo_surfaces.h), the parallax step between adjacent views in pixels is
//       step_x(w) = W / 2 · Δs_x · |1 − convergence / w|      (W: the image width)
//   where Δs_x is the difference of clip shears (rig.h: View::clipShear = offset / a) between
//   the view and its horizontal neighbours (the mean of the gaps to the nearest view on each
//   side with the same vertical shear; a view-cone rig's gaps differ per view). The kernel is
//   a box of width
//       k_x(w) = max(0, step_x(w) − 1) · S                      (S: the scale, > 0)
//   pixels: nothing within a pixel step of the focal plane (convergence) changes. For a grid,
//   a second pass does the same vertically (H, Δs_y) on the result.
//
// The filter (one row or column, pixel j covering [j, j + 1), centre c_j = j + ½): the output
// of pixel x is the mean of the input over [c_x − k_x / 2, c_x + k_x / 2], each pixel j
// weighted by its overlap with that interval — the exact box integral of the piecewise-constant
// row, so a step edge on a plane of constant depth becomes a linear ramp k pixels wide — except
// that a neighbour j takes part only when its own kernel reaches pixel x
// (|c_j − c_x| < k_j / 2 + ½): a sharp surface near the focal plane is not smeared into a
// blurred one behind it, and a focal-plane pixel (k = 0) keeps its value exactly. The weights
// are renormalised over the pixels that take part. All four channels are filtered (straight,
// not premultiplied: alpha is 255 until a transparent background is applied, after this).
// Depth is left as it was. Kernels are capped at the image's extent. Background pixels
// (depth 1, nothing drawn) lie at the far plane.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

/// The clip-shear step between `view` and its adjacent views: x along its row (views with the
/// same clipShear.y), y along its column (views with the same clipShear.x); each the mean of
/// the gaps to the nearest view on either side. The neighbours are looked up among `shears`,
/// the clip shears of the whole rig when `rig` holds only some of its views (--view-range, a
/// rank's share: their pixels stay the whole render's); empty: the rig's own views. Without a
/// neighbour: 2·interaxial / screenWidth (x, when rig.columns > 1) and
/// interaxialY / (convergence · tan(fovY / 2)) (y, when rig.rows > 1); else 0.
/// Precondition: every view has a clip shear (off-axis rigs).
glm::vec2 adjacentShearStep(const Rig& rig, int view, std::span<const glm::vec2> shears = {});

/// The kernel width in pixels for a point at eye-space distance `distance` (world units),
/// shear step `shearStep` (adjacentShearStep()), image extent `extentPx` along the step's axis:
/// max(0, extentPx / 2 · shearStep · |1 − convergence / distance| − 1) · scale.
float angularKernelWidth(float shearStep, int extentPx, float convergence, float distance,
                         float scale);

/// Filters every view of `color` in place with its depth image (see the top of this file).
/// `scale` > 0. Errors: Unsupported when `depth` is empty ("angular anti-aliasing needs a
/// depth buffer") or a view has no clip shear ("needs an off-axis rig"); Usage for a scale
/// that is not finite and > 0 or sizes that do not match.
Status applyAngularAA(const Rig& rig, std::vector<Image>& color,
                      const std::vector<DepthImage>& depth, float scale,
                      std::span<const glm::vec2> shears = {});

}  // namespace mvr
