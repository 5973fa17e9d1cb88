// mvr/session/rgbd_input.h — RGB-D in, views out (issue 43 item 3, `mvr compose IMAGE
// --from-rgbd --display NAME`): a colour picture and its depth map become a light-field
// display's views by the warp of --synthesize (mvr/core/synthesize.h), from the one view.
//
// The depth map is grey, white = near (Looking Glass's convention, mvr/composite/rgbd.h;
// a sidecar's `depth_inversion` 1 says white = far). What a grey g in 0..1 means:
//   - mvr's own RGB-D (`mvr render --format rgbd` beside its rgbd.json, whose "mvr" block
//     holds near, far, convergence and fov_y_degrees): the eye-space distance
//         w = far − g · (far − near),
//     the views are the display's view-cone rig around that camera (makeRig(): the same rig
//     `mvr render --display NAME` renders), and a pixel moves by the exact off-axis parallax
//     (s_t · (1 − C / w) · W / 2 pixels, C the convergence moved by --focus · (far − near));
//   - any other depth map (a phone's portrait mode, a depth estimator): g is taken as
//     disparity (1 / w linear in g, which is what those write), from twice the focal
//     distance at g = 0 to two thirds of it at g = 1 — the span `--convergence auto` balances,
//     the focal plane at their harmonic mean — so a = 1 − C / w = 0.5 + focus − g, on the
//     display's rig for mvr's default camera (45° vertical field of view).
// --depthiness scales the views' spread (every parallax) as on the view-cone rig.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/displays.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::session {

/// An RGB-D picture as read.
struct RgbdInput {
    Image colour;
    std::vector<float> grey;  ///< colour's size, 0..1, white (1) = near
    /// The sidecar (FILE.json beside FILE.png) when there is one.
    std::string sidecar;
    /// From an mvr sidecar's "mvr" block: the distances' range and the camera.
    bool measured = false;
    double near = 0.0, far = 0.0, convergence = 0.0, fovYDegrees = 0.0;
    /// Bridge's settings from the sidecar, when it has them.
    std::optional<double> depthiness, focus;
};

/// Reads an RGB-D picture: one file holding colour and depth side by side (`position`, or the
/// sidecar's depth_loc, else right), or two files, colour then depth (a depth map of another
/// size but the colour's aspect is area-resampled to the colour's size). Errors: Input naming
/// the file (unreadable, sizes, a malformed sidecar), Usage for a file count other than 1 or 2.
Result<RgbdInput> readRgbdInput(const std::vector<std::string>& files,
                                std::optional<composite::DepthPosition> position);

/// Looking Glass's two settings for `input`: the caller's (the command line's, Python's
/// keywords) where given, else a foreign picture's sidecar's, else 1 and 0. An mvr sidecar's
/// settings are not taken: its camera already holds the render's focal plane.
struct RgbdLook {
    double depthiness = 1.0, focus = 0.0;
};
RgbdLook rgbdLook(const RgbdInput& input, std::optional<double> depthiness,
                  std::optional<double> focus);

/// The display's views (view 0 leftmost) from `input`, as the header says: the picture
/// cropped about its centre to the display's aspect and resampled (area average) to its view
/// size when it is not that size already. Errors: Usage for a display without a view cone.
Result<std::vector<Image>> viewsFromRgbd(const RgbdInput& input, const DisplayPreset& display,
                                         double depthiness, double focus, int threads = 0);

}  // namespace mvr::session
