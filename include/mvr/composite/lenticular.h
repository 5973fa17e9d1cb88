// mvr/composite/lenticular.h — sub-pixel interleave of N views for a slanted-lenticular
// autostereoscopic panel (Looking Glass, or any van Berkel-style display).
//
// Source of the formula: C. van Berkel, "Image preparation for 3D-LCD", Proc. SPIE 3639
// (Stereoscopic Displays and Virtual Reality Systems VI), 1999: under a lens sheet slanted by
// α over an RGB-stripe panel, sub-pixel k of row l shows view
//     ((k + k_off − 3·l·tan α) mod X) · N / X,   X = sub-pixels per lens, horizontally.
// mvr uses the same relation in the parametrisation of Looking Glass Factory's lightfield
// shader and calibration (holoplay.js / LookingGlassConfig), so a panel's visual.json values
// can be used as they are:
//
//     pitchU = pitch · (screenW / dpi) · cos(atan(1 / slope))   lenticules across the screen
//     tilt   = screenH / (screenW · slope) · (flipX ? −1 : 1)
//     subp   = 1 / (3 · screenW)                                one sub-pixel, in u
//     for output pixel (px, py), row 0 at the top, texture coordinates with v UP (as in GL):
//         u = (px + 0.5) / screenW,   v = 1 − (py + 0.5) / screenH
//     for sub-pixel i = 0, 1, 2 (left to right on the panel):
//         z_i  = fract((u + i · subp + v · tilt) · pitchU − center)
//         z_i  = invertViews ? 1 − z_i : z_i
//         view_i = min(⌊z_i · N⌋, N − 1)
//         c_i  = views[view_i] sampled at (u, v) (nearest pixel; with flipX / flipY the
//                lookup is mirrored: u → 1 − u, v → 1 − v)
//     out = (c_ri.r, c_1.g, c_bi.b, 255), ri = bgr ? 2 : 0, bi = bgr ? 0 : 2
//
// View 0 is the leftmost eye's view (compose.h), which is the first tile of a Looking Glass
// quilt, so view_i indexes the quilt the same way the Looking Glass shader does.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::composite {

/// The bounds of a calibration's numbers (options, visual.json and lenticular() alike): beyond
/// them the lens phase is lost in rounding (every sub-pixel shows one view). Real panels: pitch
/// ~40..60 lenticules per inch, DPI ~200..500, slope ~-5..5, center a phase in -1..1.
inline constexpr double kMaxLenticularPitch = 10000.0;   ///< lenticules per inch, > 0
inline constexpr double kMaxLenticularDpi = 10000.0;     ///< panel pixels per inch, > 0
inline constexpr double kMaxLenticularCenter = 1.0e6;    ///< |center|, lenticules
inline constexpr double kMinLenticularSlope = 1.0e-6;    ///< |slope| at least
inline constexpr double kMaxLenticularSlope = 1.0e15;    ///< |slope| at most (~vertical lenses)

/// The shader-side values derived from a calibration for a screen of screenW×screenH.
struct LenticularShaderParams {
    double pitchU = 0;  ///< lenticules across the screen width (pitch adjusted for the slant)
    double tilt = 0;    ///< lens phase change per unit of v
    double subp = 0;    ///< one sub-pixel in u
    double center = 0;
    int ri = 0, bi = 2;  ///< which sub-pixel sample feeds red / blue
    bool invertViews = false;
};

/// Derives the shader values. Errors: Usage for dpi ≤ 0, slope = 0, a non-finite value or a
/// screen size < 1.
Result<LenticularShaderParams> lenticularShaderParams(const LenticularCalibration& calibration,
                                                      int screenWidth, int screenHeight);

/// The view (0..viewCount−1) that sub-pixel `subpixel` (0, 1, 2 from the left) of output pixel
/// (px, py) shows.
int lenticularView(const LenticularShaderParams& params, int viewCount, int screenWidth,
                   int screenHeight, int px, int py, int subpixel);

/// Where lenticular() reads each panel pixel: the derived values and, per panel row and
/// column, the view pixel sampled (nearest, mirrored by flipX / flipY). One row of the panel reads
/// one row of every view, so a panel can be composed from the views' rows as they are finished
/// (direct lenticular rendering: mvr/session/direct.h) by the same lenticularRow().
struct LenticularLayout {
    LenticularShaderParams params;
    int views = 0;
    int viewWidth = 0, viewHeight = 0;
    int screenWidth = 0, screenHeight = 0;
    std::vector<int> sourceColumn;  ///< per panel column: the view column it reads
    std::vector<int> sourceRow;     ///< per panel row: the view row it reads
    std::vector<double> columnU;    ///< per panel column: u = (px + 0.5) / screenWidth
    /// Every lens phase z of the panel is below 2^50 in magnitude, so lenticularRow() takes its
    /// floors with the round-to-integer constant, several sub-pixels a vector (else one by one,
    /// as lenticularView()); the views chosen are the same.
    bool smallPhases = false;
};

/// The layout of `viewCount` views of viewWidth×viewHeight on the calibration's panel
/// (screenWidth×screenHeight, 0 = the view size). Errors: Usage (sizes, calibration).
Result<LenticularLayout> lenticularLayout(const LenticularCalibration& calibration, int viewCount,
                                          int viewWidth, int viewHeight);

/// Panel row `py` of the layout into `out` (screenWidth RGBA8 pixels): `viewRows[v]` is view v's
/// row layout.sourceRow[py] (viewWidth RGBA8 pixels).
void lenticularRow(const LenticularLayout& layout, int py, const std::uint8_t* const* viewRows,
                   std::uint8_t* out);

/// Interleaves views (2..N, one size) into a screenWidth×screenHeight image (0 = view size).
/// Errors: Usage (view count/sizes, calibration).
Result<Image> lenticular(std::span<const Image> views, const LenticularCalibration& calibration);

/// Reads a Looking Glass calibration (the display's visual.json, as HoloPlay Service or the
/// Looking Glass Bridge exports it): {"pitch": {"value": …}, "slope": …, "center": …, "DPI": …,
/// "screenW": …, "screenH": …, "invView": …, "flipImageX": …, "flipImageY": …, "flipSubp": …,
/// "viewCone": …}. pitch, slope, center and DPI are required (viewCone, when present, must lie
/// in (0, 180) degrees; 0 counts as absent); the rest default to LenticularCalibration's
/// values (screen size 0 = the view size). A key may hold {"value": x} or x directly.
/// `what` names the source in messages. Errors: ErrorCode::Input naming the key.
Result<LenticularCalibration> parseLookingGlassCalibration(std::string_view json,
                                                           const std::string& what);
/// Reads and parses `path`. Errors: Input (missing, unreadable, malformed).
Result<LenticularCalibration> readLookingGlassCalibration(const std::filesystem::path& path);

}  // namespace mvr::composite
