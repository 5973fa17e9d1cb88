// mvr/composite/compose.h — turn N rendered views into one stereo / multi-view output.
//
// Conventions of the composite module:
//  - Views are numbered left to right: view 0 is the leftmost eye, so for stereo formats
//    views[0] is the LEFT image and views[1] the RIGHT image.
//  - Images are mvr::Image: RGBA8, row 0 at the TOP, non-premultiplied. Formats that only move
//    pixels (sbs, tb, interleaves, quilt, hdmi) copy all four channels; formats that mix colors
//    (anaglyphs, lenticular) write alpha = 255. Blank areas (HDMI gap, unused quilt tiles) are
//    opaque black.
//  - All composites here are pure CPU functions of their inputs (deterministic, no globals).
//    The gl backend composites on the GPU and must match these within rounding; the per-pixel
//    math it has to mirror is public in anaglyph.h and lenticular.h.
//  - Errors are Status/Result values, never aborts: a wrong view count, views of different
//    sizes or a size a format cannot take is ErrorCode::Usage ("mvr::composite::compose():
//    sbs needs 2 views (got 3)"); a format this build lacks is Unsupported; unwritable output
//    is Output.
//
// Formats (formatNames() lists them; `mvr compose --help` prints formatHelp()):
//   anaglyph-color | anaglyph-half-color | anaglyph-gray | anaglyph-true |
//   anaglyph-dubois (red-cyan) | anaglyph-dubois-gm | anaglyph-dubois-ab        2 views, W×H
//   sbs (full: 2W×H) | sbs-half (W×H, each view squeezed 2:1)                   2 views
//   tb (W×2H, left on top) | tb-half (W×H)                                      2 views
//   rows (row y from view y mod N) | columns (column x from view x mod N)       2..N views
//   checkerboard ((x + y) even: left)                                           2 views
//   hdmi-frame-packing (HDMI 1.4a: 1280×720 → 1280×1470, 1920×1080 → 1920×2205) 2 views
//   quilt (C×R tiles, view 0 bottom left, last view top right)                  1..N views
//   lenticular (slanted-lens sub-pixel interleave, see lenticular.h)            2..N views
//   jps (JPEG, side by side, RIGHT view on the left)                             2 views, file
//   mpo (CIPA DC-007 multi-picture JPEG, one JPEG per view)                     2..N views, file
//   rgbd (Looking Glass RGB-D: a colour image and its depth image side by side,
//         depth on the right by default; see rgbd.h)                            colour + depth
// Each format's size rules are in its row of formats() (FormatInfo::size): outputSize() gives
// the output size of views of W×H — and refuses exactly the sizes compose() refuses —, and
// largestViewSize() the largest views whose output fits a frame (the viewer's window).
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::composite {

/// Calibration of a slanted-lenticular autostereoscopic panel, in the units of the Looking
/// Glass calibration file (visual.json); see lenticular.h for the formula that uses them.
/// pitch, slope, center and dpi default to the example values of a Looking Glass Portrait
/// published with its shaders; a real panel needs its own calibration (its visual.json, see
/// readLookingGlassCalibration() in lenticular.h).
struct LenticularCalibration {
    double pitch = 52.59267;   ///< lenticules per inch, measured horizontally on the panel
    double slope = -7.08354;   ///< lens slant: panel rows per lenticule column shift (signed)
    double center = 0.81679;   ///< phase offset of the lens grid, in lenticules (0..1)
    double dpi = 324.0;        ///< panel pixels per inch
    int screenWidth = 0;       ///< output width in panel pixels; 0 = the view width
    int screenHeight = 0;      ///< output height in panel pixels; 0 = the view height
    bool bgr = false;          ///< sub-pixel order B,G,R instead of R,G,B (LG "flipSubp")
    bool invertViews = false;  ///< view order runs the other way under the lens (LG "invView")
    bool flipX = false;        ///< panel mirrored horizontally (LG "flipImageX")
    bool flipY = false;        ///< panel mirrored vertically (LG "flipImageY")
    /// The panel's total view cone in degrees (LG "viewCone"; 0 = not given). Not used by the
    /// interleave: `mvr render` / `mvr view` take it as the default --view-cone.
    double viewCone = 0.0;
};

/// rgbd: where the depth image lies beside the colour image (Looking Glass Bridge's depth_loc:
/// 0 top, 1 bottom, 2 right, 3 left; rgbd.h).
enum class DepthPosition { Right, Left, Top, Bottom };

/// Options of every format; each format reads only the ones it documents.
struct ComposeOptions {
    /// Exchange left and right (stereo formats); for N-view formats (quilt, lenticular, rows,
    /// columns, mpo) reverse the view order.
    bool swapEyes = false;
    /// sbs / sbs-half only: right view on the left half, for cross-eyed free viewing.
    /// Combined with swapEyes the two cancel.
    bool crossEyed = false;
    /// quilt: tile columns and rows; 0 = choose (see chooseQuiltLayout()). Both or neither.
    int quiltColumns = 0;
    int quiltRows = 0;
    /// lenticular panel calibration.
    LenticularCalibration lenticular;
    /// jps / mpo: JPEG quality 1..100; chroma is never subsampled (4:4:4).
    int jpegQuality = 95;
    /// mpo: distance between adjacent viewpoints (the rig's interaxial) in METRES — the unit of
    /// the MPF BaselineLength tag; mvr render passes its world units as metres. 0 = unknown.
    double baseline = 0.0;
    /// mpo: convergence DISTANCE of the rig (where adjacent views' lines of sight meet), same
    /// unit as baseline; 0 = parallel. Written as MPF ConvergenceAngle =
    /// convergenceAngleDegrees(baseline, convergence).
    double convergence = 0.0;
    /// mpo: 1-based number of the base (reference) viewpoint; 0 = (N + 1) / 2 (1 for stereo).
    int baseViewpoint = 0;
    /// quilt: the aspect its file name writes (`quilt_qsCxRaA.png`): the width / height of the
    /// picture a view shows on the panel; 0 = the views' pixel aspect. A display preset sets it
    /// when the panel stretches its tiles (include/mvr/core/displays.h).
    double quiltAspect = 0.0;
    /// rgbd: the depth image's side (default right of the colour, Bridge's depth_loc 2).
    DepthPosition rgbdDepth = DepthPosition::Right;
    /// rgbd: Looking Glass's depthiness (how deep the RGB-D image is shown, Bridge's range
    /// 0.1..2) and focus (which depth lies on the panel's plane, Bridge's range -0.05..0.05),
    /// written to the sidecar (rgbd.h); the image does not depend on them.
    double depthiness = 1.0;
    double focus = 0.0;
};

/// How a format's output size follows from its views' size W×H (FormatInfo::size).
enum class SizeRule {
    Tiled,        ///< a grid of cells, one view each: see FormatSize
    FramePacked,  ///< HDMI 1.4a frame packing: only 1280×720 → 1280×1470, 1920×1080 → 1920×2205
    QuiltGrid,  ///< C·W × R·H, C×R = options.quiltColumns × quiltRows or chooseQuiltLayout()
    Panel,      ///< the lenticular panel: options.lenticular.screenWidth × screenHeight
                ///< (0 = the view's), whatever the view size
    PerView,    ///< no single image: one image of W×H per view in a file (mpo)
    ColourDepth,  ///< rgbd: a colour image and its depth image of W×H each, 2W×H with the depth
                  ///< left or right, W×2H top or bottom (options.rgbdDepth)
};

/// The size rule of one format. SizeRule::Tiled: the output is a grid of cellsAcross ×
/// cellsDown cells, each one view of W×H squeezed to W / squeezeX × H / squeezeY (so W must be a
/// multiple of squeezeX, H of squeezeY): output (cellsAcross·W / squeezeX) × (cellsDown·H /
/// squeezeY). sbs and jps are 2×1 cells, sbs-half 2×1 cells squeezed 2:1 across, tb 1×2, tb-half
/// 1×2 squeezed 2:1 down; formats that mix or interleave the views pixel by pixel (anaglyphs,
/// rows, columns, checkerboard) are one cell, W×H. The other rules ignore the cell fields.
struct FormatSize {
    SizeRule rule = SizeRule::Tiled;
    int cellsAcross = 1, cellsDown = 1;
    int squeezeX = 1, squeezeY = 1;
};

struct ComposeOptions;
struct FormatInfo;

/// The container a format's file is written as (writeCompositeFile(), readViewFile()).
enum class FileKind {
    Png,  ///< one image: .png (or .jpg / .jpeg when the caller's file name says so)
    Jps,  ///< one side-by-side picture in a JPEG with the JPS APP3 descriptor (.jps, .jpg, .jpeg)
    Mpo,  ///< one JPEG per view in a CIPA multi-picture file (.mpo); fileOnly
};

/// How the gl backend composes a format on the GPU (mvr::gl::composeGpu() turns it into a
/// shader plan); None: the GPU does not compose it, and `--backend gl` composes it on the CPU
/// (composeFor() falls back to compose()). The composite module only names the plans.
enum class GpuPlan {
    None,
    Anaglyph,        ///< the row's name is an anaglyphMethod()
    SideBySide,      ///< sbs: 2W×H (options.crossEyed swaps the halves)
    SideBySideHalf,  ///< sbs-half
    TopBottom,       ///< tb
    TopBottomHalf,   ///< tb-half
    Rows,
    Columns,
    Checkerboard,
    FramePacking,  ///< hdmi-frame-packing
    Quilt,
    Lenticular,
};

/// Composes one format: `views` are already checked against the row (count, equal non-empty
/// sizes) and already reversed for options.swapEyes; `who` prefixes error messages
/// ("mvr::composite::compose(): NAME").
using Composer = Result<Image> (*)(std::span<const Image> views, const ComposeOptions& options,
                                   const std::string& who);

/// One output format and what it needs.
struct FormatInfo {
    std::string_view name;
    int minViews;                ///< fewest views the format accepts
    int maxViews;                ///< most views (kAnyViewCount = no limit)
    bool fileOnly;               ///< true for mpo (a file, not one image); compose() refuses it
    std::string_view extension;  ///< of the file writeComposite() writes: ".png", ".jps", ".mpo"
    std::string_view summary;    ///< one line for --help
    FormatSize size;             ///< how big the output is (outputSize(), largestViewSize())
    FileKind file = FileKind::Png;  ///< the container writeCompositeFile() writes
    Composer composer = nullptr;    ///< compose()'s work; null only for fileOnly rows (mpo)
    GpuPlan gpu = GpuPlan::None;    ///< how mvr::gl::composeGpu() composes it, or None
    /// The format's two images are one view's colour and its depth image (rgbd), not views:
    /// `mvr render` gives it the rig's centre view and that view's depth (rgbd.h).
    bool colourAndDepth = false;
};
inline constexpr int kAnyViewCount = 1 << 20;

/// All formats, in --help order (the built-in rows, then registered ones).
std::span<const FormatInfo> formats();
/// Adds a format by its row, after the built-in ones: compose(), writeComposite(), `mvr
/// compose` / `mvr render --format`, the viewer's list and (with gpu == GpuPlan::None, composed
/// on the CPU) `--backend gl` take it from then on. For tests and plugins: call it before any
/// other thread uses the formats; name, extension and summary must outlive the process (string
/// literals). Errors (ErrorCode::Usage): an empty or taken name, no composer for an image
/// format, minViews < 1 or maxViews < minViews, a GPU plan other than None (the gl backend only
/// knows the built-in plans' shaders), a FileKind::Mpo row.
Status registerFormat(const FormatInfo& format);
/// The names of all formats, in --help order.
std::vector<std::string> formatNames();
/// The format called `name`. Errors: ErrorCode::Usage listing the valid names.
Result<FormatInfo> findFormat(std::string_view name);
/// Multi-line description of the formats for `--help`.
std::string formatHelp();

/// A size in pixels.
struct Size {
    int width = 0;
    int height = 0;
    bool operator==(const Size&) const = default;
};

/// The size of the image compose() makes of `viewCount` views of viewWidth×viewHeight, from the
/// format's row (FormatInfo::size). It refuses what compose() refuses for views of that count
/// and size, with compose()'s texts after the caller's name: an unknown format, a view count
/// out of range, a size < 1, a width / height a squeezed format cannot halve, a non-HDMI size
/// for hdmi-frame-packing, a quilt grid that is malformed, too small for the views or larger
/// than 65536 pixels on a side, a lenticular calibration lenticularShaderParams() refuses
/// (ErrorCode::Usage). jps: its side-by-side picture (2W×H). mpo: the size of each of its
/// images (W×H; compose() itself refuses mpo as a file). Messages start
/// "mvr::composite::outputSize(): FORMAT: ".
Result<Size> outputSize(std::string_view format, int viewCount, int viewWidth, int viewHeight,
                        const ComposeOptions& options = {});
/// As above for a row of formats(), with `who` naming the caller in the messages (e.g.
/// "mvr::gl::composeGpu(): sbs-half"), for composites that check sizes before they draw.
Result<Size> outputSize(const FormatInfo& format, int viewCount, int viewWidth, int viewHeight,
                        const ComposeOptions& options, const std::string& who);

/// The largest view size whose output (outputSize()) fits in frameWidth×frameHeight: for a
/// window that shows the composite 1:1. Tiled: (frame / cells) · squeeze on each axis (sbs:
/// half the width; sbs-half: the width rounded down to even); hdmi-frame-packing: 1920×1080 or
/// 1280×720, whichever fits; quilt: the given grid's tiles, or (automatic grid) the largest
/// views whose own automatic grid fits; lenticular: the frame with a screen size of 0, else the
/// panel's size when it fits; mpo: the frame. Errors (ErrorCode::Usage, naming the format and
/// the frame): unknown format, view count out of range, a frame too small for one pixel per view
/// (or for the HDMI sizes, or the panel).
Result<Size> largestViewSize(std::string_view format, int viewCount, int frameWidth,
                             int frameHeight, const ComposeOptions& options = {});

/// The default anaglyph of `mvr render`: Dubois least-squares red-cyan.
inline constexpr std::string_view kDefaultAnaglyph = "anaglyph-dubois";

/// Composes `views` (left to right, all the same size) into the image of `format`.
/// Every format except mpo gives one image (jps gives its side-by-side picture, right view on
/// the left). Errors (ErrorCode::Usage): unknown format, wrong number of views, views of
/// different sizes or empty, a size the format cannot take (odd width for sbs-half, non-HDMI
/// size for hdmi-frame-packing, a quilt grid too small for N), out-of-range options.
/// ErrorCode::Unsupported: "mpo" (a multi-image file: use writeComposite() or encodeMpo()).
Result<Image> compose(std::string_view format, std::span<const Image> views,
                      const ComposeOptions& options = {});

/// File name (no folder) writeComposite() uses: "<format>.png" for image formats,
/// "quilt_qs<C>x<R>a<A>.png" for the quilt (Looking Glass convention, A = width / height of
/// one view as formatAspect() writes it), "jps.jps", "mpo.mpo". Errors as compose().
Result<std::string> compositeFileName(std::string_view format, std::span<const Image> views,
                                      const ComposeOptions& options = {});

/// Composes and writes into `outDir` (which must exist) under compositeFileName().
/// Returns the written path. Errors: as compose(); ErrorCode::Output naming the path when it
/// cannot be written.
Result<std::filesystem::path> writeComposite(std::string_view format, std::span<const Image> views,
                                             const ComposeOptions& options,
                                             const std::filesystem::path& outDir);

/// Composes and writes to exactly `file`. The container follows `file`'s extension: .png,
/// .jpg/.jpeg (image formats), .jps (jps), .mpo (mpo). Errors: as writeComposite(), plus
/// ErrorCode::Usage for an extension that does not fit the format.
Status writeCompositeFile(std::string_view format, std::span<const Image> views,
                          const ComposeOptions& options, const std::filesystem::path& file);

/// Quilt grid for `viewCount` views of `viewWidth`×`viewHeight` when the caller gives none:
/// the C×R with no empty row whose whole quilt is closest to square (|ln(C·W / (R·H))|),
/// ties to fewer blank tiles. 45 views of 1.8:1 → 5×9, 48 views of 3:4 → 8×6 (the Looking
/// Glass defaults). Precondition: all arguments ≥ 1.
std::pair<int, int> chooseQuiltLayout(int viewCount, int viewWidth, int viewHeight);

/// Aspect ratio for the quilt file name: width / height with at most 4 decimals and no
/// trailing zeros ("0.75", "1", "1.7778").
std::string formatAspect(int width, int height);

/// Parses a quilt grid "CxR" (both 1..256). Errors: ErrorCode::Usage.
Result<std::pair<int, int>> parseQuiltGrid(std::string_view text);

/// Equivalent convergence angle in degrees of two viewpoints `interaxial` apart whose lines of
/// sight meet at `convergenceDistance` (same units): 2·atan(interaxial / (2·distance)).
/// Returns 0 for a distance ≤ 0 (parallel).
double convergenceAngleDegrees(double interaxial, double convergenceDistance);

/// Reads the views in an image file, left to right: a PNG or JPEG gives one view, an MPO all
/// of its images, a JPS (by extension .jps) its two halves (stored right|left) as {left,
/// right}. Errors: ErrorCode::Input naming the path (missing, unreadable, not PNG/JPEG,
/// truncated or corrupt data).
Result<std::vector<Image>> readViewFile(const std::filesystem::path& path);

}  // namespace mvr::composite
