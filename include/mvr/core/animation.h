// mvr/core/animation.h — what changes from frame to frame of a sequence: the turntable orbit,
// keyframed camera paths and the samplers of glTF animations (LINEAR, STEP, slerp for
// rotations), all pure functions of the frame's time.
//
// Conventions:
//  - A sequence of F frames at `fps` frames per second: frame f is at time f / fps seconds.
//  - The orbit (turntable): frame f of F turns the camera by degrees · f / F about the vertical
//    axis (the camera's up vector) through the centre (the framed camera's target, i.e. the
//    scene's bounds centre), so a 360° orbit of F frames loops without repeating a frame. The
//    rig moves with the camera: every view is rebuilt from the turned camera with the same
//    spacing and convergence (rigAt()).
//  - A camera path (docs/animation.md): keys of time, position, target and optionally the
//    vertical field of view; between two keys everything is interpolated linearly; before the
//    first key the first one holds, after the last the last one. Near and far stay those of the
//    framed camera.
//  - Samplers (glTF 2.0 §3.11): `input` key times in seconds, strictly increasing; `output`
//    `components` values per key; LINEAR interpolates (rotations, 4 components x y z w: slerp
//    along the shorter arc), STEP holds the previous key; times outside the keys clamp.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

/// The camera turned by `degrees` about `centre`, around the camera's up axis (right-handed:
/// positive degrees turn counter-clockwise seen from above).
Camera orbitCamera(const Camera& camera, const glm::vec3& centre, double degrees);

/// The orbit angle of frame `frame` of `frames`: degrees · frame / frames.
double orbitDegrees(double degrees, int frame, int frames);

/// One key of a camera path.
struct CameraKey {
    double time = 0.0;  ///< seconds
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    std::optional<float> fovYDegrees;  ///< absent: the framed camera's
};

/// Keys in increasing time.
struct CameraPath {
    std::vector<CameraKey> keys;
    double duration() const { return keys.empty() ? 0.0 : keys.back().time; }
};

/// Checks a path: at least one key, finite values, strictly increasing times, position !=
/// target, fov in (0, 180). Errors: ErrorCode::Usage naming the key ("key 2: ...").
Status validateCameraPath(const CameraPath& path);

/// `base` (its up, aspect, near, far; its fov where a key has none) at `time` on `path`.
/// Precondition: validateCameraPath() passed.
Camera cameraAt(const CameraPath& path, double time, const Camera& base);

/// The rig of `rig`'s kind, views, spacing and convergence around `camera` (the rig moving
/// with the camera). Errors: those of makeRig().
Result<Rig> rigAt(const Rig& rig, const Camera& camera);

/// A glTF-style animation sampler.
enum class Interpolation { Linear, Step };
struct Sampler {
    std::vector<float> input;   ///< key times, seconds, strictly increasing
    std::vector<float> output;  ///< components values per key
    int components = 3;         ///< 3: translation / scale, 4: rotation quaternion (x y z w)
    Interpolation interpolation = Interpolation::Linear;
    bool rotation = false;  ///< LINEAR means slerp (components must be 4)
};

/// Checks a sampler (keys, sizes, finite, increasing). Errors: ErrorCode::Usage.
Status validateSampler(const Sampler& sampler);

/// The sampler's value at `time` (components values). Precondition: validateSampler() passed.
std::vector<float> sample(const Sampler& sampler, double time);
/// The vec3 of a translation or scale sampler at `time`.
glm::vec3 sampleVec3(const Sampler& sampler, double time);
/// The unit quaternion of a rotation sampler at `time`.
glm::quat sampleRotation(const Sampler& sampler, double time);

/// One node's animated transform: translation · rotation · scale, each sampler optional (a
/// missing one keeps the node's rest value).
struct NodeAnimation {
    std::optional<Sampler> translation, rotation, scale;
    glm::vec3 restTranslation{0.0f};
    glm::quat restRotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 restScale{1.0f};
};
/// The node's local matrix at `time` (T · R · S, glTF's order).
glm::mat4 nodeMatrixAt(const NodeAnimation& node, double time);

}  // namespace mvr
