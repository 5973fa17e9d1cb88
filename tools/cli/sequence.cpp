// The frame loop of `mvr render --frames / --orbit / --camera-path`: one folder per frame
// (frame-0000/view-3.png and its composites), written under frame-0000.part and renamed when
// complete, optionally a video file of one composite (or one stream per view).
#include "sequence.h"
#include "stereo_options.h"
#include "validators.h"

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

#include "distribute.h"
#include "video.h"

#include "mvr/backends.h"
#include "mvr/core/animation.h"
#include "mvr/session/sequence.h"

namespace mvr::cli {

void addSequenceOptions(CLI::App* app, SequenceOptions& o) {
    app->add_option("--frames", o.frames,
                    "Render a sequence of F frames into DIR/frame-0000/ ... (views and composites "
                    "per frame)")
        ->check(wholeIn(1, 1000000));
    app->add_option("--orbit", o.orbit,
                    "Turntable: turn the camera (and the rig with it) DEG degrees about the "
                    "scene centre over the frames (frame f at DEG·f/F); without --frames, a "
                    "frame every 5 degrees");
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
        ->check(wholeIn(0, 1024))
        ->default_val(o.threads);
    app->add_flag("--gather-stats", o.gatherStats,
                  "Under mpirun: rank 0 prints the time it spent receiving the views (the "
                  "gather) per frame");
    app->add_option("--video", o.video,
                    "Also write a video (.mkv or .mp4) of the first --format that is one image "
                    "per frame, or of every view (one stream each) without one");
    app->add_option("--codec", o.codec,
                    "The video's codec: h264 (libx264), h265 (libx265), av1 (SVT-AV1, frames of "
                    "64x64 or more) or ffv1 (lossless RGBA, .mkv)")
        ->default_val(o.codec);
    app->add_option("--crf", o.crf,
                    "The video's constant rate factor, lower is better (h264/h265 0..51, default "
                    "18/20; av1 0..63, default 30)");
    app->add_option("--encoder-preset", o.encoderPreset,
                    "The encoder's speed preset (x264/x265: ultrafast ... veryslow, default "
                    "fast; SVT-AV1: 0..13, default 10)");
}

namespace {

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

/// What a sequence stopped after `done` of its frames leaves, and how to render the rest:
/// frames are written in order, each folder whole (writeFrameFolder()).
std::string sequenceRemains(const std::string& dir, const SequenceOptions& o,
                            const std::vector<int>& todo, std::size_t done, bool video) {
    const std::string lost = video ? "; the unfinished video was removed" : "";
    if (done == 0) return fmt::format("no frame was complete: {}/ is as it was{}", dir, lost);
    if (done >= todo.size()) return fmt::format("every frame is complete in {}/{}", dir, lost);
    const std::string range = o.frameRange.empty() ? std::string()
                                                   : o.frameRange.substr(o.frameRange.find(':'));
    return fmt::format("{} of {} frames are complete in {}/ (`--frame-range {}{}` renders the "
                       "rest){}",
                       done, todo.size(), dir, todo[done], range.empty() ? ":" : range, lost);
}

}  // namespace

Status checkSequenceOptions(const SequenceOptions& o) { return session::checkSequence(o); }

int runSequence(const SequenceOptions& o, const SequenceJob& job) {
    const Prepared& p = *job.prepared;
    auto plan = session::planSequence(o);
    if (!plan) return fail(plan.status());
    if (!o.video.empty() && plan->shards > 1) {
        return fail(usageError("--video needs every frame in one process (not with --shard)"));
    }
    const int frames = plan->frames;
    const std::vector<int>& todo = plan->todo;

    // The video's composite: the first one-image format, else every view as a stream.
    std::string videoFormat;
    int videoImages = p.rig.viewCount();  // rgbd: the centre view's colour and depth
    for (const std::string& format : job.outputs.formats) {
        auto info = composite::findFormat(format);
        if (!info) return fail(info.status());
        if (videoFormat.empty() && info->extension == ".png") {
            videoFormat = format;
            if (info->colourAndDepth) videoImages = 2;
        }
    }
    composite::ComposeOptions compose = job.outputs.compose;
    compose.baseline = p.rig.interaxial;
    compose.convergence = p.rig.convergence;

    const VideoCodec codec{o.codec, o.crf, o.encoderPreset};
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
            auto s = composite::outputSize(videoFormat, videoImages, size.width, size.height,
                                           compose);
            if (!s) return fail(s.status());
            size = *s;
        }
        if (Status s = checkVideo(o.video, codec, size.width, size.height); !s) return fail(s);
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
    if (job.accepted) job.accepted();

