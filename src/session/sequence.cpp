// src/session/sequence.cpp — a recipe's sequence: its frames, each frame's scene and rig, and
// the frame folders (mvr/session/sequence.h).
#include "mvr/session/sequence.h"
#include "mvr/session/pending.h"
#include "mvr/session/screen.h"

#include <algorithm>
#include <cmath>
#include <regex>

#include <fmt/core.h>

namespace mvr::session {

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

}  // namespace

Status checkSequence(const SequenceRecipe& o) {
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

Result<SequencePlan> planSequence(const SequenceRecipe& o) {
    if (!std::isfinite(o.orbit)) {
        return usageError(fmt::format("--orbit {} is not a finite angle (degrees)", o.orbit));
    }
    // A thousand turns at most: without --frames, a frame every 5 degrees (72 000 frames).
    if (std::abs(o.orbit) > 360.0 * 1000.0) {
        return usageError(fmt::format("--orbit {:g}: at most 360000 degrees (1000 turns)", o.orbit));
    }
    if (!(o.fps > 0.0 && o.fps <= 1000.0)) {
        return usageError(fmt::format("--fps {} is out of range (expected 0 < fps <= 1000)", o.fps));
    }
    if (o.orbit != 0.0 && !o.cameraPath.empty()) {
        return usageError("--orbit and --camera-path exclude each other");
    }
    SequencePlan plan;
    plan.fps = o.fps;
    plan.orbit = o.orbit;
    if (!o.cameraPath.empty()) {
        auto read = readCameraPath(o.cameraPath);
        if (!read) return read.status();
        plan.path = std::move(read).value();
    }
    int frames = o.frames;
    if (frames == 0 && plan.path) frames = int(std::floor(plan.path->duration() * o.fps)) + 1;
    // --orbit alone: one frame every kOrbitDegreesPerFrame degrees (360: 72 frames, 3 s at 24
    // frames a second), at least 2.
    if (frames == 0 && o.orbit != 0.0 && std::abs(o.orbit) <= 360.0 * 1000.0)
        frames = std::max(2, int(std::ceil(std::abs(o.orbit) / kOrbitDegreesPerFrame)));
    if (frames < 1 || frames > 1000000) {
        return usageError(
            fmt::format("--frames {} is out of range (expected 1..1000000)", frames));
    }
    plan.frames = frames;
    auto range = parseRange(o.frameRange, frames);
    if (!range) return range.status();
    auto shard = parseShard(o.shard);
    if (!shard) return shard.status();
    plan.shards = shard->second;
    for (int f = range->first; f < range->second; ++f) {
        if (f % shard->second == shard->first) plan.todo.push_back(f);
    }
    return plan;
}

std::string SequencePlan::folder(int f) const {
    const int digits = std::max(4, int(std::to_string(frames - 1).size()));
    return fmt::format("frame-{:0{}}", f, digits);
}

FrameStepper::FrameStepper(const Prepared& prepared, const SequencePlan& plan)
    : mPrepared(prepared), mPlan(plan) {
    if (prepared.animation) mAnimated = prepared.scene;  // its nodes move in a copy, made once
}

Result<Rig> FrameStepper::advance(int f) {
    const Prepared& p = mPrepared;
    const double time = f / mPlan.fps;
    if (mAnimated) animateScene(*mAnimated, *p.animation, time);
    Camera camera = p.rig.camera;
    if (mPlan.orbit != 0.0) {
        camera = orbitCamera(camera, p.rig.camera.target, orbitDegrees(mPlan.orbit, f, mPlan.frames));
    } else if (mPlan.path) {
        camera = cameraAt(*mPlan.path, time, p.rig.camera);
    } else if (mAnimated && p.animation->cameraNode >= 0 && mAnimated->camera) {
        // The file's animated camera (the orbit and the camera path win over it).
        camera = cameraFromNode(mAnimated->camera->worldFromCamera, p.rig.camera);
    }
    std::optional<ScreenEyes> tracked;  // --eye-track: this frame's eyes on the same screen
    if (p.eyeTrack && p.rig.screen) tracked = p.eyeTrack->at(time, p.rig.screen->screen);
    auto rig = rigAt(p.rig, camera, tracked ? &*tracked : nullptr);
    if (!rig) return Status(rig.status().code(), fmt::format("frame {}: {}", f, rig.status().message()));
    return rig;
}

Result<WrittenFrame> writeFrameFolder(const std::filesystem::path& dir, const SequencePlan& plan,
                                      int f, const RenderOutput& out, const Rig& rig,
                                      const FrameOutputs& outputs, const Backend* backend,
                                      const std::string& keepFormat,
                                      ComposedImages* precomposed) {
    if (!outputs.writesFiles(out.color.size(), out.depth.size())) {
        // Nothing for the frame's folder (a video alone): the video's image is still composed.
        return writeFrameFiles(dir / plan.folder(f), out, rig, outputs, backend, keepFormat,
                               precomposed);
    }
    // The frame's files under frame-NNNN.part/, renamed when complete: a frame folder is whole
    // or absent, whatever stops the run (the .part is removed then: mvr/session/pending.h).
    const std::string name = plan.folder(f);
    const std::filesystem::path part = dir / (name + ".part"), final = dir / name;
    std::error_code ec;
    std::filesystem::remove_all(part, ec);  // an earlier run's, killed (SIGKILL) mid-frame
    std::unique_lock made(pendingMutex());  // registered and made at once
    const int ticket = addPending(part);
    std::filesystem::create_directories(part, ec);
    made.unlock();
    if (ec) {
        releasePending(ticket, true);
        return outputError(fmt::format("cannot create '{}': {}", part.string(), ec.message()));
    }
    // The frame's files, as a still's (anaglyph.png for a pair included).
    auto files = writeFrameFiles(part, out, rig, outputs, backend, keepFormat, precomposed);
    if (!files) {
        releasePending(ticket, true);
        return files.status();
    }
    std::lock_guard lock(pendingMutex());  // not stopped between the two steps
    std::filesystem::remove_all(final, ec);
    std::filesystem::rename(part, final, ec);
    releasePending(ticket, bool(ec));
    if (ec) {
        return outputError(fmt::format("cannot rename '{}' to '{}': {}", part.string(),
                                       final.string(), ec.message()));
    }
    for (std::string& path : files->paths)  // where they are now
        path = (final / std::filesystem::path(path).filename()).string();
    return files;
}

}  // namespace mvr::session
