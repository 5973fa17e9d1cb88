// The frame loop of `mvr render --frames / --orbit / --camera-path`: one folder per frame
// (frame-0000/view-3.png and its composites), written under frame-0000.part and renamed when
// complete, optionally a video file of one composite (or one stream per view).
#include "sequence.h"
#include "stereo_options.h"

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <thread>

#include <fmt/core.h>

#include "camera_path.h"
#include "distribute.h"
#include "video.h"

#include "mvr/backends.h"
#include "mvr/core/animation.h"

namespace mvr::cli {

void addSequenceOptions(CLI::App* app, SequenceOptions& o) {
    app->add_option("--frames", o.frames,
                    "Render a sequence of F frames into DIR/frame-0000/ ... (views and composites "
                    "per frame)");
    app->add_option("--orbit", o.orbit,
                    "Turntable: turn the camera (and the rig with it) DEG degrees about the "
                    "scene centre over the frames (frame f at DEG·f/F)");
    app->add_option(
        "--camera-path", o.cameraPath,
        "Keyframed camera path, a JSON file (docs/animation.md); frame f at time f/fps");
    app->add_option("--frame-range", o.frameRange,
                    "Render only frames A..B-1 of the sequence (A:B; either may be empty)");
    app->add_option("--shard", o.shard,
                    "Render only the frames f with f mod N = I (I/N, 0 <= I < N): a share for a "
                    "job array");
    app->add_option("--fps", o.fps, "Frames per second (camera path times, video)")
        ->default_val(o.fps);
    app->add_option("--threads", o.threads,
                    "CPU threads of a sequence's backend per process (0: the cores, divided by "
                    "the MPI ranks on this node less one for rank 0)")
        ->default_val(o.threads);
    app->add_flag("--gather-stats", o.gatherStats,
                  "Under mpirun: rank 0 prints the time it spent receiving the views (the "
                  "gather) per frame");
    app->add_option("--video", o.video,
                    "Also write a video (.mkv or .mp4, H.264) of the first --format that is one "
                    "image per frame, or of every view (one stream each) without one");
}

namespace {

Result<std::pair<int, int>> parseRange(const std::string& text, int frames) {
    if (text.empty()) return std::pair{0, frames};
    static const std::regex kRange(R"(\s*(\d*)\s*:\s*(\d*)\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kRange)) {
        return usageError(fmt::format("--frame-range '{}' is not of the form A:B", text));
    }
    // More than 9 digits is past any frame count (and past what std::stol may hold).
    auto number = [](const std::string& digits, long none) {
        if (digits.empty()) return none;
        return digits.size() > 9 ? 1000000000L : std::stol(digits);
    };
    const long a = number(m[1].str(), 0);
    const long b = number(m[2].str(), frames);
    if (a >= b || b > frames) {
        return usageError(fmt::format(
            "--frame-range '{}' is out of range (expected 0 <= A < B <= {} frames)", text, frames));
    }
    return std::pair{int(a), int(b)};
}

Result<std::pair<int, int>> parseShard(const std::string& text) {
    if (text.empty()) return std::pair{0, 1};
    static const std::regex kShard(R"(\s*(\d{1,6})\s*/\s*(\d{1,6})\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kShard)) {
        return usageError(fmt::format("--shard '{}' is not of the form I/N (e.g. 0/4)", text));
    }
    const int i = std::stoi(m[1].str()), n = std::stoi(m[2].str());
    if (n < 1 || i >= n) {
        return usageError(fmt::format("--shard '{}' is out of range (expected 0 <= I < N)", text));
    }
    return std::pair{i, n};
}

/// Rank 0's report: a bar on a terminal, else one line per finished frame.
class FrameProgress {
public:
    FrameProgress(int total, bool quiet) : mTotal(total), mQuiet(quiet), mTty(::isatty(2)) {}
    void done(int frame) {
        ++mDone;
        if (mQuiet) return;
        const double s = std::chrono::duration<double>(Clock::now() - mStart).count();
        const double fps = s > 0 ? mDone / s : 0.0;
        const double left = fps > 0 ? (mTotal - mDone) / fps : 0.0;
        if (mTty) {
            const int width = 30, filled = mTotal ? width * mDone / mTotal : width;
            fmt::print(stderr, "\r[{}{}] {}/{} frames, {:.2f} frames/s, {:.0f} s left\033[K",
                       std::string(filled, '#'), std::string(width - filled, '.'), mDone, mTotal,
                       fps, left);
            if (mDone == mTotal) fmt::print(stderr, "\n");
        } else {
            fmt::print(stderr, "frame {} done ({}/{}), {:.2f} frames/s, {:.0f} s left\n", frame,
                       mDone, mTotal, fps, left);
        }
        std::fflush(stderr);
    }
    double seconds() const { return std::chrono::duration<double>(Clock::now() - mStart).count(); }

private:
    using Clock = std::chrono::steady_clock;
    int mTotal, mDone = 0;
    bool mQuiet, mTty;
    Clock::time_point mStart = Clock::now();
};

}  // namespace

Status checkSequenceOptions(const SequenceOptions& o) {
    if (o.frames < 0) {
        return usageError(
            fmt::format("--frames {} is out of range (expected 1..1000000)", o.frames));
    }
    if (!(o.fps > 0.0 && o.fps <= 1000.0)) {
        return usageError(fmt::format("--fps {} is out of range (expected 0 < fps <= 1000)", o.fps));
    }
    if (o.active()) return {};
    // Options of a sequence without one would be ignored: say so instead.
    for (const auto& [name, value] : {std::pair{"--video", o.video},
                                      std::pair{"--frame-range", o.frameRange},
                                      std::pair{"--shard", o.shard}}) {
        if (!value.empty()) {
            return usageError(fmt::format(
                "{} {} needs a sequence (--frames F, --orbit DEG or --camera-path FILE)", name,
                value));
        }
    }
    return {};
}

int runSequence(const SequenceOptions& o, const SequenceJob& job) {
    const Prepared& p = *job.prepared;
    if (!std::isfinite(o.orbit)) {
        return fail(usageError(fmt::format("--orbit {} is not a finite angle (degrees)", o.orbit)));
    }
    if (!(o.fps > 0.0 && o.fps <= 1000.0)) {
        return fail(
            usageError(fmt::format("--fps {} is out of range (expected 0 < fps <= 1000)", o.fps)));
    }
    if (o.orbit != 0.0 && !o.cameraPath.empty()) {
        return fail(usageError("--orbit and --camera-path exclude each other"));
    }
    std::optional<CameraPath> path;
    if (!o.cameraPath.empty()) {
        auto read = readCameraPath(o.cameraPath);
        if (!read) return fail(read.status());
        path = std::move(read).value();
    }
    int frames = o.frames;
    if (frames == 0 && path) frames = int(std::floor(path->duration() * o.fps)) + 1;
    if (frames < 1 || frames > 1000000) {
        return fail(usageError(fmt::format(
            "--frames {} is out of range (expected 1..1000000; --orbit needs --frames)", frames)));
    }
    auto range = parseRange(o.frameRange, frames);
    if (!range) return fail(range.status());
    auto shard = parseShard(o.shard);
    if (!shard) return fail(shard.status());
    if (!o.video.empty() && shard->second > 1) {
        return fail(usageError("--video needs every frame in one process (not with --shard)"));
    }
    std::vector<int> todo;
    for (int f = range->first; f < range->second; ++f) {
        if (f % shard->second == shard->first) todo.push_back(f);
    }

    // The video's composite: the first one-image format, else every view as a stream.
    std::string videoFormat;
    for (const std::string& format : job.outputs.formats) {
        auto info = composite::findFormat(format);
        if (!info) return fail(info.status());
        if (videoFormat.empty() && info->extension == ".png") videoFormat = format;
    }
    composite::ComposeOptions compose = job.outputs.compose;
    compose.baseline = p.rig.interaxial;
    compose.convergence = p.rig.convergence;

    if (!o.video.empty()) {
        // Refuse what the video cannot take before rendering anything.
        const std::string ext = std::filesystem::path(o.video).extension().string();
        if (ext != ".mkv" && ext != ".mp4") {
            return fail(
                usageError(fmt::format("--video {}: expected a .mkv or .mp4 file", o.video)));
        }
        if (!videoAvailable()) {
            return fail(unsupportedError(fmt::format(
                "--video {}: this mvr was built without FFmpeg (libavcodec, libavformat, "
                "libswscale)",
                o.video)));
        }
        composite::Size size{p.settings.width, p.settings.height};
        if (!videoFormat.empty()) {
            auto s = composite::outputSize(videoFormat, p.rig.viewCount(), size.width, size.height,
                                           compose);
            if (!s) return fail(s.status());
            size = *s;
        }
        if (size.width % 2 || size.height % 2) {
            return fail(usageError(fmt::format(
                "--video {}: H.264 4:2:0 needs an even width and height (the frames are {}x{})",
                o.video, size.width, size.height)));
        }
    }
    // Threads per process: the cores shared by the ranks of this node, so they do not fight.
    int threads = o.threads;
    if (threads < 0 || threads > 1024) {
        return fail(usageError(fmt::format("--threads {} is out of range (0..1024)", threads)));
    }
    if (threads == 0) {
        if (const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE")) {
            // Rank 0 only composes and writes: it does not count (one rank per node plus rank 0
            // on the first node gives every node's worker all its cores).
            const int ranks = std::max(1, std::atoi(local) - 1);
            threads = std::max(1, int(std::thread::hardware_concurrency()) / ranks);
        }
    }
    std::unique_ptr<Backend> ownBackend;
    if (threads > 0) {
        auto made = makeBackend(job.backendName, {threads});
        if (!made) return fail(made.status());
        ownBackend = std::move(made).value();
    }
    Backend& backend = ownBackend ? *ownBackend : *job.backend;

    std::unique_ptr<VideoWriter> video;
    const std::filesystem::path dir(job.outDir);
    FrameProgress progress(int(todo.size()), job.quiet);
    const int digits = std::max(4, int(std::to_string(frames - 1).size()));
    // The file's animation (glTF): its nodes move in a copy of the scene, made once.
    std::optional<Scene> animated;
    if (p.animation) animated = p.scene;
    // Renders views [v0, v1) of frame f (the rig moving with the camera).
    auto renderViews = [&](int f, int v0, int v1) -> Result<RenderOutput> {
        const double time = f / o.fps;
        if (animated) animateScene(*animated, *p.animation, time);
        Camera camera = p.rig.camera;
        if (o.orbit != 0.0) {
            camera = orbitCamera(camera, p.rig.camera.target, orbitDegrees(o.orbit, f, frames));
        } else if (path) {
            camera = cameraAt(*path, time, p.rig.camera);
        } else if (animated && p.animation->cameraNode >= 0 && animated->camera) {
            // The file's animated camera (--orbit and --camera-path win over it).
            camera = cameraFromNode(animated->camera->worldFromCamera, p.rig.camera);
        }
        auto rig = rigAt(p.rig, camera);
        if (!rig) {
            return Status(rig.status().code(),
                          fmt::format("frame {}: {}", f, rig.status().message()));
        }
        if (v0 > 0 || v1 < rig->viewCount()) {
            // A share of the views: the culling frustum still encloses all of them.
            rig->views = std::vector<View>(rig->views.begin() + v0, rig->views.begin() + v1);
        }
        auto rendered = backend.render(animated ? *animated : p.scene, *rig, p.settings, job.method);
        if (!rendered) {
            return Status(rendered.status().code(),
                          fmt::format("frame {}: {}", f, rendered.status().message()));
        }
        if (job.surfaces && job.surfaces->floatingWindow &&
            int(rig->views.size()) != p.rig.viewCount()) {
            // The floating window's strips depend on the outermost views of the row, which a
            // share of the views does not hold (sky, labels and letterbox are per view).
            return usageError(
                "--floating-window needs every view of a frame in one rank: give at least as "
                "many frames as worker ranks");
        }
        if (job.surfaces) {
            if (Status s = applySurfaces(*job.surfaces, *rig, *rendered); !s) {
                return Status(s.code(), fmt::format("frame {}: {}", f, s.message()));
            }
        }
        if (!job.outputs.depth) rendered->depth.clear();  // not written, not sent between ranks
        return rendered;
    };
    auto emitFrame = [&](int f, const RenderOutput& out) -> Status {
        const std::string name = fmt::format("frame-{:0{}}", f, digits);
        const std::filesystem::path part = dir / (name + ".part"), final = dir / name;
        std::error_code ec;
        std::filesystem::remove_all(part, ec);
        std::filesystem::create_directories(part, ec);
        if (ec) {
            return (
                outputError(fmt::format("cannot create '{}': {}", part.string(), ec.message())));
        }
        // The frame's files, as a still's (anaglyph.png for a pair included).
        auto files = session::writeOutputs(part, out, p.rig, job.outputs, &backend,
                                           o.video.empty() ? std::string() : videoFormat);
        if (!files) return files.status();
        std::optional<Image> videoImage = std::move(files->kept);
        std::filesystem::remove_all(final, ec);
        std::filesystem::rename(part, final, ec);
        if (ec) {
            return (outputError(fmt::format("cannot rename '{}' to '{}': {}", part.string(),
                                            final.string(), ec.message())));
        }
        if (!o.video.empty()) {
            const Image& first = videoImage ? *videoImage : out.color[0];
            if (!video) {
                const int streams = videoImage ? 1 : int(out.color.size());
                auto opened = VideoWriter::open(
                    o.video, streams, first.width, first.height, o.fps,
                    videoImage ? matroskaStereoMode(videoFormat, compose.swapEyes) : std::string());
                if (!opened) return (opened.status());
                video = std::move(opened).value();
            }
            if (videoImage) {
                if (Status s = video->add(0, *videoImage); !s) return (s);
            } else {
                for (int v = 0; v < int(out.color.size()); ++v) {
                    if (Status s = video->add(v, out.color[v]); !s) return (s);
                }
            }
        }
        progress.done(f);
        return {};
    };
    if (Status s = distributeFrames(todo, p.rig.viewCount(), renderViews, emitFrame,
                                    o.gatherStats);
        !s) {
        return fail(s);
    }
    if (!isRankZero()) return 0;
    if (video) {
        if (Status s = video->finish(); !s) return fail(s);
    }
    if (!job.quiet) {
        fmt::print("rendered {} frame{} of {} ({} view{} of {}x{}, {}:{}) in {:.2f} s into {}/\n",
                   todo.size(), todo.size() == 1 ? "" : "s", frames, p.rig.viewCount(),
                   p.rig.viewCount() == 1 ? "" : "s", p.settings.width, p.settings.height,
                   job.backendName, job.method, progress.seconds(), job.outDir);
        if (video) fmt::print("wrote video {}\n", o.video);
    }
    return 0;
}

}  // namespace mvr::cli