    std::unique_ptr<VideoWriter> video;
    std::size_t complete = 0;  // frames whose folder is in place
    const std::filesystem::path dir(job.outDir);
    FrameProgress progress(int(todo.size()), job.quiet);
    // Per frame: the scene the file's animation moves, the camera and the rig around it.
    session::FrameStepper stepper(p, *plan);
    // Renders views [v0, v1) of frame f (the rig moving with the camera).
    auto renderViews = [&](int f, int v0, int v1) -> Result<RenderOutput> {
        auto rig = stepper.advance(f);
        if (!rig) return rig.status();
        if (v0 > 0 || v1 < rig->viewCount()) {
            // A share of the views: the culling frustum still encloses all of them.
            rig->views = std::vector<View>(rig->views.begin() + v0, rig->views.begin() + v1);
        }
        auto rendered = backend.render(stepper.scene(), *rig, p.settings, job.method);
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
        if (!job.outputs.readsDepth()) rendered->depth.clear();  // not read, not sent between ranks
        return rendered;
    };
    // --write-cameras: each frame's own rig (the camera moves), wherever the frame was rendered.
    std::optional<session::FrameStepper> cameraStepper;
    if (job.outputs.cameras) cameraStepper.emplace(p, *plan);
    auto emitFrame = [&](int f, const RenderOutput& out) -> Status {
        Rig frameRig = p.rig;
        if (cameraStepper) {
            auto r = cameraStepper->advance(f);
            if (!r) return r.status();
            frameRig = std::move(*r);
        }
        // The frame's folder, as a still's files (anaglyph.png for a pair included).
        auto files = session::writeFrameFolder(dir, *plan, f, out, frameRig, job.outputs, &backend,
                                               o.video.empty() ? std::string() : videoFormat);
        if (!files) return files.status();
        ++complete;
        if (job.made) job.made->keep();
        session::setOutputProgress(
            sequenceRemains(job.outDir, o, todo, complete, !o.video.empty()));
        std::optional<Image> videoImage = std::move(files->kept);
        if (!o.video.empty()) {
            const Image& first = videoImage ? *videoImage : out.color[0];
            if (!video) {
                const int streams = videoImage ? 1 : int(out.color.size());
                auto opened = VideoWriter::open(
                    o.video, streams, first.width, first.height, o.fps,
                    videoImage ? matroskaStereoMode(videoFormat, compose.swapEyes) : std::string(),
                    codec);
                if (!opened) return (opened.status());
                video = std::move(opened).value();
                // Looking Glass players read a quilt's layout from the file name.
                const std::filesystem::path file(o.video);
                if (videoFormat == "quilt" &&
                    file.stem().string().find("_qs") == std::string::npos) {
                    auto name = composite::compositeFileName(videoFormat, out.color, compose);
                    const std::string qs =
                        name ? std::filesystem::path(*name).stem().string() : std::string();
                    if (qs.find("_qs") != std::string::npos) {
                        fmt::print(stderr,
                                   "warning: --video {}: Looking Glass players read a quilt's "
                                   "layout from its name: call it {}{}{}\n",
                                   o.video, file.stem().string(), qs.substr(qs.find("_qs")),
                                   file.extension().string());
                    }
                }
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
    session::setOutputProgress(sequenceRemains(job.outDir, o, todo, 0, !o.video.empty()));
    if (Status s = distributeFrames(todo, p.rig.viewCount(), renderViews, emitFrame,
                                    o.gatherStats);
        !s) {
        video.reset();  // its temporary file is removed
        return fail(Status(s.code(), fmt::format("{}; {}", s.message(),
                                                 sequenceRemains(job.outDir, o, todo, complete,
                                                                 !o.video.empty()))));
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
