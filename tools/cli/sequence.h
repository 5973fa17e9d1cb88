// tools/cli/sequence.h — `mvr render` over many frames: --orbit, --camera-path, --frames,
// --frame-range, --shard, --fps and --video. sequence.cpp owns the frame loop; render_cmd.cpp
// hands over to it when a sequence option is given.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "options.h"

#include "mvr/core/stereo_surfaces.h"

#include "mvr/composite/compose.h"
#include "mvr/session/outputs.h"
#include "mvr/session/pending.h"
#include "mvr/session/recipe.h"

namespace mvr::cli {

/// --frames, --orbit, --camera-path, ...: the recipe's sequence (mvr/session/recipe.h).
using SequenceOptions = session::SequenceRecipe;

void addSequenceOptions(CLI::App* app, SequenceOptions& o);

/// Where a sequence's time went (`mvr bench outputs`), in seconds summed over its frames; the
/// stages overlap (issue 37), so they add up to more than `wall`.
struct SequenceTimes {
    double render = 0.0;        ///< rendering the frames and their surfaces (this process)
    session::WriteTimes files;  ///< the frame folders: composing, encoding, writing, whole
    double video = 0.0;         ///< encoding (and muxing) the video's frames, its trailer
    double wall = 0.0;          ///< the whole frame loop, the video's trailer included
    int frames = 0;             ///< frames written
};

/// What the sequence renders with (render_cmd.cpp's options, resolved).
struct SequenceJob {
    const Prepared* prepared = nullptr;
    Backend* backend = nullptr;
    std::string backendName, method;
    std::string outDir;
    session::FrameOutputs outputs;  ///< each frame's files (session::writeOutputs())
    bool quiet = false;
    const StereoSurfaces* surfaces = nullptr;  ///< --sky, --label…: drawn into every frame
    /// The folders made for outDir: kept once a frame is complete, else removed when empty.
    session::MadeFolders* made = nullptr;
    /// Called once the sequence's own options are accepted (the prepared notes are printed
    /// then: a refused run prints its error line alone).
    std::function<void()> accepted;
    SequenceTimes* times = nullptr;  ///< filled when given
};

/// The sequence options' own checks, before anything is rendered or written: --frames >= 0,
/// --fps in (0, 1000], and --video / --frame-range / --shard only with a sequence.
Status checkSequenceOptions(const SequenceOptions& o);

int runSequence(const SequenceOptions& o, const SequenceJob& job);

}  // namespace mvr::cli
