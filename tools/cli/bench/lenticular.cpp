// `mvr bench lenticular` (issue 43): direct lenticular rendering against the quilt path. Per
// display (the Looking Glass Portrait's calibration, a Go-like one), side by side frame after
// frame on one backend: one view; the quilt path — the N views rendered whole (soft:unified)
// and composed by composite::lenticular(); and --direct (mvr/session/direct.h), the panel
// composed from the views' rows as the bands finish. Medians; the two panels compared once.
#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <fmt/format.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "options.h"

#include "mvr/backends.h"
#include "mvr/composite/lenticular.h"
#include "mvr/session/direct.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"

namespace mvr::cli::bench {
namespace {

struct LenticularOptions {
    std::vector<std::string> models;
    int grid = 1;
    std::vector<std::string> displays{"portrait", "go"};
    int frames = 5;
    int aa = 1;
};

/// A display's calibration: the Portrait's visual.json values (tests/fuzz/corpus/visual_json);
/// for the Go, its panel (1440x2560, 491 DPI) under Portrait-like lenses — a stand-in, no Go
/// visual.json being at hand; the cost hardly depends on the lens values.
composite::LenticularCalibration calibrationOf(const std::string& display) {
    composite::LenticularCalibration c;
    c.pitch = 52.59267044067383, c.slope = -7.083540916442871, c.center = 0.8167931437492371;
    c.dpi = 324.0;
    c.invertViews = true, c.flipY = true, c.bgr = true;
    if (display == "go") c.dpi = 491.0;
    return c;  // the screen size: the preset's panel (prepare())
}

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

int runLenticular(const LenticularOptions& o) {
    auto backend = makeBackend("soft");
    if (!backend) return fail(backend.status());
    fmt::print("Direct lenticular rendering (issue 43): soft, {} frames after 1 warm-up each, "
               "medians; --aa {}, angular anti-aliasing off\n\n",
               o.frames, o.aa);
    fmt::print("| display | views | panel | one view | quilt path (render + compose) | direct "
               "| direct / quilt path | direct × one view | same pixels |\n"
               "|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& display : o.displays) {
        session::RenderRecipe r;
        r.models = o.models;
        r.grid = o.grid;
        r.display = display;
        r.aa = o.aa;
        r.surfaces.angularAA = "off";
        r.outputs.compose.lenticular = calibrationOf(display);
        r.outputs.calibrationGiven = true;
        r.outputs.direct = true;
        auto prepared = session::prepare(r);
        if (!prepared) return fail(prepared.status());
        const Prepared& p = *prepared;
        const composite::LenticularCalibration cal = session::frameOutputs(p).compose.lenticular;
        Rig one = p.rig;
        one.views = {p.rig.views[p.rig.views.size() / 2]};
        one.columns = 1;
        std::vector<double> oneMs, renderMs, composeMs, quiltMs, directMs;
        bool same = true;
        for (int f = 0; f <= o.frames; ++f) {
            auto t = Clock::now();
            auto single = (*backend)->render(p.scene, one, p.settings, "unified");
            if (!single) return fail(single.status());
            const double oneView = msSince(t);
            t = Clock::now();
            auto views = (*backend)->render(p.scene, p.rig, p.settings, "unified");
            if (!views) return fail(views.status());
            const double render = msSince(t);
            t = Clock::now();
            auto composed = composite::lenticular(views->color, cal);
            if (!composed) return fail(composed.status());
            const double compose = msSince(t);
            views = Result<RenderOutput>(RenderOutput{});  // the quilt's memory given back
            t = Clock::now();
            auto direct = session::renderDirectLenticular(**backend, p.scene, p.rig, p.settings,
                                                          "unified", cal);
            if (!direct) return fail(direct.status());
            const double directPath = msSince(t);
            if (f == 0) {  // the warm-up frame: the comparison
                same = direct->rgba == composed->rgba;
                continue;
            }
            oneMs.push_back(oneView), renderMs.push_back(render), composeMs.push_back(compose);
            quiltMs.push_back(render + compose), directMs.push_back(directPath);
        }
        const double one1 = statsOf(oneMs).median, quilt = statsOf(quiltMs).median,
                     direct = statsOf(directMs).median;
        fmt::print("| {} | {} of {}x{} | {}x{} | {:.1f} ms | {:.1f} ms ({:.1f} + {:.1f}) | {:.1f} "
                   "ms | {:.2f}× | {:.2f}× | {} |\n",
                   display, p.rig.viewCount(), p.settings.width, p.settings.height,
                   cal.screenWidth, cal.screenHeight, one1, quilt, statsOf(renderMs).median,
                   statsOf(composeMs).median, direct, direct / quilt, direct / one1,
                   same ? "yes" : "NO");
        if (!same) return fail(internalError(fmt::format(
                       "{}: the direct panel differs from the composed views", display)));
    }
    return 0;
}

}  // namespace

PaperBench addLenticular(CLI::App* bench) {
    auto o = std::make_shared<LenticularOptions>();
    CLI::App* app = bench->add_subcommand(
        "lenticular",
        "Direct lenticular rendering (issue 43): per display, one view, the quilt path (the "
        "views rendered, then composed) and --direct, side by side; medians, × the quilt path "
        "and × one view");
    addModelOptions(app, o->models, o->grid);
    app->add_option("--displays", o->displays, "Displays, comma separated (default portrait,go)")
        ->delimiter(',');
    app->add_option("--frames", o->frames, "Timed frames per display")
        ->default_val(o->frames)
        ->check(CLI::Range(1, 1000));
    app->add_option("--aa", o->aa, "Samples a pixel (1, 2, 4, 8)")->default_val(o->aa);
    return {app, [o] { return runLenticular(*o); }};
}

}  // namespace mvr::cli::bench
