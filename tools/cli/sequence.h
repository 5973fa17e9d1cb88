// tools/cli/sequence.h — `mvr render` over many frames: --orbit, --camera-path, --frames,
// --frame-range, --shard, --fps and --video. sequence.cpp owns the frame loop; render_cmd.cpp
// hands over to it when a sequence option is given.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "options.h"

#include "mvr/core/stereo_surfaces.h"

#include "mvr/composite/compose.h"

namespace mvr::cli {

struct SequenceOptions {
    double orbit = 0.0;      ///< --orbit DEG: turntable over the frames
    int frames = 0;          ///< --frames F (0: no sequence)
    std::string cameraPath;  ///< --camera-path FILE.json (docs/animation.md)
    std::string frameRange;  ///< --frame-range A:B (inclusive A, exclusive B)
    std::string shard;       ///< --shard I/N: frames f with f mod N == I
    double fps = 24.0;       ///< --fps: times of the camera path, and the video's rate
    std::string video;       ///< --video FILE.mkv|.mp4
    bool gatherStats = false;  ///< --gather-stats: rank 0's gather time (MPI)
    int threads = 0;         ///< --threads: CPU threads per process; 0 = cores / ranks on this node
    bool active() const { return frames > 0 || orbit != 0.0 || !cameraPath.empty(); }
};

void addSequenceOptions(CLI::App* app, SequenceOptions& o);

/// What the sequence renders with (render_cmd.cpp's options, resolved).
struct SequenceJob {
    const Prepared* prepared = nullptr;
    Backend* backend = nullptr;
    std::string backendName, method;
    std::string outDir;
    std::vector<std::string> formats;
    composite::ComposeOptions compose;
    bool depth = false;
    bool quiet = false;
    const StereoSurfaces* surfaces = nullptr;  ///< --sky, --label…: drawn into every frame
};

/// The sequence options' own checks, before anything is rendered or written: --frames >= 0,
/// --fps in (0, 1000], and --video / --frame-range / --shard only with a sequence.
Status checkSequenceOptions(const SequenceOptions& o);

int runSequence(const SequenceOptions& o, const SequenceJob& job);

}  // namespace mvr::cli
