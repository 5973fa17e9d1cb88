// mvr/core/displays.h — what a real display needs (issue 13, docs/displays.md): the device
// presets (`--display NAME`: views, quilt, view size, picture aspect, view cone, panel, output
// format), comfort measured against a physical screen (parallax in cm and degrees of vergence
// against the 6.5 cm interocular budget, nvidia-gtc2010 "Eye Separation" … "Parallax Budget")
// and the rules `--convergence auto` / `--separation auto` choose by.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

/// One display a preset renders for. Light-field panels take a quilt of `views` tiles
/// (`quiltColumns` × `quiltRows`, view 0 bottom left) of `quiltWidth` × `quiltHeight` pixels;
/// stereo displays take two views composed as `format`.
struct DisplayPreset {
    std::string_view name;                ///< the --display name, e.g. "portrait"
    std::string_view description;         ///< e.g. "Looking Glass Portrait"
    int views = 2;                        ///< a row of this many views
    int quiltColumns = 0, quiltRows = 0;  ///< 0 for stereo displays
    int quiltWidth = 0, quiltHeight = 0;  ///< the whole quilt, pixels (0 for stereo displays)
    int viewWidth = 0, viewHeight = 0;    ///< one view, pixels (the quilt's tile)
    /// Width / height of the picture one view shows on the panel (the quilt name's aspect, the
    /// camera's aspect). It may differ from viewWidth / viewHeight: the panel stretches the tile.
    float aspect = 1.0f;
    float viewConeDegrees = 0.0f;  ///< total view cone (0: a stereo pair spaced by interaxial)
    int panelWidth = 0, panelHeight = 0;  ///< the panel's native resolution
    std::string_view format;  ///< the compose format it takes: quilt, hdmi-frame-packing, …
    std::string_view source;  ///< where the figures come from (docs/displays.md cites them)
    /// An eye-tracked stereo monitor (Samsung Odyssey 3D, Acer SpatialLabs, Sony's Spatial
    /// Reality Display): its picture in mm, rendered with `--rig screen` (mvr/core/screen_rig.h)
    /// unless another rig is asked for; 0 for other displays.
    float screenWidthMm = 0.0f, screenHeightMm = 0.0f;
    /// The panel leaning back, degrees (Sony's stands: 45): screenOfSize()'s tilt.
    float screenTiltDegrees = 0.0f;
    bool tracked() const { return screenWidthMm > 0.0f; }
};

/// All presets, in `mvr info --displays` order.
std::span<const DisplayPreset> displayPresets();
std::vector<std::string> displayNames();
/// The preset called `name`. Errors: ErrorCode::Usage listing the valid names.
Result<DisplayPreset> findDisplay(std::string_view name);
/// The per-view aspect as the quilt name writes it (`_qsCxRaA`): "0.75", "1.7778".
std::string aspectText(double aspect);

/// A physical screen and where the viewer sits (centimetres).
struct ScreenGeometry {
    float widthCm = 0.0f;            ///< width of the picture on the screen, > 0
    float viewingDistanceCm = 0.0f;  ///< eyes to screen; 0 = unknown (no vergence angles)
    float interocularCm = 6.5f;      ///< nvidia-gtc2010: 2.5" ⇔ 6.5 cm on average
};
/// Nearer than this the screen counts as a desktop screen (nvidia-gtc2010: "when the screen is
/// close to the user (PC scenario) most of the users cannot handle more than 50% of the Eye
/// Separation"): the budget is half the eye separation.
inline constexpr float kDesktopDistanceCm = 100.0f;

/// The parallax budget of a screen: the largest |parallax| between the views the two eyes see,
/// as a fraction of the screen width. Eye separation = interocular / screen width (the parallax
/// of a point at infinity for parallel eyes), halved for a desktop viewing distance.
struct ParallaxBudget {
    float eyeSeparation = 0.0f;  ///< interocular / screen width
    float fraction = 0.0f;       ///< the budget, fraction of the screen width
    bool desktop = false;        ///< viewing distance known and < kDesktopDistanceCm
};
ParallaxBudget parallaxBudget(const ScreenGeometry& screen);

/// `--depth-percent P`: the largest parallax `--separation auto` may give the eyes, as a
/// percentage of the budget: 0 < P <= kMaxDepthPercent, default kDefaultDepthPercent (fill it).
inline constexpr float kMaxDepthPercent = 100.0f;
inline constexpr float kDefaultDepthPercent = 100.0f;

/// The parallax between adjacent views of a point at infinity, fraction of the screen width:
/// the separation for off-axis and toe-in rigs (nvidia-gtc2010 "Separation should be
/// Comfortable": "the maximum parallax at infinity is Separation"), 0 for a parallel rig.
float parallaxAtInfinity(const Rig& rig);

