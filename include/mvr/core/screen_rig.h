// mvr/core/screen_rig.h — a rig from a physical screen and the viewer's tracked eyes, as the
// eye-tracked stereo monitors' runtimes render (Samsung Odyssey 3D, Acer SpatialLabs, Sony's
// Spatial Reality Display, Leia / Dimenco SR panels): each eye sees the scene through the
// screen's rectangle with its own off-axis frustum (Kooima, "Generalized Perspective
// Projection", 2008; nvidia-gtc2010's "the screen is a window"), no toe-in.
//
// Screen space, in millimetres: the units the monitors' SDKs give eye positions in, a room's
// axes (+X right, +Y up, +Z toward the viewer). By default the screen is W × H mm centred on
// the origin, facing +Z; a tilted panel (Sony's at 45°) is given by three corners (lower-left
// pa, lower-right pb, upper-left pc) or by a tilt (screenOfSize()). Eyes are points in the
// same space.
//
// The screen in the scene: centred on the framed centre camera's convergence point (what a
// plain render shows, as nvidia-gtc2010 maps the screen to the convergence plane), scaled
// uniformly so that the screen's width is the window's width there; the room's right / up /
// toward-the-viewer axes are the camera's right / up / backward, so the scene stays upright in
// the room on a tilted panel (an upright screen is exactly the camera's window). Each eye's
// frustum then passes through the four corners of the screen: the corners project to the image
// corners in every eye, a point on the screen has zero parallax, and a point at distance d
// behind it (along the screen's normal) has the parallax
//     p = e · d / (D + d)     (e: the eyes' separation, D: their distance to the screen, mm)
// that similar triangles give.
#pragma once

#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/status.h"

namespace mvr {

/// A physical screen rectangle (mm): lower-left, lower-right and upper-left corners.
struct ScreenCorners {
    glm::vec3 lowerLeft{-300.0f, -170.0f, 0.0f};
    glm::vec3 lowerRight{300.0f, -170.0f, 0.0f};
    glm::vec3 upperLeft{-300.0f, 170.0f, 0.0f};

    float width() const { return glm::length(lowerRight - lowerLeft); }
    float height() const { return glm::length(upperLeft - lowerLeft); }
    glm::vec3 centre() const { return 0.5f * (lowerRight + upperLeft); }
    glm::vec3 right() const { return glm::normalize(lowerRight - lowerLeft); }
    glm::vec3 up() const { return glm::normalize(upperLeft - lowerLeft); }
    glm::vec3 normal() const { return glm::normalize(glm::cross(right(), up())); }
};

/// A screen of width × height mm centred on the origin, facing +Z, or leaning back by
/// `tiltDegrees` about its horizontal centre line (the top away from the viewer, the normal
/// turned up: 45 for Sony's Spatial Reality Displays).
ScreenCorners screenOfSize(float widthMm, float heightMm, float tiltDegrees = 0.0f);

/// The screen and the two eyes (mm, screen space).
struct ScreenEyes {
    ScreenCorners screen;
    glm::vec3 leftEye{-31.5f, 0.0f, 600.0f};
    glm::vec3 rightEye{31.5f, 0.0f, 600.0f};
};

/// Eyes `ipdMm` apart along the screen's right axis, centred on `head` (mm, screen space).
ScreenEyes eyesAtHead(const ScreenCorners& screen, glm::vec3 head, float ipdMm);

/// Checks the screen: finite corners, width and height ≥ 1 mm and ≤ 100 m, a right angle at the
/// lower-left corner within 0.1°. Errors: Usage naming `what` and the problem.
Status validateScreen(const ScreenCorners& screen, const std::string& what);

/// Checks the screen (validateScreen()) and the eyes (finite, in front of the screen by ≥ 1 mm, at
/// most 100 m away, not at the same point). Errors: Usage naming `what` and the problem.
Status validateScreenEyes(const ScreenEyes& s, const std::string& what = "--rig screen");

/// One eye's view through a screen whose corners and eye are in world space (Kooima): the view
/// looks along −normal from `eye`, its frustum's sides pass through the corners.
View kooimaView(const glm::vec3& lowerLeft, const glm::vec3& lowerRight,
                const glm::vec3& upperLeft, const glm::vec3& eye, float near, float far);

/// Where a screen-space point (mm) lies in the world once the screen's centre is `framing`'s
/// (a framed centre camera's) convergence point at distance `convergence` and its width the
/// window's width there, the room's axes the camera's (the header).
glm::vec3 screenToWorld(const Camera& framing, float convergence, const ScreenCorners& screen,
                        const glm::vec3& pointMm);

/// The two-view rig (left, right) of a screen and eyes placed as the header says, around the
/// framed camera `framing` (its window at `convergence`; its near / far planes kept as world
/// planes). Rig::kind is List; Rig::camera is the eyes' midpoint looking at the screen (the
/// shading's centre eye); Rig::convergence its distance to the screen and Rig::interaxial the
/// eyes' distance, both in world units, so parallaxRange() and the comfort report apply.
Result<Rig> makeScreenRig(const Camera& framing, float convergence, const ScreenEyes& eyes);

}  // namespace mvr
