// src/session/cameras.cpp — every view's camera as matrices and pinhole intrinsics
// (mvr/session/cameras.h: the conventions).
#include "mvr/session/cameras.h"

#include <nlohmann/json.hpp>

namespace mvr::session {

std::vector<ViewCamera> viewCameras(const Rig& rig, int width, int height) {
    std::vector<ViewCamera> out;
    for (const View& v : rig.views) {
        ViewCamera c;
        c.viewMatrix = v.viewFromWorld;
        c.worldFromCamera = glm::inverse(v.viewFromWorld);
        c.projection = v.clipFromView;
        const glm::mat4& p = v.clipFromView;  // column-major: p[col][row]
        // x_ndc = P00 X/Z - P02 with OpenCV's X = x, Z = -z (and P02 = p[2][0]); u measured from
        // the left edge is (x_ndc + 1) W / 2; OpenCV puts pixel 0's centre at 0: minus 0.5.
        c.fx = 0.5 * width * p[0][0];
        c.cx = 0.5 * width * (1.0 - p[2][0]) - 0.5;
        // y_ndc = -P11 Y/Z - P12 with Y = -y; v from the top edge is (1 - y_ndc) H / 2.
        c.fy = 0.5 * height * p[1][1];
        c.cy = 0.5 * height * (1.0 + p[2][1]) - 0.5;
        // near / far of a perspective projection: P22 = -(f + n) / (f - n), P32 = -2fn / (f - n).
        const float a = p[2][2], b = p[3][2];
        c.near = b / (a - 1.0f);
        c.far = b / (a + 1.0f);
        out.push_back(c);
    }
    return out;
}

namespace {

nlohmann::ordered_json rowMajor(const glm::mat4& m) {
    nlohmann::ordered_json rows = nlohmann::ordered_json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
    return rows;
}

}  // namespace

std::string camerasJson(const Rig& rig, int width, int height,
                        const std::optional<std::pair<int, int>>& viewRange) {
    using Json = nlohmann::ordered_json;
    Json j;
    j["convention"] =
        "matrices row-major; camera looks down -Z, +Y up (OpenGL); projection is OpenGL's "
        "clip-from-camera; intrinsics are OpenCV's (x right, y down, z forward; pixel (0,0)'s "
        "centre at (0,0)); world units";
    j["width"] = width;
    j["height"] = height;
    j["rig"] = {{"kind", std::string(rigKindName(rig.kind))},
                {"columns", rig.columns},
                {"rows", rig.rows},
                {"interaxial", rig.interaxial},
                {"convergence", rig.convergence},
                {"fov_y_degrees", rig.camera.fovYDegrees},
                {"aspect", rig.camera.aspect}};
    if (viewRange) j["rig"]["view_range"] = {viewRange->first, viewRange->second};
    const int first = viewRange ? viewRange->first : 0;
    Json views = Json::array();
    const std::vector<ViewCamera> cams = viewCameras(rig, width, height);
    for (std::size_t i = 0; i < cams.size(); ++i) {
        const ViewCamera& c = cams[i];
        // A range is a row (view_range.h): its views' column is their number in the rig.
        const int index = first + int(i);
        views.push_back({{"index", index},
                         {"column", viewRange ? index : index % std::max(rig.columns, 1)},
                         {"row", viewRange ? 0 : index / std::max(rig.columns, 1)},
                         {"world_from_camera", rowMajor(c.worldFromCamera)},
                         {"view_matrix", rowMajor(c.viewMatrix)},
                         {"projection", rowMajor(c.projection)},
                         {"intrinsics", {{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}}},
                         {"near", c.near},
                         {"far", c.far}});
    }
    j["views"] = std::move(views);
    return j.dump(2) + "\n";
}

}  // namespace mvr::session
