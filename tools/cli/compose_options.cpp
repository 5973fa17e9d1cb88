#include "compose_options.h"

// The command-line options of the composite formats: CLI11 glue of the tools, kept out of the
// composite library (which knows no command line).
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>

#include <fmt/core.h>
#include <CLI/CLI.hpp>

#include "mvr/composite/lenticular.h"
#include "mvr/composite/rgbd.h"
#include "validators.h"

namespace mvr::cli {

using composite::LenticularCalibration;
using composite::parseQuiltGrid;
using composite::readLookingGlassCalibration;

void addComposeOptions(CLI::App* app, composite::ComposeOptions& options, bool withStereoMetadata) {
    const std::string group = "Composite formats";
    app->add_flag("--swap-eyes", options.swapEyes,
                  "Exchange left and right (N views: reverse their order)")
        ->group(group);
    app->add_flag("--cross-eyed", options.crossEyed,
                  "sbs / sbs-half: right view on the left, for cross-eyed viewing")
        ->group(group);
    app->add_option_function<std::string>(
           "--quilt",
           [&options](const std::string& text) {
               Result<std::pair<int, int>> grid = parseQuiltGrid(text);
               if (!grid) {  // parseQuiltGrid's message names --quilt and the value itself
                   const std::string& why = grid.status().message();
                   throw CLI::ValidationError(why.rfind("--quilt", 0) == 0 ? why
                                                                           : "--quilt: " + why);
               }
               options.quiltColumns = grid->first;
               options.quiltRows = grid->second;
           },
           "quilt: tile grid CxR, e.g. 8x6 (default: the most square quilt that fits N views)")
        ->type_name("CxR")
        ->group(group);
    app->add_option("--jpeg-quality", options.jpegQuality, "jps / mpo / .jpg: JPEG quality")
        ->check(wholeIn(1, 100))
        ->default_val(options.jpegQuality)
        ->group(group);
    app->add_option("--base-viewpoint", options.baseViewpoint,
                    "mpo: 1-based base viewpoint (default (N + 1) / 2)")
        ->check(wholeIn(1, 4096))
        ->group(group);
    if (withStereoMetadata) {
        app->add_option("--baseline", options.baseline,
                        "mpo: distance between adjacent viewpoints in metres (BaselineLength)")
            ->check(numberIn(0.0, 1.0e6))
            ->group(group);
        app->add_option("--convergence", options.convergence,
                        "mpo: convergence distance in metres, 0 = parallel (ConvergenceAngle)")
            ->check(numberIn(0.0, 1.0e9))
            ->group(group);
    }
    app->add_option_function<std::string>(
           "--rgbd-depth-position",
           [&options](const std::string& text) {
               Result<composite::DepthPosition> p = composite::parseDepthPosition(text);
               if (!p) throw CLI::ValidationError(p.status().message());
               options.rgbdDepth = *p;
           },
           "rgbd: where the depth image lies beside the colour: right (default), left, top, "
           "bottom (Looking Glass Bridge's depth_loc 2, 3, 0, 1)")
        ->type_name("SIDE")
        ->group(group);
    app->add_option("--depthiness", options.depthiness,
                    "Looking Glass's depthiness: the view cone's spread (0: identical views, "
                    "0..2) and, with --format rgbd, how deep the RGB-D image is shown (Bridge's "
                    "0.1..2), written to rgbd.json")
        ->check(numberIn(0.0, 2.0))
        ->default_val(options.depthiness)
        ->group(group);
    app->add_option("--focus", options.focus,
                    "Looking Glass's focus (Bridge's range -0.05..0.05): the view cone's focal "
                    "plane moved toward the viewer by F of the scene's depth and, with --format "
                    "rgbd, which depth lies on the panel's plane, written to rgbd.json")
        ->check(numberIn(-0.05, 0.05))
        ->default_val(options.focus)
        ->group(group);
    LenticularCalibration& cal = options.lenticular;
    // Defined before the single lenticular values, so that those given with it override it
    // (CLI11 runs option callbacks in definition order).
    app->add_option_function<std::string>(
           "--lenticular-calibration",
           [&cal](const std::string& path) {
               Result<LenticularCalibration> loaded = readLookingGlassCalibration(path);
               if (!loaded)  // a file's fault: its code (2), not usage (main.cpp)
                   throw CLI::ValidationError(
                       "--lenticular-calibration: " + loaded.status().message(),
                       exitCode(loaded.status().code()));
               cal = *loaded;
           },
           "lenticular: a Looking Glass visual.json (pitch, slope, center, DPI, screenW/H, "
           "invView, flipImageX/Y, flipSubp); single --lenticular-* values override it")
        ->type_name("FILE")
        ->group(group);
    app->add_option("--lenticular-pitch", cal.pitch, "lenticular: lenticules per inch")
        ->check(positiveAtMost(composite::kMaxLenticularPitch))
        ->default_val(cal.pitch)
        ->group(group);
    app->add_option("--lenticular-slope", cal.slope, "lenticular: lens slope (non-zero)")
        ->check(nonZeroMagnitudeIn(composite::kMinLenticularSlope,
                                   composite::kMaxLenticularSlope))
        ->default_val(cal.slope)
        ->group(group);
    app->add_option("--lenticular-center", cal.center, "lenticular: lens phase (lenticules)")
        ->check(numberIn(-composite::kMaxLenticularCenter, composite::kMaxLenticularCenter))
        ->default_val(cal.center)
        ->group(group);
    app->add_option("--lenticular-dpi", cal.dpi, "lenticular: panel pixels per inch")
        ->check(positiveAtMost(composite::kMaxLenticularDpi))
        ->default_val(cal.dpi)
        ->group(group);
    app->add_option_function<std::string>(
           "--lenticular-screen",
           [&cal](const std::string& text) {
               int w = 0, h = 0;
               char x = 0, extra = 0;
               if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 ||
                   (x != 'x' && x != 'X') || w < 1 || h < 1 || w > 16384 || h > 16384)
                   throw CLI::ValidationError(
                       "--lenticular-screen",
                       fmt::format("'{}' (expected WxH, 1..16384 each, e.g. 1536x2048)", text));
               cal.screenWidth = w;
               cal.screenHeight = h;
           },
           "lenticular: panel resolution WxH (default: the view size)")
        ->type_name("WxH")
        ->group(group);
    app->add_flag("--lenticular-bgr", cal.bgr, "lenticular: sub-pixels are B,G,R")->group(group);
    app->add_flag("--lenticular-invert-views", cal.invertViews,
                  "lenticular: views run right to left under the lens")
        ->group(group);
    app->add_flag("--lenticular-flip-x", cal.flipX, "lenticular: panel mirrored horizontally")
        ->group(group);
    app->add_flag("--lenticular-flip-y", cal.flipY, "lenticular: panel mirrored vertically")
        ->group(group);
}

}  // namespace mvr::cli
