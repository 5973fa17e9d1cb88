// mvr/core/rig.h — cameras and multi-view rigs: off-axis stereo, the NVIDIA clip-space form,
// toe-in and parallel rigs, rows and grids of N views, explicit view lists, the culling
// frustum that encloses every view, and parallax.
//
// Conventions (OpenGL): right-handed eye space, the eye looks down −Z, +Y up. Clip space as
// glFrustum makes it: clip.w = −z_eye (distance in front of the eye), NDC = clip.xyz / clip.w,
// x and y in [−1, 1] left→right and bottom→top, z in [−1, 1] near→far. Window depth =
// ndc.z / 2 + 1/2. Distances (interaxial, convergence, near, far) are world units.
//
// Off-axis stereo (sorbier2008 §2, Bourke; nvidia-gtc2010 "Defining stereo projection"): every
// eye is the mono camera translated along its own x axis (and y for grids) by `offset`, looking
// the same way; each eye's frustum is asymmetric so that all frustums meet in the same window
// on the convergence plane. With top = near·tan(fovY/2), the window's half width at the
// convergence plane a = convergence·aspect·tan(fovY/2), an eye at offset o has
//     left  = −(a + o)·near/convergence,  right = (a − o)·near/convergence,
// and its view matrix translates the world by −o. Its clip position differs from the mono
// camera's only in x (and y):
//     clip.x = mono.x + (o / a)·(clip.w − convergence)
// which is the nvidia-gtc2010 form clip.x += eyeSign · separation · (clip.w − convergence) with
// separation = interaxial / screenWidth, screenWidth = 2a (the window width at the
// convergence plane), eyeSign = −1 left, +1 right. View::clipShear holds o / a.
// Parallax of a point, as a fraction of screen width, between a pair of eyes:
//     parallax = separation · (1 − convergence / w)
// zero on the convergence plane, negative in front of it (out of the screen), → separation at
// infinity.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/status.h"

namespace mvr {

inline constexpr int kMaxViews = 128;

/// The mono (center) camera: where the viewer is and what it sees.
struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDegrees = 45.0f;
    float aspect = 4.0f / 3.0f;  ///< width / height of one view
    float near = 0.1f;
    float far = 100.0f;

    glm::mat4 viewFromWorld() const;  ///< lookAt
    glm::mat4 clipFromView() const;   ///< symmetric perspective
};

/// One viewpoint.
struct View {
    glm::mat4 viewFromWorld{1.0f};
    glm::mat4 clipFromView{1.0f};
    glm::vec3 eyeWorld{0.0f};  ///< the eye position in world space
    /// For off-axis rigs: the view's clip position is the rig's center clip position sheared:
    /// clip.x += clipShear.x · (clip.w − convergence), clip.y += clipShear.y · (…). Absent for
    /// rigs whose views differ by more than an offset (toe-in, parallel, explicit lists).
    std::optional<glm::vec2> clipShear;

    glm::mat4 clipFromWorld() const { return clipFromView * viewFromWorld; }
};

/// A plane n·p + d ≥ 0 inside (n unit, world space).
struct Plane {
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    float d = 0.0f;
    float distance(const glm::vec3& p) const { return glm::dot(normal, p) + d; }
};

/// A convex volume bounded by six planes (left, right, bottom, top, near, far).
struct Frustum {
    std::array<Plane, 6> planes;
    bool contains(const glm::vec3& p, float eps = 0.0f) const;
};

enum class RigKind { OffAxis, ToeIn, Parallel, List };

struct ScreenEyes;  // mvr/core/screen_rig.h

/// A multi-view rig: `columns × rows` views numbered left to right, then top to bottom
/// (view 0 is the top-left viewpoint; for a row, view 0 is the leftmost eye).
struct Rig {
    RigKind kind = RigKind::OffAxis;
    Camera camera;  ///< the mono/center camera
    int columns = 1;
    int rows = 1;
    float interaxial = 0.0f;   ///< distance between horizontally adjacent eyes
    float interaxialY = 0.0f;  ///< distance between vertically adjacent eyes (grids)
    float convergence = 5.0f;  ///< distance to the zero-parallax plane (off-axis, toe-in)
    std::vector<View> views;
    Frustum cullingFrustum;  ///< encloses every view's frustum
    /// A screen rig's screen and eyes (makeScreenRig(), screen_rig.h), the framed camera and
    /// convergence it was placed by: rigAt() rebuilds it around a moved camera. Null otherwise.
    std::shared_ptr<const ScreenEyes> screen;
    Camera screenFraming;
    float screenConvergence = 0.0f;
    /// A sub-pixel sample's offset (antialias.h's offsetRig()), NDC per unit w: every view's
    /// clipFromView already holds it; the centre camera's clip transform adds it (the soft
    /// backend's shear form derives the views from it). Zero otherwise.
    glm::vec2 clipJitter{0.0f};

    int viewCount() const { return static_cast<int>(views.size()); }
    glm::vec3 centerEye() const { return camera.position; }
    /// Screen (window) width at the convergence plane: 2 · convergence · aspect · tan(fovY/2).
    float screenWidth() const;
    /// separation = interaxial / screenWidth (nvidia-gtc2010).
    float separation() const;
};

