// tools/cli/distribute.h — the frames of a sequence over MPI ranks (Open MPI, when the build
// found it: MVR_WITH_MPI). Run under mpirun with more than one rank, rank 0 hands out work
// items (a frame, or a share of a frame's views when there are fewer frames than workers)
// as workers ask for them, gathers the views and emits the frames in order (it writes every
// file); without mpirun, or with one rank, the frames are rendered here one after the other.
#pragma once

#include <functional>
#include <vector>

#include "mvr/core/render.h"
#include "mvr/core/status.h"

namespace mvr::cli {

using RenderViewsFn = std::function<Result<RenderOutput>(int frame, int v0, int v1)>;
/// Emits a frame on rank 0 (`out` may be moved from: it is not used again).
using EmitFrameFn = std::function<Status(int frame, RenderOutput& out)>;

/// Renders `frames` (each of `views` views) and emits each frame once, in order, on rank 0.
/// A worker's failure stops the run with rank 0 printing "error: rank R: ..." (exit non-zero).
/// Depth images travel with the views when the render returns them. `gatherStats`: rank 0
/// prints one "gather: ..." line on stderr (the time it spent receiving and unpacking views).
/// `settle`: called on rank 0 before a failed distributed run is ended (MPI_Abort), so that
/// the frames' writes still running finish (the output then holds what the message says).
Status distributeFrames(const std::vector<int>& frames, int views, const RenderViewsFn& render,
                        const EmitFrameFn& emit, bool gatherStats = false,
                        const std::function<void()>& settle = {});

/// False on the MPI workers (they write nothing and print nothing).
bool isRankZero();
/// Whether this build distributes frames over MPI ranks (built with Open MPI).
bool mpiAvailable();

}  // namespace mvr::cli
