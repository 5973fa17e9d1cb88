// src/session/rgbd_output.cpp — the two images of a colour-and-depth format (rgbd) from a
// rendered frame (mvr/session/outputs.h, mvr/composite/rgbd.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>

#include "mvr/session/cameras.h"
#include "mvr/session/outputs.h"

namespace mvr::session {

int centreView(const Rig& rig) {
    if (rig.columns < 1 || rig.rows < 1 || rig.columns % 2 == 0 || rig.rows % 2 == 0) return -1;
    const int v = (rig.rows / 2) * rig.columns + rig.columns / 2;
    return v < rig.viewCount() ? v : -1;
}

Status checkCentreView(const Rig& rig, const std::string& who) {
    if (centreView(rig) >= 0) return {};
    return usageError(fmt::format(
        "{}: the RGB-D image is the rig's centre view, and {} has none (give an odd "
        "number of views, e.g. --views 1)",
        who,
        rig.rows > 1 ? fmt::format("a {}x{} grid", rig.columns, rig.rows)
                     : fmt::format("a row of {} views", rig.columns)));
}

Result<ColourAndDepth> colourAndDepthOf(const RenderOutput& out, const Rig& rig,
                                        const std::string& who) {
    if (Status s = checkCentreView(rig, who); !s) return s;
    const int v = centreView(rig);
    if (std::size_t(v) >= out.color.size()) {
        return internalError(fmt::format("{}: no image of view {}", who, v));
    }
    if (std::size_t(v) >= out.depth.size() || out.depth[std::size_t(v)].depth.empty()) {
        return unsupportedError(fmt::format(
            "{}: the method {} gives no depth images (choose another --method)", who, out.method));
    }
    const DepthImage& d = out.depth[std::size_t(v)];
    // The view's distances, normalised between the nearest and farthest drawn (the scene's
    // near and far as the view sees it: all 8 bits for the scene); nothing drawn: the planes.
    const glm::mat4& p = rig.views[std::size_t(v)].clipFromView;
    const float p22 = p[2][2], p32 = p[3][2];
    std::vector<float> distance(d.depth.size());
    double near = std::numeric_limits<double>::infinity(), far = 0.0;
    for (std::size_t i = 0; i < distance.size(); ++i) {
        distance[i] = distanceOfDepth(p22, p32, d.depth[i]);
        if (std::isfinite(distance[i])) {
            near = std::min(near, double(distance[i]));
            far = std::max(far, double(distance[i]));
        }
    }
    if (!(near <= far)) near = p32 / (p22 - 1.0f), far = p32 / (p22 + 1.0f);
    // One distance only (a plane facing the view): a range of 1e-6 of it, all drawn white.
    if (!(far - near > 1e-6 * std::max(1.0, near))) far = near + 1e-6 * std::max(1.0, near);
    ColourAndDepth cd;
    cd.images.push_back(out.color[std::size_t(v)]);
    cd.images.push_back(composite::rgbdDepthImage(distance, d.width, d.height, near, far));
    cd.sidecar.width = out.color[std::size_t(v)].width;
    cd.sidecar.height = out.color[std::size_t(v)].height;
    cd.sidecar.near = near;
    cd.sidecar.far = far;
    cd.sidecar.view = v;
    cd.sidecar.convergence = rig.convergence;
    cd.sidecar.fovYDegrees = rig.camera.fovYDegrees;
    return cd;
}

}  // namespace mvr::session
