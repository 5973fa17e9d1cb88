// mvr/session/cameras.h — every view's camera as other tools take it (library mvr::session):
// matrices, pinhole intrinsics, and the linear distance behind a window depth. Written as
// DIR/cameras.json by `mvr render --write-cameras` and returned by Python (result.views,
// result.distance).
//
// Conventions. World: right-handed, as the scene. Camera (OpenGL): looking down -Z, +Y up, +X
// right; world_from_camera maps it into the world (its translation is the eye), view_matrix is
// its inverse, projection is the OpenGL clip-from-camera matrix (off-axis views: a sheared
// frustum). All 4x4 matrices are written row-major (m[row][col]). Intrinsics (OpenCV pinhole:
// camera axes x right, y down, z forward, i.e. OpenGL's with y and z negated): a point (X, Y, Z)
// with Z > 0 lands at pixel u = fx X / Z + cx, v = fy Y / Z + cy, where pixel (0, 0)'s centre
// is (0, 0) and v grows downwards (rows top first, as the images); the off-axis shift is in cx
// (and cy for grids). Distance: eye-space distance along the view axis (-Z), world units.
#pragma once

#include <optional>
#include <utility>

#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/rig.h"

namespace mvr::session {

struct ViewCamera {
    glm::mat4 worldFromCamera{1.0f};
    glm::mat4 viewMatrix{1.0f};  ///< camera from world
    glm::mat4 projection{1.0f};  ///< clip from camera (OpenGL)
    double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels (OpenCV)
    float near = 0, far = 0;
};

/// Every view's camera for views of width x height pixels, in rig order.
std::vector<ViewCamera> viewCameras(const Rig& rig, int width, int height);

/// cameras.json: {"convention": ..., "width", "height", "rig": {...}, "views": [{"index",
/// "column", "row", "world_from_camera", "view_matrix", "projection", "intrinsics": {"fx",
/// "fy", "cx", "cy"}, "near", "far"}, ...]}.
/// `viewRange` (--view-range A:B): the rig's views are views A..B of the whole rig: "index" and
/// "column" count from A, and "rig" says "view_range": [A, B].
std::string camerasJson(const Rig& rig, int width, int height,
                        const std::optional<std::pair<int, int>>& viewRange = {});

/// The distance (see the header) of window depth `d` of a perspective projection whose
/// glm (column-major) entries are p22 = P[2][2] and p32 = P[3][2]; +inf for d >= 1 (nothing
/// drawn). z_ndc = (p22 z + p32) / (-z), so -z = p32 / (z_ndc + p22).
inline float distanceOfDepth(float p22, float p32, float d) {
    if (!(d < 1.0f)) return std::numeric_limits<float>::infinity();
    return p32 / ((2.0f * d - 1.0f) + p22);
}

}  // namespace mvr::session
