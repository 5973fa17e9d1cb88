// mvr/composite/rgbd.h — Looking Glass RGB-D images (format "rgbd"): one view's colour and its
// depth side by side, as Looking Glass Bridge, Studio and the Blender add-on read them, and the
// sidecar JSON holding Bridge's `rgbd` settings.
//
// Bridge's settings (bridge.js, src/library/schemas/schema.hologram.ts and defaults.ts, the
// `RGBDHologramArgs` of `@lookingglass/bridge`; docs/displays.md cites them):
//   depth_loc        where the depth image lies: 0 top, 1 bottom, 2 right, 3 left
//   depth_inversion  0: white is near (Looking Glass's depth maps), 1: white is far
//   chroma_depth     0: a grey depth map, 1: a colour-coded one
//   depthiness       how deep the image is shown, 0.1 .. 2
//   focus            which depth is on the panel's plane, -0.05 .. 0.05 (0: Bridge's default)
//   zoom             0.1 .. 2
//   aspect           width / height of the colour image (not of the pair)
// mvr writes grey depth, white = near (depth_inversion 0, chroma_depth 0).
//
// The depth image (rgbdDepthImage()): linear in the eye-space distance d along the view axis
// between `near` and `far` (`mvr render`: the nearest and farthest distance drawn in the view,
// so the scene spans the 8 bits): grey g = round(255 · (far − d) / (far − near)), clamped;
// pixels where nothing was drawn are 0 (black, as far as can be). A reader decodes
//     d = far − g / 255 · (far − near),
// within (far − near) / 510 of the distance rendered. The sidecar records near and far.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::composite {

/// Parses right | left | top | bottom. Errors (ErrorCode::Usage): "--rgbd-depth-position
/// TEXT: expected right, left, top or bottom".
Result<DepthPosition> parseDepthPosition(std::string_view text);
/// "right", "left", "top", "bottom".
std::string_view depthPositionName(DepthPosition position);
/// Bridge's depth_loc of a position: top 0, bottom 1, right 2, left 3.
int bridgeDepthLoc(DepthPosition position);

/// The grey depth image (RGB = g, alpha 255) of `distances` (width · height eye-space distances
/// along the view axis, +inf where nothing was drawn), white = near; see the header.
/// Precondition: distances.size() == width · height, 0 < near < far.
Image rgbdDepthImage(std::span<const float> distances, int width, int height, double near,
                     double far);

/// The rgbd composer: views = {colour, depth image} of the same size (already checked);
/// the depth image is copied beside the colour at options.rgbdDepth. options.swapEyes does
/// not reorder the two (they are no pair of eyes).
Result<Image> composeRgbd(std::span<const Image> views, const ComposeOptions& options,
                          const std::string& who);

/// What the sidecar says besides Bridge's settings.
struct RgbdSidecar {
    std::string image;  ///< the RGB-D image's file name ("rgbd.png")
    int width = 0, height = 0;  ///< of the colour image
    double near = 0.0, far = 0.0;  ///< the depth image's range (world units)
    int view = 0;  ///< the rig's view it shows
    /// The camera (`mvr compose --from-rgbd` rebuilds a display's views around it): the
    /// zero-parallax distance and the vertical field of view, degrees. 0: not written.
    double convergence = 0.0, fovYDegrees = 0.0;
};

/// The sidecar JSON (rgbd.json): {"type": "rgbd", "uri": IMAGE, "settings": {Bridge's rgbd
/// fields}, "mvr": {"view", "near", "far", "convergence", "fov_y_degrees", "depth": the
/// decoding formula}} (convergence and fov_y_degrees only when known). "uri" and
/// "settings" are the arguments of bridge.js's `RGBDHologram`.
std::string rgbdSidecarJson(const ComposeOptions& options, const RgbdSidecar& sidecar);

}  // namespace mvr::composite
