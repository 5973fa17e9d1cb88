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
//    along the shorter arc), STEP holds the previous key, CUBICSPLINE is glTF's Hermite spline
//    (3 × components values per key: in-tangent, value, out-tangent; rotations normalised);
//    times outside the keys clamp (before the first key the first value, after the last key the
//    last value holds).
//  - Scene animations (a glTF file's first animation, SceneAnimation): the file's node
//    hierarchy with each node's rest transform and its channels; at time t every node's world
//    matrix is its parent's world × its local T·R·S at t, and animateScene() moves the
//    instances and the file camera of a loaded scene to time t.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
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
/// with the camera). A screen rig (Rig::screen) is placed around `eyes` when given (a tracked
/// or moved head's, on the same screen), else around its own. Errors: those of makeRig() /
/// makeScreenRig().
Result<Rig> rigAt(const Rig& rig, const Camera& camera, const ScreenEyes* eyes = nullptr);

/// A glTF-style animation sampler.
enum class Interpolation { Linear, Step, CubicSpline };
struct Sampler {
    std::vector<float> input;   ///< key times, seconds, strictly increasing
    std::vector<float> output;  ///< components values per key (CUBICSPLINE: 3 × components)
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
    /// The morph target weights of the node's mesh (glTF path "weights": one component per
    /// target); animateScene() morphs the meshes of the node's instances.
    std::optional<Sampler> weights;
    glm::vec3 restTranslation{0.0f};
    glm::quat restRotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 restScale{1.0f};
};
/// The node's local matrix at `time` (T · R · S, glTF's order).
glm::mat4 nodeMatrixAt(const NodeAnimation& node, double time);

/// One node of a file's hierarchy, for re-evaluating world transforms over time.
struct AnimatedNode {
    std::string name;
    int parent = -1;                        ///< index into SceneAnimation::nodes (before it), -1: root
    glm::mat4 rest{1.0f};                   ///< the local matrix when not animated
    std::optional<NodeAnimation> animation;  ///< the channels that target the node
};

/// A file's animation (glTF: its first), bound to the instances and the camera of its scene.
struct SceneAnimation {
    std::string name;
    double duration = 0.0;  ///< the last key time of all its samplers, seconds
    std::vector<AnimatedNode> nodes;  ///< parents before their children
    /// An instance moved by a node: worldFromModel = worldFromRoot × world(node).
    struct Target {
        int instance = 0;  ///< index into Scene::instances
        int node = 0;
        glm::mat4 worldFromRoot{1.0f};
    };
    std::vector<Target> instances;
    /// A skinned instance (glTF skins): its mesh (Mesh::joints) posed by its joints' nodes:
    /// joint j's matrix is world(meshNode)⁻¹ · world(joints[j]) · inverseBind[j], or without a
    /// mesh node (-1: the loader's, whose skinned instances stand at the root, as glTF ignores
    /// the node's own transform) world(joints[j]) · inverseBind[j].
    struct Skin {
        int instance = 0;
        int meshNode = -1;
        std::vector<int> joints;  ///< nodes, in the order of Mesh::joints' indices
        std::vector<glm::mat4> inverseBind;
    };
    std::vector<Skin> skins;
    int cameraNode = -1;  ///< the node of Scene::camera, -1: the camera is not animated
    glm::mat4 cameraWorldFromRoot{1.0f};
};

/// Checks node order, parents, instance and camera indices and every sampler.
/// Errors: ErrorCode::Input naming the node.
Status validateSceneAnimation(const SceneAnimation& animation);

/// Every node's world matrix (relative to the file's root) at `time`.
std::vector<glm::mat4> nodeWorldsAt(const SceneAnimation& animation, double time);

/// A skin's joint matrices (SceneAnimation::Skin) from the nodes' world matrices `world`.
std::vector<glm::mat4> skinMatrices(const SceneAnimation::Skin& skin,
                                    const std::vector<glm::mat4>& world);

/// Moves `scene`'s animated instances and (cameraNode >= 0) its camera to `time`, morphs
/// the meshes of instances whose node animates its weights (applyMorphWeights(); a mesh two
/// such nodes share takes the later node's) and poses the skinned ones (poseSkin(), with
/// skinMatrices()).
/// Precondition: validateSceneAnimation() passed and the indices fit `scene`.
void animateScene(Scene& scene, const SceneAnimation& animation, double time);

/// The camera at an animated camera node: `worldFromCamera`'s origin, looking down its −Z with
/// its +Y up (glTF), the target at `base`'s distance ahead; fov, aspect, near and far are
/// `base`'s (the framed camera's).
Camera cameraFromNode(const glm::mat4& worldFromCamera, const Camera& base);

/// Applies a placement (scene_io.h's transformScene) to the animation's targets.
void transformAnimation(SceneAnimation& animation, const glm::mat4& worldFromScene);

}  // namespace mvr
