// mvr/session/sequence.h — a recipe's sequence (library mvr::session): its frames checked and
// listed as `mvr render --frames / --orbit / --camera-path` lists them, the scene and rig of
// each frame (the orbit, the camera path, the model file's animation), and the frame folders
// (frame-NNNN/, written under frame-NNNN.part and renamed when complete) that `mvr render`, its
// MPI rank 0 and Python's mvr.render_sequence() write through writeOutputs().
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mvr/core/animation.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"
#include "mvr/session/camera_path.h"
#include "mvr/session/outputs.h"
#include "mvr/session/prepare.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

/// --orbit without --frames: one frame every this many degrees (at least 2 frames).
inline constexpr double kOrbitDegreesPerFrame = 5.0;

/// The checks of the sequence fields before anything is rendered or written: frames >= 0, fps in
/// (0, 1000], and video / frameRange / shard only with a sequence.
Status checkSequence(const SequenceRecipe& s);

/// The frames of an active sequence.
struct SequencePlan {
    int frames = 0;         ///< of the whole sequence
    std::vector<int> todo;  ///< the frames to render here (frameRange, shard), ascending
    double fps = 24.0;
    double orbit = 0.0;
    std::optional<CameraPath> path;
    int shards = 1;  ///< N of shard I/N
    /// The folder of frame f: "frame-0003" (at least 4 digits, as many as the last frame's).
    std::string folder(int f) const;
};
/// Checks and lists the frames (reads the camera path). Errors: ErrorCode::Usage naming the
/// option ("--frame-range '5:2' is out of range ..."), the camera path's errors.
Result<SequencePlan> planSequence(const SequenceRecipe& s);

/// The scene and rig of each frame of a prepared recipe: a copy of the scene that the model
/// file's animation moves (made once), the camera of the orbit, the camera path or the file's
/// animated camera, and the rig rebuilt around it (rigAt()).
class FrameStepper {
public:
    FrameStepper(const Prepared& prepared, const SequencePlan& plan);
    /// Moves the scene to frame f and returns that frame's rig. Errors: "frame F: ...".
    Result<Rig> advance(int f);
    /// The scene of the last advance() (the prepared scene when nothing is animated).
    const Scene& scene() const { return mAnimated ? *mAnimated : mPrepared.scene; }

private:
    const Prepared& mPrepared;
    const SequencePlan& mPlan;
    std::optional<Scene> mAnimated;
};

/// Writes frame f's files (writeOutputs()) into DIR/frame-NNNN.part, then renames it to
/// DIR/frame-NNNN (replacing an older one). `keepFormat`: as writeOutputs(); `precomposed`:
/// as writeFrameFiles().
Result<WrittenFrame> writeFrameFolder(const std::filesystem::path& dir, const SequencePlan& plan,
                                      int f, const RenderOutput& out, const Rig& rig,
                                      const FrameOutputs& outputs, const Backend* backend,
                                      const std::string& keepFormat = {},
                                      ComposedImages* precomposed = nullptr);

}  // namespace mvr::session
