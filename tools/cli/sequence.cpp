// The frame loop of `mvr render --frames / --orbit / --camera-path`: one folder per frame
// (frame-0000/view-3.png and its composites), written under frame-0000.part and renamed when
// complete, optionally a video file of one composite (or one stream per view).
#include "sequence.h"
#include "stereo_options.h"
#include "validators.h"

#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>
#include <thread>

#include <fmt/core.h>

#include "distribute.h"
#include "video.h"

#include "mvr/backends.h"
#include "mvr/core/animation.h"
#include "mvr/session/frame_queue.h"
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
    std::size_t complete = 0;  // frames whose folder is in place (the files' thread counts)
    const std::filesystem::path dir(job.outDir);
    FrameProgress progress(int(todo.size()), job.quiet);
    SequenceTimes ownTimes;
    SequenceTimes& times = job.times ? *job.times : ownTimes;
    const auto runStart = std::chrono::steady_clock::now();
    // Per frame: the scene the file's animation moves, the camera and the rig around it.
    session::FrameStepper stepper(p, *plan);
    // Renders views [v0, v1) of frame f (the rig moving with the camera).
    auto renderViews = [&](int f, int v0, int v1) -> Result<RenderOutput> {
        const auto start = std::chrono::steady_clock::now();
        auto rig = stepper.advance(f);
        if (!rig) return rig.status();
        if (v0 > 0 || v1 < rig->viewCount()) {
            // A share of the views: the culling frustum still encloses all of them.
            rig->views = std::vector<View>(rig->views.begin() + v0, rig->views.begin() + v1);
        }
        if (p.synthesize > 1 && (v0 > 0 || v1 < rig->viewCount())) {
            return usageError(fmt::format(
                "--synthesize {}: warps within whole rows of views, not a share of a frame's "
                "views (MPI ranks sharing frames do)",
                p.synthesize));
        }
        auto rendered = session::renderViews(backend, p, stepper.scene(), *rig, p.settings, job.method);
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
        times.render += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return rendered;
    };
    // --write-cameras: each frame's own rig (the camera moves), wherever the frame was rendered.
    std::optional<session::FrameStepper> cameraStepper;
    if (job.outputs.cameras) cameraStepper.emplace(p, *plan);
    const std::string keepFormat = o.video.empty() ? std::string() : videoFormat;
    // The composites are composed on this thread, before the frame leaves it: a GPU backend
    // composes on its context, this thread's; and on the CPU a composite made here comes from
    // the main malloc arena, whose freed blocks are reused (another thread's arena holds at
    // most 64 MiB a heap: a 45 MB quilt took fresh pages every frame there, ~180 ms instead of
    // ~8; bench/README.md).
    const bool composeHere = true;
    std::string videoNameWarning;  // said once the video is opened

    // Writing beside rendering (issue 37): frame f's files are written on the files' thread
    // (each file encoded by a worker) while frame f+1 renders on this one, and its video frame
    // is encoded on the video's thread while frame f+1's files are written; each queue holds
    // at most `depth` frames (MVR_WRITE_QUEUE; 0: all on this thread, one frame at a time).
    // Frames go through both in order. Declared after what the writes use, the video's queue
    // before the files' (whose writes push onto it): they are joined first.
    const int depth = session::writeQueueDepth();
#if defined(__GLIBC__)
    // With frames in flight, two or three composites of tens of MB are alive at once: glibc
    // would serve each from a fresh mmap (over its 32 MiB threshold, main.cpp's
    // retainFreedMemory()) and unmap it when freed, so every frame's quilt faulted in 45 MB of
    // new pages (a Portrait video at 1.96 frames/s against 2.68 one frame at a time; with this,
    // 2.89). Without mmap the freed blocks are reused, as main.cpp intends (trim threshold 1 GiB).
    if (depth > 0) mallopt(M_MMAP_MAX, 0);
