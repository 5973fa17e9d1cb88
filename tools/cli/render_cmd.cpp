// `mvr render`: scene or model files → one PNG per view (+ depth), the anaglyph for a stereo
// pair, and any composite format.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>

#include <fmt/core.h>

#include "command.h"
#include "compose_options.h"
#include "options.h"
#include "mvr/session/pending.h"
#include "stereo_options.h"
#include "sequence.h"
#include "validators.h"

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/core/synthesize.h"
#include "mvr/session/direct.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/sequence.h"

namespace mvr::cli {
namespace {

struct RenderOptions {
    SceneOptions scene;
    std::string backend;  ///< default: the registry's first backend
    std::string method;   ///< empty: the backend's default (its fastest exact method)
    std::string outDir = "out";
    std::vector<std::string> formats;
    bool depth = false;
    bool cameras = false;  ///< --write-cameras
    std::string pngCompression = "fast";  ///< --png-compression
    std::string depthFormat = "png16";    ///< --depth-format
    std::string write;                    ///< --write: what is written (empty: the defaults)
    bool quiet = false;
    bool check = false;
    bool direct = false;  ///< --direct (mvr/session/direct.h)
    composite::ComposeOptions compose;
    StereoSurfaceOptions surfaces;  ///< --sky, --floating-window, --letterbox, --label…
    SequenceOptions sequence;       ///< --frames, --orbit, ...: sequence.cpp owns the frame loop
    std::string reportJson;         ///< --report-json FILE: the comfort report (docs/displays.md)
    std::string viewRange;          ///< --view-range A:B (mvr/session/view_range.h)
    const CLI::App* app = nullptr;  ///< the parsed command: which options were given
    CLI::Option* calibrationOption = nullptr;  ///< --lenticular-calibration (a preset's lenticular)
    CLI::Option* quiltOption = nullptr;        ///< --quilt (overrides a preset's grid)
};

/// `--check`: renders the reference — the backend's multipass, or the registry's first
/// backend's multipass when the method is multipass itself — and prints, per view, the fraction
/// of pixels with a channel more than 2/255 off it (the conformance suite's and
/// src/gl/README.md's "wrong pixels") and the largest channel difference.
Status checkAgainstReference(const std::string& backendName, const std::string& method,
                             const Prepared& p, const RenderOutput& out) {
    std::string refName = backendName;
    if (method == "multipass" || out.method == "multipass") refName = backendNames().front();
    auto ref = makeBackend(refName);
    if (!ref) return ref.status();
    if (Status s = (*ref)->supports("multipass"); !s) return s;
    std::optional<TerminalProgress> progress;
    progress.emplace(fmt::format("rendering the reference {}:multipass", refName));
    auto reference = (*ref)->render(p.scene, p.rig, p.settings, "multipass");
    progress.reset();
    if (!reference) return reference.status();
    const std::vector<ViewDifference> diffs = viewDifferences(out.color, reference->color);
    for (std::size_t v = 0; v < diffs.size(); ++v) {
        const ViewDifference& d = diffs[v];
        fmt::print(
            "check: view {}: {}:{} vs {}:multipass: {:.2f} % of the pixels differ by more than "
            "{}/255 ({} of {}); largest difference {}/255\n",
            v, backendName, out.method, refName, d.percent(), kArtifactThreshold, d.differing,
            d.pixels, d.maxDelta);
    }
    return {};
}

/// `--check` with `--synthesize K`: renders every view exactly (the same backend and method,
/// surfaces drawn) and prints, per warped view, its PSNR against the exact one and the fraction
/// of pixels with a channel more than 2/255 off, then the worst view.
Status checkSynthesis(Backend& backend, const std::string& method, const Prepared& p,
                      const StereoSurfaces& surfaces, const RenderOutput& out) {
    std::optional<TerminalProgress> progress;
    progress.emplace(fmt::format("rendering the {} views exactly", p.rig.viewCount()));
    auto exact = backend.render(p.scene, p.rig, p.settings, method);
    progress.reset();
    if (!exact) return exact.status();
    if (Status s = applySurfaces(surfaces, p.rig, *exact); !s) return s;
    const std::vector<char> isExact =
        exactMask(int(out.color.size()), exactViews(p.rig, p.synthesize));
    double worst = std::numeric_limits<double>::infinity(), worstShare = 0.0;
    int warped = 0;
    for (std::size_t v = 0; v < out.color.size(); ++v) {
        if (isExact[v]) continue;
        const ImageDiff e = compareImages(out.color[v], exact->color[v], kArtifactThreshold);
        ++warped;
        worst = std::min(worst, e.psnr);
        worstShare = std::max(worstShare, e.percentDiffering());
        fmt::print("check: view {} (warped): PSNR {:.2f} dB against the exact view; {:.2f} % of "
                   "the pixels differ by more than {}/255 ({} of {})\n",
                   v, e.psnr, e.percentDiffering(), kArtifactThreshold, e.differingPixels,
                   e.pixels);
    }
    fmt::print("check: --synthesize {}: {} of {} views warped; lowest PSNR {:.2f} dB, at most "
               "{:.2f} % of a view's pixels more than {}/255 off\n",
               p.synthesize, warped, out.color.size(), worst, worstShare, kArtifactThreshold);
    return {};
}

/// `--direct`: the lenticular image composed from the views' rows as they are finished
/// (mvr/session/direct.h), written alone.
int runDirect(const RenderOptions& o, const Prepared& p, Backend& backend,
              const std::string& method, const StereoSurfaces& surfaces,
              const std::function<void()>& printNotes) {
    for (const auto& [given, option] :
         {std::pair{o.check, "--check"}, std::pair{!o.reportJson.empty(), "--report-json"},
          std::pair{!o.viewRange.empty(), "--view-range"}}) {
        if (given)
            return fail(usageError(fmt::format(
                "--direct: keeps no view, so {} has nothing to read (leave one of them out)",
                option)));
    }
    std::vector<std::string> notes;
    const session::FrameOutputs outputs = session::frameOutputs(p);
    if (Status s = session::checkDirect(p, outputs, surfaces, backend,
                                        o.backend.empty() ? backend.name() : o.backend, method,
                                        &notes);
        !s)
        return fail(s);
    printNotes();
    for (const std::string& note : notes)
        if (!o.quiet) fmt::print(stderr, "{}\n", note);
    const auto start = std::chrono::steady_clock::now();
    std::optional<TerminalProgress> progress;
    const composite::LenticularCalibration& cal = outputs.compose.lenticular;
    progress.emplace(fmt::format("rendering {} views of {}x{} into a {}x{} panel", p.rig.viewCount(),
                                 p.settings.width, p.settings.height,
                                 cal.screenWidth > 0 ? cal.screenWidth : p.settings.width,
                                 cal.screenHeight > 0 ? cal.screenHeight : p.settings.height));
    auto panel = session::renderDirectLenticular(backend, p.scene, p.rig, p.settings, method,
                                                 outputs.compose.lenticular);
    progress.reset();
    if (!panel) return fail(panel.status());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const int panelWidth = panel->width, panelHeight = panel->height;
    auto files = session::writeDirectPanel(o.outDir, std::move(panel).value(), p.rig, outputs,
                                           &backend, method);
    if (!files) return fail(files.status());
    if (!o.quiet) {
        fmt::print("rendered {} ({} triangles) from {} views at {}x{} straight into a {}x{} "
                   "lenticular panel, {} shading, soft:{} in {:.1f} ms\n",
                   p.sceneName, p.scene.triangleCount(), p.rig.viewCount(), p.settings.width,
                   p.settings.height, panelWidth, panelHeight, shadingName(p.settings.shading),
                   method, ms);
        fmt::print("wrote:\n");
        for (const std::string& w : files->paths) fmt::print("  {}\n", w);
    }
    return 0;
}

/// The recipe of the command line (mvr/session/recipe.h).
session::RenderRecipe recipeOf(const RenderOptions& o) {
    session::RenderRecipe r = o.scene.recipe();
    const bool calibrationGiven = o.calibrationOption && o.calibrationOption->count() > 0;
    if (calibrationGiven && o.compose.lenticular.viewCone > 0.0)
        r.calibrationViewCone = o.compose.lenticular.viewCone;
    r.surfaces = o.surfaces.recipe();
    r.sequence = o.sequence;
    r.outputs.directory = o.outDir;
    r.outputs.formats = o.formats;
    r.outputs.depth = o.depth;
    r.outputs.cameras = o.cameras;
    r.outputs.pngCompression = o.pngCompression;
    r.outputs.depthFormat = o.depthFormat;
    r.outputs.write = o.write;
    r.outputs.reportJson = o.reportJson;
    r.outputs.compose = o.compose;
    r.outputs.calibrationGiven = calibrationGiven;
    r.outputs.quiltGiven = o.quiltOption && o.quiltOption->count() > 0;
    r.outputs.direct = o.direct;
    r.viewRange = o.viewRange;
    r.backend = o.backend;
    r.method = o.method;
    if (o.app) {
        for (const CLI::Option* opt : o.app->get_options())
            if (opt->count() > 0) r.given.push_back(opt->get_name());
    }
    return r;
}

int runRender(const RenderOptions& o) {
    const session::RenderRecipe recipe = recipeOf(o);
    auto prepared = session::prepare(recipe);
    if (!prepared) return fail(prepared.status());
    if (o.outDir.empty()) return fail(usageError("-o '': expected an output directory"));
    // An option given an empty value is a mistake (a shell variable unset), never "the default".
    if (o.app) {
        for (const CLI::Option* opt : o.app->get_options()) {
            for (const std::string& value : opt->results()) {
                if (opt->get_type_size() != 0 && value.empty()) {
                    return fail(usageError(
                        fmt::format("{} '': expected a value", opt->get_name())));
                }
            }
        }
    }
    auto backend = makeBackend(o.backend);
    if (!backend) {
        return fail(Status(backend.status().code(),
                           fmt::format("--backend {}: {}", o.backend, backend.status().message())));
    }
    const std::string method = o.method.empty() ? (*backend)->defaultMethod() : o.method;
    if (Status s = (*backend)->supports(method); !s) {
        return fail(Status(s.code(), fmt::format("--method {}: {}", method, s.message())));
    }
    const Prepared& p = *prepared;
    auto surfaces = session::buildSurfaces(recipe, p);
    if (!surfaces) return fail(surfaces.status());

    if (Status s = checkSequenceOptions(recipe.sequence); !s) return fail(s);
    if (recipe.sequence.active()) {  // its frames and --camera-path file, before -o is made
        if (auto plan = session::planSequence(recipe.sequence); !plan) return fail(plan.status());
    }

    // The notes once the whole request is accepted: a refused one prints its error line alone.
    auto printNotes = [&] {
        for (const std::string& note : prepared->notes) {  // -q keeps the warnings only
            if (!o.quiet || note.rfind("note: ", 0) != 0) fmt::print(stderr, "{}\n", note);
        }
    };
    const session::FrameOutputs outputs = session::frameOutputs(p);

    if (recipe.outputs.direct && recipe.sequence.active())
        return fail(usageError("--direct: renders a still; a sequence's frames need their views "
                               "(leave --direct out)"));
    if (recipe.sequence.active()) {
        // The output folder, removed again (when empty) should no frame be complete.
        auto made = session::MadeFolders::make(o.outDir);
        if (!made) return fail(made.status());
        SequenceJob job{&p,      backend->get(), o.backend, method,
                        o.outDir, outputs,       o.quiet,   &*surfaces, &*made,
                        printNotes};
        return runSequence(recipe.sequence, job);
    }

    if (recipe.outputs.direct) return runDirect(o, p, **backend, method, *surfaces, printNotes);
    printNotes();
    const auto start = std::chrono::steady_clock::now();
    std::optional<TerminalProgress> progress;
    progress.emplace(fmt::format("rendering {} view{} of {}x{} on {}:{}", p.rig.viewCount(),
                                 p.rig.viewCount() == 1 ? "" : "s", p.settings.width,
                                 p.settings.height, o.backend, method));
    auto rendered = session::renderViews(**backend, p, p.scene, p.rig, p.settings, method);
    progress.reset();
    if (!rendered) return fail(rendered.status());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (Status s = applySurfaces(*surfaces, p.rig, *rendered); !s) return fail(s);
    const RenderOutput& out = *rendered;
    if (int(out.color.size()) != p.rig.viewCount()) {
        return fail(internalError(fmt::format("backend returned {} images for {} views",
                                              out.color.size(), p.rig.viewCount())));
    }

    progress.emplace(fmt::format("writing and composing {} view{}", p.rig.viewCount(),
                                 p.rig.viewCount() == 1 ? "" : "s"));
    const std::optional<ComfortReport> comfort = comfortReport(p.rig, out);
    const std::optional<ScreenComfortReport> screenComfort = screenComfortReport(p, comfort);
    // The images and the report are one set: all of it is written, or none (issue 44).
    std::vector<session::ExtraFile> extra;
    if (!o.reportJson.empty())
        extra.push_back({o.reportJson, comfortJson(p, comfort, screenComfort), "--report-json"});
    auto files = session::writeOutputs(o.outDir, out, p.rig, outputs, backend->get(), {}, extra);
    progress.reset();
    if (!files) return fail(files.status());
    const std::vector<std::string> written = std::move(files->paths);
    session::setOutputProgress(fmt::format("every file is in place in {}/", o.outDir));
    for (const std::string& w : renderWarnings(p, out, comfort, screenComfort))
        fmt::print(stderr, "{}\n", w);
    if (!o.quiet) {
        fmt::print(
            "rendered {} ({} triangles) from {} view{} at {}x{}, {} shading, {}:{}{} in {:.1f} ms\n",
            p.sceneName, p.scene.triangleCount(), p.rig.viewCount(),
            p.rig.viewCount() == 1 ? "" : "s", p.settings.width, p.settings.height,
            shadingName(p.settings.shading), o.backend, out.method,
            out.note.empty() ? "" : " (" + out.note + ")", ms);
        fmt::print(
            "rig: {} {}x{}, interaxial {:.4g}, convergence {:.4g}, separation {:.2f}% of screen width\n",
            rigKindName(p.rig.kind), p.rig.columns, p.rig.rows, p.rig.interaxial, p.rig.convergence,
            100.0 * p.rig.separation());
        if (comfort) fmt::print("{}\n", comfort->line);
        if (screenComfort) fmt::print("{}\n", screenComfort->line);
        fmt::print("wrote:\n");
        for (const std::string& w : written) fmt::print("  {}\n", w);
    }
    if (o.check) {
        const Status s = p.synthesize > 1
                             ? checkSynthesis(**backend, method, p, *surfaces, out)
                             : checkAgainstReference(o.backend, method, p, out);
        if (!s) return fail(s);
    }
    return 0;
}

const CommandRegistrar kRender(10, [](CLI::App& root) -> std::function<int()> {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* app = root.add_subcommand(
        "render",
        "Render a scene or model files from N viewpoints into DIR/view-0.png ... view-{N-1}.png "
        "(views numbered left to right, then top to bottom), plus DIR/anaglyph.png for a stereo pair");
    o->scene.addTo(app);
    o->app = app;
    o->backend = backendNames().front();
    std::string backendHelp = "Backend:";
    for (const std::string& name : backendChoices()) {  // the registry's rows, then auto
        auto e = findBackend(name);
        if (!e) continue;
        backendHelp += fmt::format("{} {} ({})", backendHelp.back() == ':' ? "" : ";", name,
                                   (*e)->description);
    }
    app->add_option("--backend", o->backend, backendHelp)->default_val(o->backend);
    app->add_option(
        "--method", o->method,
        "Method of the backend (see `mvr info`); default: the backend's fastest exact "
        "method (soft unified, bit-identical to soft multipass, the reference; gl auto, "
        "measured)")
        ->check(nonEmpty("a method of the backend; `mvr info` lists them"));
    app->add_option("-o,--output", o->outDir, "Output directory")->default_val(o->outDir);
    app->add_flag("--depth", o->depth, "Also write depth-0.png ... (16-bit, near = black)");
    app->add_option("--depth-format", o->depthFormat,
                    "The depth files: png16 (depth-N.png, 16-bit, near = black) or exr "
                    "(depth-N.exr: linear eye-space distance in world units, +inf where empty)")
        ->default_val(o->depthFormat);
    app->add_option("--png-compression", o->pngCompression,
                    "PNG compression, lossless in every mode: fast (zlib level 1: ~4x faster "
                    "to write, ~10 % larger), default (libpng's), small (level 9, slowest)")
        ->default_val(o->pngCompression);
    app->add_flag("--write-cameras", o->cameras,
                  "Also write cameras.json: every view's world-from-camera, view and projection "
                  "matrices, pinhole intrinsics (fx, fy, cx, cy) and near / far "
                  "(conventions: include/mvr/session/cameras.h)");
    app->add_option("--write", o->write,
                    "What to write, a comma list of views, depth, composites (anaglyph.png of "
                    "a pair, --format's files), cameras, video. Default: views and composites; "
                    "a --display preset only its composite; a sequence with --video only the "
                    "video. --depth and --write-cameras add theirs")
        ->type_name("LIST");
    app->add_flag("-q,--quiet", o->quiet, "Print nothing on success");
    app->add_flag("--check", o->check,
                  "Also render the reference (the backend's multipass; for a multipass method, "
                  "the first backend's multipass) and print per view the fraction of pixels "
                  "more than 2/255 off it and the largest difference");
    app->add_flag("--direct", o->direct,
                  "With --format lenticular (or a display preset and its calibration): compose "
                  "the panel image from the views' rows as soft:unified finishes them, with no "
                  "view or quilt in memory; the same pixels as composing the rendered views "
                  "(a preset's quilt is then not written; docs/displays.md)");
    app->add_option("--format", o->formats,
                    "Also write composites: DIR/<format>.png (.mpo, .jps); repeatable")
        ->check(CLI::IsMember(composite::formatNames()));
    addComposeOptions(app, o->compose);
    o->calibrationOption = app->get_option("--lenticular-calibration");
    o->quiltOption = app->get_option("--quilt");
    app->add_option("--report-json", o->reportJson,
                    "Write the comfort report (parallax range, the screen's budget, the rules "
                    "broken; fields in docs/displays.md) to FILE as JSON")
        ->type_name("FILE");
    app->add_option("--view-range", o->viewRange,
                    "Render only views A..B (both included) of the rig, named as in the whole "
                    "render (view-A.png ... view-B.png), for farms that split a quilt's views; "
                    "no composites (render the ranges, then `mvr compose`)")
        ->type_name("A:B");
    o->surfaces.addTo(app);
    addSequenceOptions(app, o->sequence);
    return [o] { return runRender(*o); };
});

}  // namespace
}  // namespace mvr::cli
