// tools/viewer/view_state.h — the viewer's camera and stereo state, and the 3D cursor's
// placement: pure functions, no window or GL, so that they are unit tested.
//
// Conventions: those of mvr/core/rig.h (right-handed, eye looks down −Z, +Y up, window depth in
// [0, 1]). View pixels: row 0 at the top, pixel centres at +0.5. Parallax is a fraction of the
// screen width, positive behind the screen (nvidia-gtc2010: separation · (1 − convergence / w)).
#pragma once

#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/rig.h"
#include "mvr/core/screen_rig.h"
#include "mvr/core/status.h"

namespace mvr::viewer {

/// The stereo camera the viewer renders with. It starts as the rig that `mvr render` builds for
/// the same options, unchanged until the user moves it (so frame 0 matches `mvr render`).
///  - Orbit turns the camera around `camera.target` (yaw about world +Y, pitch about the camera's
///    x axis, clamped to ±89° from the horizon); pan moves camera and target along the camera's
///    x and y axes; zoom scales the camera–target distance.
///  - Convergence follows zoom (convergence / distance is kept): the screen plane stays at the
///    same place in the scene, as the scene's depth budget does.
///  - Separation (interaxial / screen width) is what the user sets and sees; it is kept when
///    convergence or the aspect ratio change, by recomputing the interaxial.
struct StereoCamera {
    Camera camera;
    RigKind kind = RigKind::OffAxis;
    float interaxial = 0.065f;
    float convergence = 5.0f;
    float sceneRadius = 1.0f;  ///< bounding radius of the scene, for near/far after zoom
    int columns = 2;           ///< views in the row (2: a stereo pair)
    /// > 0: a view-cone rig (RigParams::viewConeDegrees): the row spread over this many
    /// degrees, interaxial ignored by rig(); 0: views spaced by interaxial.
    float viewConeDegrees = 0.0f;

    /// From a prepared rig (`mvr render`'s, a single row), the scene's bounding radius and the
    /// rig's view cone (Prepared::viewConeDegrees; 0: none).
    static StereoCamera fromRig(const Rig& rig, float sceneRadius, float viewConeDegrees = 0.0f);

    float separation() const;              ///< interaxial / screen width at convergence
    void setSeparation(float separation);  ///< clamped to [0, 0.25]
    void setConvergence(float distance);   ///< clamped to (near·1.01, far]; keeps separation
    void setAspect(float aspect);          ///< no-op when equal; keeps separation
    void orbit(float yawRadians, float pitchRadians);
    void pan(float dxFraction, float dyFraction);  ///< fractions of the view height at target
    void zoom(float factor);  ///< distance ×= factor (> 1 moves away), clamped ≥ radius/100
    float distance() const { return glm::length(camera.position - camera.target); }
    /// Sets the view cone, clamped to [kMinViewCone, kMaxViewCone] degrees (view-cone rigs).
    void setViewCone(float degrees);
    static constexpr float kMinViewCone = 1.0f, kMaxViewCone = 170.0f;

    /// --rig screen (the prepared rig has Rig::screen): that rig, whose screen and framing move
    /// with the camera (rigAt()), its eyes (an eye track's of the frame: setEyes()) moved by
    /// headOffsetMm, the head as the user moved it (mm of screen space).
    std::optional<Rig> screenRig;
    glm::vec3 headOffsetMm{0.0f};
    /// Moves the head by `deltaMm`; false (unmoved) when an eye would leave the space in front
    /// of the screen, or for other rigs.
    bool moveHead(glm::vec3 deltaMm);
    /// The screen's width, mm (--rig screen; else 0).
    float screenWidthMm() const;
    /// The eyes before headOffsetMm (an eye track's of this frame); no-op for other rigs.
    void setEyes(const ScreenEyes& eyes);

    /// The rig of the current state: `columns` views in one row (the view cone's spread when
    /// viewConeDegrees > 0). Errors: makeRig()'s.
    Result<Rig> rig() const;
};

/// Eye-space distance w (clip.w) of window depth `d` in [0, 1) for a perspective near/far.
float distanceFromWindowDepth(float d, float near, float far);

/// The parallax range of a frame from view 0's depth image (pixels with depth < 1), as `mvr
/// render` reports it; nullopt when no pixel was drawn or there is no depth image.
std::optional<ParallaxRange> frameParallaxRange(const Rig& rig, const DepthImage& depth);

/// Where the 3D cursor goes in each eye.
struct CursorPlacement {
    bool onSurface = false;  ///< a surface is under the mouse (else: screen depth)
    float distance = 0.0f;   ///< eye-space w of the cursor's point (convergence if not on surface)
    glm::vec3 world{0.0f};   ///< the cursor's world-space point
    glm::vec2 viewPx[2]{};   ///< its position in view 0 and view 1, pixels (row 0 at top)
    float parallax = 0.0f;   ///< (ndc_1.x − ndc_0.x) / 2: fraction of the screen width
};

/// Places the 3D cursor for the mouse at `screenPx` (pixels of one view, as if seen by the mono
/// centre camera) on the surface under it, read back from `depth0` (view 0's depth image).
/// The centre camera's ray through the mouse is searched for the distance w whose point, seen
/// by view 0, has window depth w: a fixed-point iteration w ← depth0(project₀(ray(w))) from the
/// depth straight under the mouse (exact in a few steps on a smooth surface; on a silhouette
/// it settles on one side). Then the point is projected into each view: off-axis eyes place it
/// with parallax separation · (1 − convergence / w). No surface (background, empty depth, as
/// for gs-mrt) → the point on the convergence plane: zero parallax, like the HUD.
/// Precondition: rig has two views; depth0 is empty or the view size `width`×`height`.
CursorPlacement placeCursor(const Rig& rig, const DepthImage& depth0, glm::vec2 screenPx, int width,
                            int height);

}  // namespace mvr::viewer
