// mvr/core/framing.h — how `mvr render` frames a scene: the centre camera, its near and far
// planes, the convergence and the default spacing of the views. A library user who frames a
// scene here and renders it gets exactly the images the command line writes.
//
// The camera: the scene's own viewpoint (Scene::viewpoint) where it has one; otherwise on the
// +Z side of the bounds' centre, looking at it, at 1.05 × the distance at which the bounding
// sphere fits the narrower of the two fields of view. near = max(d − 2.5 r, 0.02 d), far =
// d + 3 r (d = distance to the target, r = bounding radius). The convergence plane defaults to
// the target's distance; the interaxial to convergence / 30 (or from a separation, nvidia-gtc2010).
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"

namespace mvr {

/// A viewpoint given by the caller (`mvr render --azimuth / --camera-position / --camera-matrix`):
/// the centre camera's eye, the point it looks at and its up direction.
struct Viewpoint {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
};

struct FramingParams {
    RigKind kind = RigKind::OffAxis;
    int columns = 2;                   ///< views per row
    int rows = 1;                      ///< rows of views
    float fovYDegrees = 45.0f;         ///< vertical field of view, (0, 180)
    std::optional<float> interaxial;   ///< world units, >= 0; default convergence / 30
    std::optional<float> separation;   ///< fraction of the screen width; excludes interaxial
    std::optional<float> convergence;  ///< world units, > 0; default: distance to the target
    /// Degrees, [0, 180): an off-axis row spread evenly in angle over this view cone (the
    /// Looking Glass camera, RigParams::viewConeDegrees); 0: interaxial/separation spacing.
    float viewConeDegrees = 0.0f;
    /// View cone only (RigParams::coneSpread): Looking Glass's depthiness, the views' spread.
    float coneSpread = 1.0f;
    /// World units the convergence (focal) plane moves toward the camera from where it would
    /// be (Looking Glass's focus, session/cone_depth.cpp); the result must stay > 0.
    float focusShift = 0.0f;
    std::optional<glm::vec3> clearColor;  ///< default: Scene::background
    /// Width / height of the picture one view shows (the camera's aspect); default: the view's
    /// pixel aspect. A display preset whose panel stretches its quilt tiles sets it (displays.h).
    std::optional<float> aspect;
    // Appended (issue 14): a camera from the file (Scene::camera) is the centre camera: its
    // position and orientation, its yfov unless fovOverridesSceneCamera (then fovYDegrees),
    // its znear / zfar as limits of the depth range, which hugs the scene's bounding sphere
    // (frameCamera()'s margins) when the camera is outside it; the target (and default
    // convergence) is the bounds' centre's depth along its axis. The output's aspect is used,
    // with the field of view fitted so that the file's frame stays whole (fitFileFov()).
    bool useSceneCamera = true;
    bool fovOverridesSceneCamera = false;
    /// The centre camera's viewpoint, over the file's camera and the scene's own viewpoint;
    /// fovYDegrees is its field of view, near / far hug the scene's bounding sphere.
    std::optional<Viewpoint> viewpoint;
};

/// A rig and settings ready for Backend::render().
struct RenderRequest {
    Rig rig;
    RenderSettings settings;
};

/// The centre camera for `scene` seen at `aspect` (width / height of one view).
Camera frameCamera(const Scene& scene, float fovYDegrees, float aspect);

/// The widest vertical field of view fitFileFov() gives (a very narrow output of a wide file
/// camera).
inline constexpr float kMaxFittedFovDegrees = 170.0f;

/// A file camera's vertical field of view (radians) at an output of `aspect` (width / height):
/// the file's whole frame stays in the picture, as a camera's sensor fit does. At least as
/// wide as the file's `fileAspect`: yfov as given (more is seen left and right); narrower:
/// the file's horizontal field of view kept (a Portrait view of a square camera sees its full
/// width, and more above and below). fileAspect 0 (not given): yfov as given.
float fitFileFov(float yfovRadians, float fileAspect, float aspect);

/// The centre camera from a file's camera (see FramingParams::useSceneCamera).
Camera cameraFromScene(const SceneCamera& fileCamera, const Scene& scene,
                       std::optional<float> fovYDegrees, float aspect);

/// The distance at which frameCamera() sees the whole bounding sphere of `scene` at this field
/// of view and aspect (5 % margin): what `--distance auto` means.
float fitDistance(const Scene& scene, float fovYDegrees, float aspect);

/// The centre camera of a viewpoint (FramingParams::viewpoint).
Camera cameraFromViewpoint(const Viewpoint& viewpoint, const Scene& scene, float fovYDegrees,
                           float aspect);

/// The centre camera frameScene() builds its rig around: cameraFromViewpoint() of
/// params.viewpoint when given, else cameraFromScene() of the file's camera when
/// params.useSceneCamera and the scene has one, else frameCamera() of the bounds.
/// `aspect`: width / height of one view. (Also what `--convergence auto`'s depth pre-pass sees.)
Camera centreCamera(const Scene& scene, const FramingParams& params, float aspect);

/// Frames `scene` for views of `settings`' size (its clear colour is replaced by
/// params.clearColor or the scene's background). Errors: Usage naming the parameter (fov,
/// interaxial, separation, convergence, views) and its range; validateRequest()'s errors.
Result<RenderRequest> frameScene(const Scene& scene, const FramingParams& params,
                                 RenderSettings settings = {});

// ---- exposure ----------------------------------------------------------------------------------
// Lights from files are in KHR_lights_punctual's units (lux, candela) with no tone mapping: 1
// lights a surface facing the light at its full colour. Files written in photometric units
// (Blender's exporter: a 1000 W lamp is 54 000 cd) saturate; an exposure scales every light.

/// How brightly the brightest of the scene's lights lights `point`, relative to full colour:
/// the largest over the lights of (largest colour channel × lighting.h's lightAt() attenuation
/// at `point`: 1 for directional lights, the range and cone falloff for point and spot lights).
/// 0 when the scene has no light.
float brightestLightAt(const Scene& scene, glm::vec3 point);

/// Multiplies every light's colour by 2^ev (an exposure of `ev` stops).
void exposeLights(Scene& scene, float ev);

}  // namespace mvr
