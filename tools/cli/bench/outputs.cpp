// `mvr bench outputs` (issue 37): the way out as fast as the render? For each configuration of
// the table — 48 views of 420×560 as PNGs, the Looking Glass Portrait quilt, a 1080p
// side-by-side pair, a Portrait quilt video, a 1080p side-by-side video — what `mvr render`
// does, run in this process through the same session code: set-up (load, frame, rig), then
// per frame the render, composing, encoding and writing (summed over the threads that ran
// them), the video's encoding, and the whole run end to end with its frames per second.
// Sequences write beside the rendering as `mvr render` does (MVR_WRITE_QUEUE / --queue).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

#include <fmt/core.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bench/experiments.h"
#include "bench/harness.h"
#include "bench/report.h"
#include "options.h"
#include "sequence.h"
#include "video.h"

#include "mvr/backends.h"
#include "mvr/session/frame_queue.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/surfaces.h"

namespace mvr::cli::bench {

namespace {

namespace fs = std::filesystem;

struct OutputsOptions {
    std::vector<std::string> models;
    int grid = 1;
    std::vector<std::string> configs;  ///< empty: all
    bool full = false;
    bool tiny = false;
    int runs = 0;    ///< 0: 1, or 3 with --full
    int frames = 0;  ///< a video's frames; 0: the configuration's
    int queue = -1;  ///< sequences' write queue (MVR_WRITE_QUEUE); -1: the default
    int threads = 0;
    std::string backend = "soft";
    bool json = false;
};

/// A configuration: the options of `mvr render` it stands for, as a recipe.
struct Config {
    const char* name;
    const char* what;
    int views;             ///< 0: the display's
    const char* display;   ///< "" none
    int width, height;     ///< 0: the display's
    const char* format;    ///< "" none
    int frames, fullFrames;  ///< a video's frames (default, --full); 0: a still
    const char* video;     ///< the video's extension, "" none
};
constexpr Config kConfigs[] = {
    {"views", "--views 48 --size 420x560 (48 PNGs)", 48, "", 420, 560, "", 0, 0, ""},
    {"portrait", "--display portrait (the 3360x3360 quilt)", 0, "portrait", 0, 0, "", 0, 0, ""},
    {"sbs", "--views 2 --size 1920x1080 --format sbs (views, anaglyph, sbs)", 2, "", 1920, 1080,
     "sbs", 0, 0, ""},
    {"portrait-video", "--display portrait --orbit 90 --frames F --video q.mp4", 0, "portrait", 0,
     0, "", 3, 8, ".mp4"},
    {"sbs-video", "--views 2 --size 1920x1080 --format sbs --orbit 90 --frames F --video s.mkv",
     2, "", 1920, 1080, "sbs", 6, 24, ".mkv"},
};

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

session::RenderRecipe recipeOf(const Config& c, const OutputsOptions& o,
                               const std::vector<std::string>& models, const fs::path& dir) {
    session::RenderRecipe r;
    r.models = models;
    r.grid = o.grid;
    if (c.views) r.views = c.views;
    r.display = c.display;
    int w = c.width, h = c.height;
    if (o.tiny) {  // a tenth of each side (the Portrait's views: 42x56)
        if (!w) w = 420, h = 560;
        w = std::max(16, w / 10 / 2 * 2), h = std::max(16, h / 10 / 2 * 2);
    }
    if (w) r.size = fmt::format("{}x{}", w, h);
    if (*c.format) r.outputs.formats = {c.format};
    r.outputs.directory = dir.string();
    r.backend = o.backend;
    // Writing is measured, as before angular anti-aliasing (a post-process on the CPU, whose
    // cost bench/README.md gives apart): the Portrait rows keep their figures.
    r.surfaces.angularAA = "off";
    if (c.frames) {
        r.sequence.orbit = 90.0;
        r.sequence.frames = o.frames ? o.frames : o.full ? c.fullFrames : o.tiny ? 2 : c.frames;
        // "_qs": no warning about the quilt's layout in the name (the file is thrown away).
        r.sequence.video = (dir.parent_path() / fmt::format("{}_qs{}", c.name, c.video)).string();
        r.sequence.threads = o.threads;
    }
    return r;
}

/// One run of a configuration: its row (times in seconds, per frame where they add up).
Result<OutputsRow> runOnce(const Config& c, const OutputsOptions& o,
                           const std::vector<std::string>& models, const fs::path& dir) {
    OutputsRow row;
    row.config = c.name;
    row.command = c.what;
    const double cpu0 = processCpuMs();
    const auto start = Clock::now();
    const session::RenderRecipe recipe = recipeOf(c, o, models, dir);
    auto prepared = session::prepare(recipe);
    if (!prepared) return prepared.status();
    const Prepared& p = *prepared;
    auto backend = makeBackend(o.backend, {.threads = o.threads});
    if (!backend) return backend.status();
    const std::string method = (*backend)->defaultMethod();
    auto surfaces = session::buildSurfaces(recipe, p);
    if (!surfaces) return surfaces.status();
    const session::FrameOutputs outputs = session::frameOutputs(p);
    row.views = p.rig.viewCount();
    row.width = p.settings.width, row.height = p.settings.height;
    row.setup = secondsSince(start);
    const auto run = Clock::now();
    if (recipe.sequence.active()) {
        SequenceTimes times;
        SequenceJob job{&p, backend->get(), o.backend, method, dir.string(), outputs, true,
                        &*surfaces, nullptr, {}, &times};
        if (const int rc = runSequence(recipe.sequence, job); rc != 0) {
            return Status(ErrorCode::Internal, fmt::format("{}: mvr render failed", c.name));
        }
        row.frames = recipe.sequence.frames;
        row.render = times.render, row.compose = times.files.compose;
        row.encode = times.files.encode, row.write = times.files.write, row.video = times.video;
    } else {
        const auto t = Clock::now();
        auto rendered = (*backend)->render(p.scene, p.rig, p.settings, method);
        if (!rendered) return rendered.status();
        if (Status s = session::applySurfaces(*surfaces, p.rig, *rendered); !s) return s;
        row.render = secondsSince(t);
        auto files = session::writeOutputs(dir, *rendered, p.rig, outputs, backend->get());
        if (!files) return files.status();
        row.frames = 1;
        row.compose = files->times.compose, row.encode = files->times.encode;
        row.write = files->times.write;
        row.files = int(files->paths.size());
    }
    row.endToEnd = secondsSince(run);
    row.cpu = (processCpuMs() - cpu0) / 1000.0;
    return row;
}

int runOutputs(const OutputsOptions& o) {
    const int runs = o.runs > 0 ? o.runs : o.full ? 3 : 1;
    if (runs > 100) return fail(usageError(fmt::format("--runs {}: at most 100", runs)));
    if (o.frames < 0 || o.frames > 10000)
        return fail(usageError(fmt::format("--frames {} is out of range (0..10000)", o.frames)));
    if (o.threads < 0 || o.threads > 1024)
        return fail(usageError(fmt::format("--threads {} is out of range (0..1024)", o.threads)));
    std::vector<const Config*> configs;
    for (const Config& c : kConfigs) {
        if (o.configs.empty() ||
            std::find(o.configs.begin(), o.configs.end(), c.name) != o.configs.end())
            configs.push_back(&c);
    }
    for (const std::string& name : o.configs) {
        if (std::none_of(std::begin(kConfigs), std::end(kConfigs),
                         [&](const Config& c) { return name == c.name; }))
            return fail(usageError(fmt::format(
                "--configs {}: unknown (expected views, portrait, sbs, portrait-video, "
                "sbs-video)",
                name)));
    }
    std::vector<std::string> models = o.models;
    if (models.empty() && o.full) {
        auto bunny = findModel("", "stanford-bunny.obj");
        if (!bunny) return fail(bunny.status());
        models.push_back(*bunny);
    }
    OutputsOptions opts = o;
    if (o.full && o.grid == 1) opts.grid = 9;
    if (o.queue >= 0) ::setenv("MVR_WRITE_QUEUE", std::to_string(o.queue).c_str(), 1);
    BackendSet backends({.threads = o.threads});
    if (auto b = backends.get(o.backend); !b) return fail(b.status());

    OutputsReport report;
    const Machine machine = describeMachine(backends);
    report.machine = &machine;
    report.runs = runs;
    report.queue = session::writeQueueDepth();
    report.scene = models.empty() ? std::string("the procedural scene")
                                  : fmt::format("{} x{}", fmt::join(models, ", "), opts.grid);
    const fs::path tmp =
        fs::temp_directory_path() / fmt::format("mvr-bench-outputs-{}", ::getpid());
    std::error_code ec;
    for (const Config* c : configs) {
        if (c->frames && !videoAvailable()) {
            report.skipped.push_back(fmt::format("{}: this mvr was built without FFmpeg", c->name));
            continue;
        }
        std::vector<OutputsRow> samples;
        for (int r = 0; r < runs; ++r) {
            // Each run into a fresh folder (a first write, as a user's), removed after it.
            const fs::path dir = tmp / fmt::format("{}-{}", c->name, r) / "out";
            fs::create_directories(dir.parent_path(), ec);
            auto row = runOnce(*c, opts, models, dir);
            fs::remove_all(dir.parent_path(), ec);
            if (!row) {
                fs::remove_all(tmp, ec);
                return fail(row.status());
            }
            samples.push_back(std::move(row).value());
        }
        report.rows.push_back(medianRow(samples));
    }
    fs::remove_all(tmp, ec);
    return printOutputsReport(report, o.json);
}

}  // namespace

PaperBench addOutputs(CLI::App* bench) {
    auto o = std::make_shared<OutputsOptions>();
    CLI::App* app = bench->add_subcommand(
        "outputs",
        "Writing outputs (issue 37): per configuration (48 views as PNGs, the Portrait quilt, a "
        "1080p sbs pair, a Portrait quilt video, a 1080p sbs video), the set-up, and per frame "
        "the render, composing, encoding, writing and video encoding, the whole run end to end "
        "and its frames per second");
    addModelOptions(app, o->models, o->grid);
    app->add_option("--configs", o->configs,
                    "Configurations, comma separated: views, portrait, sbs, portrait-video, "
                    "sbs-video (default: all)")
        ->delimiter(',');
    app->add_flag("--full", o->full,
                  "The issue's table: stanford-bunny.obj --grid 9 (unless models are given), "
                  "videos of 8 and 24 frames, 3 runs each (medians)");
    app->add_flag("--tiny", o->tiny, "Every size a tenth, videos of 2 frames (a smoke test)");
    app->add_option("--runs", o->runs, "Runs of each configuration, medians (default 1; --full 3)");
    app->add_option("--frames", o->frames, "Frames of each video (default 3 and 6; --full 8 and 24)");
    app->add_option("--queue", o->queue,
                    "Frames a sequence's write queues hold (MVR_WRITE_QUEUE; 0: written one "
                    "frame at a time on the rendering thread)")
        ->check(CLI::Range(0, 8));
    app->add_option("--threads", o->threads, "soft: worker threads (0 = one per core)")
        ->default_val(o->threads);
    app->add_option("--backend", o->backend, "The backend rendering")->default_val(o->backend);
    app->add_flag("--json", o->json, "Print JSON: {bench, machine, scene, runs, queue, skipped, results: [...]}");
    return {app, [o] { return runOutputs(*o); }};
}

}  // namespace mvr::cli::bench