/// `--separation auto`: the separation between adjacent views (fraction of the screen width)
/// that makes the largest |parallax| between them — at infinity (parallaxAtInfinity: behind
/// everything in the scene, the rule nvidia-gtc2010 states for Separation), at the scene's
/// nearest and at its farthest eye-space distance — `depthPercent` % of `budget.fraction`.
/// `trial` is the rig at some separation > 0 (parallax is linear in it for off-axis and
/// parallel rigs, nearly so for toe-in). 0 when no parallax grows with the separation.
float autoSeparation(const Rig& trial, float nearest, float farthest,
                     const ParallaxBudget& budget, float depthPercent = kDefaultDepthPercent);

/// How many views apart the two eyes are: 1 for a stereo pair; for a row of N views spread
/// over a view cone seen from a known distance, the angle the eyes subtend
/// (2·atan(interocular / 2·distance)) over the angle between adjacent views
/// (cone / (N − 1)), rounded, in [1, N − 1]; otherwise 1 (adjacent views).
int eyePairViews(const Rig& rig, float viewConeDegrees, const ScreenGeometry& screen);

/// The comfort report against a screen.
struct ScreenComfort {
    ScreenGeometry screen;
    ParallaxBudget budget;
    int pairViews = 1;         ///< eyePairViews()
    float minParallax = 0.0f;  ///< between the eyes' views, fraction of screen width
    float maxParallax = 0.0f;
    float minParallaxCm = 0.0f;  ///< the same on the screen, cm (negative: out of the screen)
    float maxParallaxCm = 0.0f;
    /// Between the eyes' views at infinity (the separation; 0 for parallel rigs), fraction and
    /// cm; judged against the budget only for stereo rigs (`separationRule`).
    float infinityParallax = 0.0f, infinityParallaxCm = 0.0f;
    bool separationRule = false;
    /// Vergence angle of the eyes (degrees) for the nearest and farthest point and for the
    /// screen plane: 2·atan((interocular − parallax) / (2·distance)); NaN without a distance.
    /// Negative: the eyes diverge.
    float nearestVergenceDeg = 0.0f, farthestVergenceDeg = 0.0f, screenVergenceDeg = 0.0f;
    bool comfortable = true;
    std::string why;  ///< empty when comfortable, else the budget rules broken, in words
};
/// `outer` is parallaxRange() of the rig (between its outer views); the eyes' pair sees
/// pairViews / (columns − 1) of it (exact for evenly spaced views; a view-cone row uses its mean
/// spacing). Rules: |parallax| ≤ budget both in and out of the screen; behind the screen beyond
/// the interocular distance the eyes diverge (said so); and for an off-axis or toe-in rig
/// without a view cone (`viewConeDegrees` 0), the rule `--separation auto` chooses by: the
/// parallax at infinity (the separation, nvidia-gtc2010's "maximum comfort separation") within
/// the budget. Within 1e-4 of a limit counts as within (float rounding of a chosen value).
ScreenComfort screenComfort(const Rig& rig, const ParallaxRange& outer, int pairViews,
                            const ScreenGeometry& screen, float viewConeDegrees = 0.0f);

/// `--convergence auto`: the zero-parallax distance that uses a symmetric parallax budget best
/// for scene distances [nearest, farthest] — the harmonic mean 2 / (1/nearest + 1/farthest),
/// where the off-axis parallax s·(1 − C/w) out of the screen at `nearest` equals the parallax
/// into it at `farthest`: the largest |parallax| is then the smallest any plane gives, so the
/// separation can be the largest within the budget. Always in [nearest, farthest] and never
/// nearer than nearest·2 (the convergence/2 rule holds).
float balancedConvergence(float nearest, float farthest);

/// Distances (eye-space w) of the depth values of one depth image that are not background
/// (window depth < 1), for a perspective near/far; the `lowPercent` and `highPercent`
/// percentiles of their histogram (robust to a stray pixel). Empty when nothing was drawn.
struct DepthPercentiles {
    float nearest = 0.0f, farthest = 0.0f;  ///< the percentiles
    float minimum = 0.0f, maximum = 0.0f;   ///< the extremes
    long pixels = 0;                        ///< pixels that hit the scene
};
std::optional<DepthPercentiles> depthPercentiles(std::span<const float> windowDepth, float near,
                                                 float far, float lowPercent = 1.0f,
                                                 float highPercent = 99.0f);
/// Eye-space distance w of a window depth d in [0, 1) for a perspective near/far.
float distanceFromWindowDepth(float d, float near, float far);

}  // namespace mvr