/// Rig parameters as the command line gives them.
struct RigParams {
    RigKind kind = RigKind::OffAxis;
    int columns = 2;            ///< views per row
    int rows = 1;               ///< rows of views
    float interaxial = 0.065f;  ///< eye spacing, world units
    float interaxialY = -1.0f;  ///< vertical spacing for grids; < 0: same as interaxial
    float convergence = 5.0f;   ///< zero-parallax distance, > near
    /// View-cone rig (Looking Glass camera model, issue 13): when > 0 with an off-axis single
    /// row, the N views are spread evenly in angle over this total cone (degrees): view i sits
    /// at angle θ_i = −cone/2 + cone·i/(N−1) as seen from the focal-plane centre, i.e. shifted
    /// sideways by convergence·tan(θ_i); `interaxial` is ignored. 0: uniform interaxial.
    float viewConeDegrees = 0.0f;
    /// View cone only: the views' offsets from the centre scaled (Looking Glass's
    /// "depthiness", `--depthiness`): every parallax scales with it; 0: every view the centre
    /// camera's (identical views), 1: the cone as given. 0 ≤ spread ≤ 2.
    float coneSpread = 1.0f;
};

/// Checks parameters (finite, positive where needed, views within kMaxViews, convergence
/// > near, near < far, fov in (0, 180)). Errors: ErrorCode::Usage naming the value.
Status validateRigParams(const Camera& camera, const RigParams& params);

/// Builds a rig. Precondition: validateRigParams() passed (else returns its error).
///  - OffAxis: parallel eyes, asymmetric frustums meeting on the convergence plane.
///  - ToeIn: eyes translated, each rotated to look at the point on the camera axis at the
///    convergence distance, symmetric frustums (introduces vertical parallax: for comparison).
///  - Parallel: eyes translated, symmetric frustums (no convergence: zero parallax at infinity).
Result<Rig> makeRig(const Camera& camera, const RigParams& params);

/// A rig from an explicit list of views (e.g. the lights of a shadow pass); `camera` supplies
/// the center eye for shading. Errors: empty list or more than kMaxViews.
Result<Rig> makeListRig(const Camera& camera, std::vector<View> views);

/// Separation ↔ interaxial for a camera and convergence distance (nvidia-gtc2010).
float separationFromInteraxial(const Camera& camera, float interaxial, float convergence);
float interaxialFromSeparation(const Camera& camera, float separation, float convergence);

/// The nvidia-gtc2010 clip-space stereo: clip.x += eyeSign · separation · (clip.w − convergence).
glm::vec4 applyClipSpaceStereo(glm::vec4 monoClip, float eyeSign, float separation,
                               float convergence);

/// The horizontal parallax of a world point between views `a` and `b`, as a fraction of the
/// screen width: (ndc_b.x − ndc_a.x) / 2. Positive = behind the screen.
float parallax(const Rig& rig, const glm::vec3& worldPoint, int a, int b);

/// The culling frustum enclosing the frustums of all `views` (their 8 corners each): near and
/// far planes of `camera`'s axis through the nearest and farthest corners, and four side
/// planes, each a supporting plane of all corners, containing the camera's x or y axis.
Frustum enclosingFrustum(const Camera& camera, std::span<const View> views);

/// The 8 world-space corners of a view's frustum (near then far; ndc order (−,−),(+,−),(+,+),(−,+)).
std::array<glm::vec3, 8> frustumCorners(const View& view);

/// Parses "offaxis" | "toein" | "parallel". Errors: ErrorCode::Usage listing the choices.
Result<RigKind> parseRigKind(const std::string& name);
const char* rigKindName(RigKind kind);

/// The parallax range (fraction of screen width, between the outermost views of the row) of
/// the given window depths of view 0's depth image — for the comfort report.
struct ParallaxRange {
    float minParallax = 0.0f;  ///< most negative (nearest, out of the screen)
    float maxParallax = 0.0f;  ///< most positive (farthest, into the screen)
    float nearestDistance = 0.0f, farthestDistance = 0.0f;  ///< eye-space distances seen
    /// Everything within [convergence/2, 100·convergence] and no parallax beyond one screen
    /// width between views two eyes see together (|parallax| > 1: no display can show that;
    /// e.g. --separation 50): a pair's two views; for N > 2 views, adjacent views.
    bool comfortable = true;
    std::string why;  ///< empty when comfortable, else the rule broken, in words
};

/// Comfort report over eye-space distances `w` actually rendered (nvidia-gtc2010 "Parallax
/// budget"), between the outermost eyes (total separation s, half baseline h), each rig its own
/// formula for a point on the axis at w: off-axis s · (1 − convergence / w); parallel
/// −s · convergence / w (zero only at infinity; no [convergence/2, 100 x convergence] rule);
/// toe-in tan(atan(h / convergence) − atan(h / w)) / tan(fovX / 2).
ParallaxRange parallaxRange(const Rig& rig, float nearestW, float farthestW);

}  // namespace mvr