#endif
    session::FrameQueue videoQueue(depth);
    session::FrameQueue filesQueue(depth);
    struct Frame {
        int f = 0;
        RenderOutput out;
        Rig rig;
        std::optional<session::ComposedImages> composed;
    };
    // The video's thread: frame f's images (the composite, or every view) into the video.
    auto encodeVideoFrame = [&](int f, const std::vector<Image>& images, bool composite) -> Status {
        const auto start = std::chrono::steady_clock::now();
        if (!video) {
            const Image& first = images.at(0);
            auto opened = VideoWriter::open(
                o.video, int(images.size()), first.width, first.height, o.fps,
                composite ? matroskaStereoMode(videoFormat, compose.swapEyes) : std::string(),
                codec);
            if (!opened) return opened.status();
            video = std::move(opened).value();
            if (!videoNameWarning.empty()) fmt::print(stderr, "{}\n", videoNameWarning);
        }
        for (int v = 0; v < int(images.size()); ++v) {
            if (Status s = video->add(v, images[std::size_t(v)]); !s) return s;
        }
        times.video += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        progress.done(f);
        return {};
    };
    // The files' thread: frame f's folder, then its video frame handed on.
    auto writeFrame = [&](Frame& frame) -> Status {
        auto files = session::writeFrameFolder(dir, *plan, frame.f, frame.out, frame.rig,
                                               job.outputs, nullptr, keepFormat,
                                               frame.composed ? &*frame.composed : nullptr);
        if (!files) return files.status();
        times.files.compose += files->times.compose;
        times.files.encode += files->times.encode;
        times.files.write += files->times.write;
        times.files.wall += files->times.wall;
        ++times.frames;
        ++complete;
        if (job.made) job.made->keep();
        session::setOutputProgress(
            sequenceRemains(job.outDir, o, todo, complete, !o.video.empty()));
        if (o.video.empty()) {
            progress.done(frame.f);
            return {};
        }
        auto images = std::make_shared<std::vector<Image>>();
        const bool composite = files->kept.has_value();
        if (composite) {
            images->push_back(std::move(*files->kept));
        } else {
            *images = std::move(frame.out.color);  // one stream per view
        }
        return videoQueue.push([&encodeVideoFrame, f = frame.f, images, composite] {
            return encodeVideoFrame(f, *images, composite);
        });
    };
    // This thread: frame f rendered (moved from), queued for writing.
    auto emitFrame = [&](int f, RenderOutput& out) -> Status {
        auto frame = std::make_shared<Frame>();
        frame->f = f;
        frame->out = std::move(out);
        frame->rig = p.rig;
        if (cameraStepper) {
            auto r = cameraStepper->advance(f);
            if (!r) return r.status();
            frame->rig = std::move(*r);
        }
        if (composeHere) {
            auto composed =
                session::composeImages(frame->out, frame->rig, job.outputs, &backend, keepFormat);
            if (!composed) return composed.status();
            frame->composed = std::move(composed).value();
        }
        if (videoFormat == "quilt" && !o.video.empty() && f == todo.front()) {
            // Looking Glass players read a quilt's layout from the file name.
            const std::filesystem::path file(o.video);
            if (file.stem().string().find("_qs") == std::string::npos) {
                auto name = composite::compositeFileName(videoFormat, frame->out.color, compose);
                const std::string qs =
                    name ? std::filesystem::path(*name).stem().string() : std::string();
                if (qs.find("_qs") != std::string::npos) {
                    videoNameWarning = fmt::format(
                        "warning: --video {}: Looking Glass players read a quilt's layout from "
                        "its name: call it {}{}{}",
                        o.video, file.stem().string(), qs.substr(qs.find("_qs")),
                        file.extension().string());
                }
            }
        }
        return filesQueue.push([&writeFrame, frame] { return writeFrame(*frame); });
    };
    // Every queued write done (in order), whatever stopped the frames: the first failure of
    // the writes wins (in a run one frame at a time it came first).
    auto settle = [&]() -> Status {
        Status files = filesQueue.finish();
        Status videoFrames = videoQueue.finish();
        return !files ? files : videoFrames;
    };
    session::setOutputProgress(sequenceRemains(job.outDir, o, todo, 0, !o.video.empty()));
    Status s = distributeFrames(todo, p.rig.viewCount(), renderViews, emitFrame, o.gatherStats,
                                [&] { (void)settle(); });
    if (Status written = settle(); !written) s = written;
    if (!s) {
        video.reset();  // its temporary file is removed
        return fail(Status(s.code(), fmt::format("{}; {}", s.message(),
                                                 sequenceRemains(job.outDir, o, todo, complete,
                                                                 !o.video.empty()))));
    }
    if (!isRankZero()) return 0;
    if (video) {
        const auto start = std::chrono::steady_clock::now();
        if (Status finished = video->finish(); !finished) {
            video.reset();  // its temporary file is removed
            return fail(Status(finished.code(),
                               fmt::format("{}; {}", finished.message(),
                                           sequenceRemains(job.outDir, o, todo, complete, true))));
        }
        times.video += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    times.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart).count();
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
