// mvr/core/synthesize.h — view synthesis from depth (issue 43, `--synthesize K`): every K-th
// view of a row (and the row's last) is rendered exactly, with its depth; the views between are
// forward-warped from the two exact views around them.
//
// The warp is exact geometry for an off-axis rig (rig.h: every view's clip position is the
// centre camera's sheared, clip.x += s.x · (clip.w − C)): a point at eye-space distance w lands
// in view t at the NDC x of view s plus (s_t − s_s) · (1 − C / w), i.e.
//     Δx = (s_t − s_s) · (1 − C / w) · W / 2   pixels,
// a horizontal shear per pixel (views of one row share their vertical shear, so rows stay rows).
// 1 / w is affine in window depth, so per source pixel a = 1 − C / w is computed once and each
// target view multiplies it by its own factor.
//
// Per target view, the two exact views around it (the nearer first) are warped into it, a
// one-dimensional mesh warp along each row: two adjacent source pixels whose landing points are
// in order and at most two pixels apart are one surface, and the target pixels between them
// take their colour and depth interpolated (a fractional shift resamples; a stretched surface
// leaves no crack); pixels not joined land alone. Nearer depths win; the nearer source keeps
// ties. A target pixel nothing lands on (a disocclusion neither source sees) takes the colour
// and depth of the farther of its row's nearest filled pixels on either side: what a
// disocclusion uncovers is background. Shading in mvr is view-independent (the centre eye's
// specular, lighting.h), so a surface point has one colour in every view: the error is only
// where neither source sees what the target sees, and at resampled edges.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

/// The largest K of --synthesize (rows of 2..kMaxViews views; K ≥ columns − 1 keeps the ends).
inline constexpr int kMaxSynthesisStep = 64;

/// The columns of a row of `columns` views rendered exactly with step `k` (k ≥ 1): 0, k, 2k, …
/// and columns − 1, increasing, without repeats.
std::vector<int> exactColumns(int columns, int k);

/// The views (rig order) rendered exactly with step `k`: exactColumns() of every row.
std::vector<int> exactViews(const Rig& rig, int k);

/// Per view of a rig of `viewCount` views, 1 where `exact` (exactViews()) lists it, else 0.
/// Precondition: every entry of `exact` is in 0..viewCount − 1.
std::vector<char> exactMask(int viewCount, const std::vector<int>& exact);

/// Whether `rig` can be synthesized: an off-axis rig (every view has a clip shear), views laid
/// out as rows × columns, at least 3 columns. Errors: Usage naming `option` ("--synthesize 4")
/// and why.
Status checkSynthesisRig(const Rig& rig, const std::string& option);

/// `rig` with only the views in `views` (indices into rig.views, increasing): one row per row of
/// `rig`, `views.size() / rig.rows` columns. Precondition: the same count in every row.
Rig subRig(const Rig& rig, const std::vector<int>& views);

/// Fills every view of `out` (rig order, rig.viewCount() colour and depth images of one size)
/// that `exact` does not list, from the views it lists, as the header says. `exact` must hold
/// each row's first and last column. Errors: Usage for a rig checkSynthesisRig() refuses,
/// Internal for sizes that do not match.
Status synthesizeViews(const Rig& rig, const std::vector<int>& exact, RenderOutput& out,
                       int threads = 0);

/// Warps one view into others of its row (`mvr compose --from-rgbd`): `color`, per pixel an
/// order depth `depth` (nearer smaller, below 1; 1 and above is background, as window depth)
/// and the parallax factor a = 1 − C / w (`factor`, one per pixel), into one view per entry of
/// `shears` (each target's clip shear minus the source's), by the one-source form of the warp
/// above: holes take the farther of their row's nearest filled pixels. Errors: Internal for
/// sizes that do not match.
Result<std::vector<Image>> warpFromView(const Image& color, const DepthImage& depth,
                                        std::span<const float> factor,
                                        std::span<const float> shears,
                                        float maxStretch = 2.0f, int threads = 0);

/// Renders `rig` with `backend` as --synthesize `k` does: the exact views as one render (the
/// sub-rig of exactViews(), with depth), the others synthesized; the output holds every view of
/// `rig` in order with its depth. k == 1 is a plain render. Errors: the backend's, and
/// checkSynthesisRig()'s.
Result<RenderOutput> renderSynthesized(Backend& backend, const Scene& scene, const Rig& rig,
                                       const RenderSettings& settings, const std::string& method,
                                       int k);

/// renderSynthesized() into `out`, reusing its images as Backend::renderInto() does (frame
/// after frame: no allocation); k <= 1 is backend.renderInto().
Status renderSynthesizedInto(Backend& backend, const Scene& scene, const Rig& rig,
                             const RenderSettings& settings, const std::string& method, int k,
                             RenderOutput& out);

}  // namespace mvr
