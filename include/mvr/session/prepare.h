// mvr/session/prepare.h — a RenderRecipe made ready to render (library mvr::session): the scene
// (models placed and combined, a named scene, exposure, billboards), the rig (views, display
// preset, spacing including --convergence auto / --separation auto through a depth pre-pass on
// the registry's first backend), the settings, the outputs a display preset adds, and the
// reports `mvr render` prints after rendering (parallax, screen comfort, its JSON, warnings).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/animation.h"
#include "mvr/core/displays.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/session/recipe.h"
#include "mvr/session/screen.h"

namespace mvr::session {

/// What a render writes (RenderRecipe::outputs.write, `--write`), each kind of file on or off.
/// Without --write: a still writes its views and composites (anaglyph.png for a pair, the
/// formats' files); a display preset only its composite (the quilt; the views on request); a
/// sequence with a video only the video. depth-N.png and cameras.json when asked for.
struct WriteSet {
    bool views = true;       ///< view-N.png
    bool depth = false;      ///< depth-N.png
    bool composites = true;  ///< anaglyph.png for a pair and the formats' files
    bool cameras = false;    ///< cameras.json
    bool video = false;      ///< a sequence's video (sequence.video)
};

/// "warning: --X is ignored ..." for each option in recipe.given that the recipe ignores
/// (--shadow-map-size without --shadows, --fps or --threads without a sequence, the lenticular
/// calibration without a lenticular image, ...). `formats`: the formats written, a display
/// preset's included.
std::vector<std::string> ignoredOptionWarnings(const RenderRecipe& recipe,
                                               const std::vector<std::string>& formats);

/// The WriteSet of a recipe (`display`: a display preset is in use). Errors (ErrorCode::Usage):
/// an unknown or empty word in --write, video without --video FILE, --video FILE with a --write
/// that leaves it out.
Result<WriteSet> writeSetOf(const RenderRecipe& recipe, bool display);

/// A scene, rig and settings ready to render.
struct Prepared {
    Scene scene;
    Rig rig;
    RenderSettings settings;
    std::string sceneName;                 ///< "default scene" or the model file names
    std::optional<DisplayPreset> display;  ///< the recipe's display preset
    std::optional<ScreenGeometry> screen;  ///< screenWidthCm (and viewingDistanceCm)
    float viewConeDegrees = 0.0f;          ///< the rig's view cone (0: none)
    /// One-line notes: what --convergence auto / --separation auto chose ("note: …") and
    /// warnings ("warning: …", e.g. views that see nothing of the scene).
    std::vector<std::string> notes;
    /// 2^EV of --exposure (1 without): the lights', the environment's and an HDR sky's scale.
    float exposureScale = 1.0f;
    /// The model file's animation (glTF's first), played by sequences (docs/animation.md);
    /// cameraNode is -1 when the file camera is not the rig's (noFileCamera, grid).
    std::optional<SceneAnimation> animation;
    /// The recipe's formats and composite options plus what its display preset adds
    /// (displayOutputs()).
    std::vector<std::string> formats;
    composite::ComposeOptions compose;
    PngCompression png = PngCompression::Fast;  ///< the recipe's outputs.pngCompression
    WriteSet write;  ///< what is written (writeSetOf())
    bool depthExr = false;  ///< the recipe's outputs.depthFormat is exr
    /// --view-range A:B: the rig holds views A..B of the whole rig (view_range.h); none: all.
    std::optional<std::pair<int, int>> viewRange;
    /// --rig screen's --eye-track: the eyes of each frame (FrameStepper); the rig has frame 0's.
    std::shared_ptr<const EyeTrack> eyeTrack;
    /// Angular anti-aliasing's scale (recipe.surfaces.angularAA resolved; 0: off): the surfaces
    /// built with buildSurfaces(recipe, prepared) apply it (surfaces.h).
    float angularAA = 0.0f;
    /// --synthesize K (1: off), checked against the rig; render through renderViews().
    int synthesize = 1;
    /// The whole rig's clip shears (before --view-range cuts it): each view's neighbours.
    std::vector<glm::vec2> angularAAShears;
};

/// Where prepare() sends the warnings of loading models ("warning: ..."), as they happen.
/// Default (none given): stderr, one line each.
using WarningSink = std::function<void(const std::string&)>;

/// Loads the models (or the named scene), builds the rig and settings; validates everything,
/// every format to write included: each takes the rig's views at their size (outputSize()), so
/// that a render fails before it writes anything ("--format jps: needs 2 views (got 4)"; only
/// when the recipe writes files or names formats).
/// Errors: ErrorCode::Usage for bad values (the message names the `mvr render` option), Input
/// for unreadable models, the backends' errors for the depth pre-pass.
Result<Prepared> prepare(const RenderRecipe& recipe, const WarningSink& warn = {});

/// Resolves --angular-aa (recipe.surfaces.angularAA) into `prepared.angularAA` and asks the
/// backend for depth when it is on (`settings.depth`; the depth files stay as `write` says).
/// "auto": scale 1 when the render is for a multi-view display — a --display preset with a
/// view cone, or a view cone (--view-cone, a calibration's) — on an off-axis rig of more than
/// one view; off otherwise (plain renders, stereo pairs, the benches). "off": 0. A number: that
/// scale, 0 < S <= 100. Errors (ErrorCode::Usage, naming the option and value): anything else,
/// a scale with one view (no adjacent view: no kernel), or with a rig whose views have no clip
/// shear (--rig toein, parallel, screen).
Status resolveAngularAA(const RenderRecipe& recipe, Prepared& prepared);

/// Checks --synthesize K (1..kMaxSynthesisStep; above 1 an off-axis rig of rows of at least 3
/// views: checkSynthesisRig()) into `prepared.synthesize`. Errors: Usage naming the option.
Status resolveSynthesis(const RenderRecipe& recipe, Prepared& prepared);

/// The render of a prepared recipe's views: `backend.render()`, or with --synthesize K the
/// exact views and the warped others (renderSynthesized()). `scene` and `rig` are the frame's
/// (a sequence moves them); the settings and K are `prepared`'s.
Result<RenderOutput> renderViews(Backend& backend, const Prepared& prepared, const Scene& scene,
                                 const Rig& rig, const RenderSettings& settings,
                                 const std::string& method);

/// Parses "WxH" (both 1..16384). Errors: ErrorCode::Usage, naming `what` ("--size").
Result<std::pair<int, int>> parseSize(const std::string& text, const char* what);

/// A display preset's outputs: its format (if not already asked for), the quilt grid unless
/// `quiltGiven` (or the view count changed: then the most square quilt), the quilt name's aspect
/// (the camera's: `cameraAspect`), and lenticular when a calibration was given (its panel size
/// unless the calibration names one).
void displayOutputs(const DisplayPreset& d, bool calibrationGiven, bool quiltGiven,
                    float cameraAspect, std::vector<std::string>& formats,
                    composite::ComposeOptions& compose);

/// The views whose frustum the scene's bounding sphere lies entirely outside of.
std::vector<int> viewsMissingScene(const Scene& scene, const Rig& rig);

/// Renders the depth of `camera` alone (at most 256 pixels across, on the registry's first
/// backend) and returns the 1st / 99th percentile distances of what it hit; none when it hit
/// nothing or the backend gives no depth.
Result<std::optional<DepthPercentiles>> centreDepthPrepass(const Scene& scene, const Camera& camera,
                                                           const RenderSettings& settings);

// ---- the reports after a render ----------------------------------------------------------------

/// The parallax between the outer views over the depth range view 0 saw, and its line. None for
/// one column of views, without depth, or when nothing was drawn.
struct ComfortReport {
    ParallaxRange range;
    std::string line;  ///< "parallax between outer views: ... (comfortable: ...)", no newline
};
std::optional<ComfortReport> comfortReport(const Rig& rig, const RenderOutput& out);

/// The comfort report against the screen (screenWidthCm / viewingDistanceCm), after
/// comfortReport(): the parallax between the views the eyes see in cm and degrees of vergence
/// against the interocular budget (displays.h), and its line.
struct ScreenComfortReport {
    ScreenComfort comfort;
    std::string line;  ///< "on a 12 cm screen at 40 cm: ... (comfortable | uncomfortable: why)"
};
std::optional<ScreenComfortReport> screenComfortReport(const Prepared& p,
                                                       const std::optional<ComfortReport>& range);
/// The comfort report as JSON (`mvr render --report-json`; fields in docs/displays.md).
std::string comfortJson(const Prepared& p, const std::optional<ComfortReport>& range,
                        const std::optional<ScreenComfortReport>& screen);
/// Warnings after a render ("warning: ..."): no view drew anything; parallax far above the
/// budget (twice it with a screen, one screen width without).
std::vector<std::string> renderWarnings(const Prepared& p, const RenderOutput& out,
                                        const std::optional<ComfortReport>& range,
                                        const std::optional<ScreenComfortReport>& screen);

}  // namespace mvr::session
