// tools/viewer/view_command.cpp — `mvr view`'s options (CLI11) and its start: the options
// become a session::RenderRecipe (mvr/session/recipe.h), session::prepare() gives the scene, the
// rig and a display preset's outputs as it does for `mvr render`, and the window takes over
// (viewer.cpp).
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fmt/core.h>
#include <fmt/format.h>

#include "input.h"
#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/composite/lenticular.h"
#include "mvr/session/prepare.h"
#include "viewer.h"
#include "viewer_backends.h"
#include "viewer_window.h"

namespace mvr::viewer {

std::vector<std::string> viewerFormats() {
    // The formats table's image formats of one cell grid that take a pair (anaglyphs, sbs, tb,
    // their halves, rows, columns, checkerboard and any registered one), then quad-buffer.
    std::vector<std::string> names;
    for (const composite::FormatInfo& f : composite::formats()) {
        if (f.file == composite::FileKind::Png && f.size.rule == composite::SizeRule::Tiled &&
            f.minViews <= 2 && f.maxViews >= 2)
            names.emplace_back(f.name);
    }
    names.emplace_back("quad-buffer");
    return names;
}

std::vector<std::string> viewerViewFormats() {
    // "view", then the table's formats of all N views in one picture: quilt, lenticular.
    std::vector<std::string> names = {"view"};
    for (const composite::FormatInfo& f : composite::formats()) {
        if (f.file == composite::FileKind::Png && (f.size.rule == composite::SizeRule::QuiltGrid ||
                                                   f.size.rule == composite::SizeRule::Panel))
            names.emplace_back(f.name);
    }
    return names;
}

session::RenderRecipe viewerRecipe(const ViewerOptions& o) {
    session::RenderRecipe r = o.scene.recipe();
    if (o.calibrationGiven && o.composeOptions.lenticular.viewCone > 0.0)
        r.calibrationViewCone = o.composeOptions.lenticular.viewCone;
    r.outputs.compose = o.composeOptions;
    r.outputs.calibrationGiven = o.calibrationGiven;
    r.outputs.quiltGiven = o.quiltGiven;
    r.backend = o.backend;
    r.method = o.method;
    if (!r.aa) r.aa = 1;  // interactive: one sample a pixel unless --aa asks (presets take 4)
    r.surfaces.angularAA = "off";  // a post-process of written views (angular_aa.h), not drawn
    return r;
}

int runViewer(const ViewerOptions& given) {
    auto script = parseScript(given.script);
    if (!script) return cli::fail(script.status());
    if (given.frames < 0) {
        return cli::fail(
            usageError(fmt::format("--frames {} is out of range (expected >= 0)", given.frames)));
    }
    // The scene, the rig and a preset's quilt grid, aspect and panel: the session's. An eye
    // track is replayed here (viewer.cpp), where `mvr render` needs a sequence for it.
    session::RenderRecipe recipe = viewerRecipe(given);
    const std::string track = std::exchange(recipe.screen.eyeTrack, {});
    auto prepared = session::prepare(recipe);
    if (!prepared) return cli::fail(prepared.status());
    if (!track.empty()) {
        if (!prepared->rig.screen)
            return cli::fail(usageError(fmt::format("--eye-track {} needs --rig screen", track)));
        auto read = session::readEyeTrack(track, prepared->rig.screen->screen);
        if (!read) return cli::fail(read.status());
        prepared->eyeTrack = std::make_shared<const session::EyeTrack>(std::move(read).value());
    }
    for (const std::string& note : prepared->notes) {  // -q keeps the warnings only
        if (!given.quiet || note.rfind("note: ", 0) != 0) fmt::print(stderr, "{}\n", note);
    }
    if (prepared->rig.rows != 1 || prepared->rig.viewCount() < 2) {
        return cli::fail(usageError(fmt::format(
            "mvr view shows a row of views: {}x{} views requested (expected --views N, N >= 2)",
            prepared->rig.columns, prepared->rig.rows)));
    }
    ViewerOptions options = given;
    options.composeOptions = prepared->compose;
    if (options.composeOptions.quiltAspect <= 0.0) {
        options.composeOptions.quiltAspect = prepared->rig.camera.aspect;
    }
    return runViewerWindow(options, std::move(prepared).value(), std::move(script).value());
}

std::function<int()> addViewCommand(CLI::App& root) {
    auto o = std::make_shared<ViewerOptions>();
    o->scene.size = "960x540";
    CLI::App* app = root.add_subcommand(
        "view",
        "Interactive stereo viewer: orbit, pan and zoom a scene or model files in a window, "
        "switch the method and the output format live, with a HUD and a 3D cursor");
    o->scene.addTo(app);
    o->backend = defaultViewerBackend();
    const std::string fallback = fallbackViewerBackend();
    auto* backend =
        app->add_option("--backend", o->backend,
                        fmt::format("Backend: {} (default: {}, the first GPU backend{})",
                                    fmt::join(backendNames(), " or "), o->backend,
                                    fallback.empty() || fallback == o->backend
                                        ? std::string()
                                        : fmt::format("; falls back to {} when it has no "
                                                      "context, unless given",
                                                      fallback)))
            ->default_val(o->backend);
    std::vector<std::string> interactive;
    for (const BackendEntry& e : backends())
        if (!e.interactiveMethod.empty()) interactive.push_back(e.name + " " + e.interactiveMethod);
    app->add_option("--method", o->method,
                    fmt::format("Method of the backend (see `mvr info`; default: the backend's "
                                "default method{}); m/M cycle them",
                                interactive.empty()
                                    ? std::string()
                                    : fmt::format(", except {}", fmt::join(interactive, ", "))));
    std::vector<std::string> allFormats = viewerFormats();
    const std::vector<std::string> viewFormats = viewerViewFormats();
    allFormats.insert(allFormats.end(), viewFormats.begin(), viewFormats.end());
    auto* format =
        app->add_option("--format", o->format,
                        "Output: a stereo format (of views i, i+1 of a row), or view (one view), "
                        "quilt, lenticular (all N views); default: the --display preset's "
                        "output, else anaglyph-dubois; f/F cycle them")
            ->default_val(o->format)
            ->check(CLI::IsMember(allFormats));
    auto* quilt = app->add_option_function<std::string>(
                         "--quilt",
                         [o](const std::string& text) {
                             Result<std::pair<int, int>> grid = composite::parseQuiltGrid(text);
                             if (!grid)
                                 throw CLI::ValidationError("--quilt", grid.status().message());
                             o->composeOptions.quiltColumns = grid->first;
                             o->composeOptions.quiltRows = grid->second;
                         },
                         "quilt: tile grid CxR (default: the --display preset's, else the most "
                         "square quilt)")
                      ->type_name("CxR");
    auto* calibration =
        app->add_option_function<std::string>(
               "--lenticular-calibration",
               [o](const std::string& path) {
                   Result<composite::LenticularCalibration> loaded =
                       composite::readLookingGlassCalibration(path);
                   if (!loaded) {
                       throw CLI::ValidationError("--lenticular-calibration",
                                                  loaded.status().message());
                   }
                   o->composeOptions.lenticular = *loaded;
               },
               "lenticular: a Looking Glass visual.json: adds the lenticular output (the "
               "default under --display) and its viewCone is the default --view-cone")
            ->type_name("FILE");
    app->add_flag("--swap-eyes", o->swapEyes, "Exchange the left and right views");
    app->add_option("--compose", o->compose,
                    "Where anaglyphs are mixed: gpu (composite::anaglyphGlsl in the window) or cpu "
                    "(composite::compose, as mvr render); other formats are composed on the CPU")
        ->default_val(o->compose)
        ->check(CLI::IsMember({"gpu", "cpu"}));
    app->add_option("--frames", o->frames, "Render N frames and exit (0: until the window closes)")
        ->default_val(o->frames);
    app->add_option(
        "--screenshot", o->screenshot,
        "Write the last frame (what the window shows) to FILE (PNG); p saves FILE-1.png, …");
    app->add_option(
        "--script", o->script,
        "Comma-separated keys applied one per frame, e.g. \"m,m,+\" or \">,>,v\"; also left, right, up, "
        "down, pgup, pgdn, esc, f1, f12, at:X:Y (mouse), drag:DX:DY, pan:DX:DY, head:DX:DY, wheel:N, size:W:H");
    app->add_flag("--no-hud", o->noHud, "Hide the HUD and the 3D cursor");
    app->add_flag("-q,--quiet", o->quiet, "Print nothing but errors");
    std::string keys = "Keys (also shown in the window by ? or F1):\n";
    for (const KeyHelp& k : keyHelp()) keys += fmt::format("  {:<12} {}\n", k.keys, k.what);
    keys +=
        "The view size follows the window (--size sets the first one); side-by-side shows two "
        "half-width views, top-bottom two half-height views.\n"
        "N views (--views N, --view-cone DEG, --display NAME): f cycles view (one view at a "
        "time), quilt, lenticular (with --lenticular-calibration), then the stereo formats "
        "(views i and i+1); . and , (> and <) step through the views; + and - change the view "
        "cone by 5 degrees; v toggles the single view. Under --display the preset's output "
        "is shown first.";
    app->footer(keys);
    return [o, backend, format, quilt, calibration] {
        o->backendGiven = backend->count() > 0;
        o->formatGiven = format->count() > 0;
        o->quiltGiven = quilt->count() > 0;
        o->calibrationGiven = calibration->count() > 0;
        return runViewer(*o);
    };
}

}  // namespace mvr::viewer
