// src/composite/rgbd.cpp — Looking Glass RGB-D images and their sidecar (mvr/composite/rgbd.h).
#include "mvr/composite/rgbd.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <fmt/core.h>

namespace mvr::composite {

Result<DepthPosition> parseDepthPosition(std::string_view text) {
    for (DepthPosition p :
         {DepthPosition::Right, DepthPosition::Left, DepthPosition::Top, DepthPosition::Bottom}) {
        if (text == depthPositionName(p)) return p;
    }
    return usageError(fmt::format(
        "--rgbd-depth-position '{}': expected right, left, top or bottom", text));
}

std::string_view depthPositionName(DepthPosition position) {
    switch (position) {
        case DepthPosition::Left: return "left";
        case DepthPosition::Top: return "top";
        case DepthPosition::Bottom: return "bottom";
        case DepthPosition::Right: break;
    }
    return "right";
}

int bridgeDepthLoc(DepthPosition position) {
    switch (position) {
        case DepthPosition::Top: return 0;
        case DepthPosition::Bottom: return 1;
        case DepthPosition::Left: return 3;
        case DepthPosition::Right: break;
    }
    return 2;
}

Image rgbdDepthImage(std::span<const float> distances, int width, int height, double near,
                     double far) {
    Image out(width, height);
    const double span = far - near;
    for (std::size_t i = 0; i < distances.size() && i < std::size_t(width) * height; ++i) {
        const double d = distances[i];
        std::uint8_t g = 0;  // nothing drawn (+inf): black, the farthest
        if (std::isfinite(d)) {
            const double v = std::round(255.0 * (far - d) / span);
            g = std::uint8_t(std::clamp(v, 0.0, 255.0));
        }
        std::uint8_t* px = &out.rgba[i * 4];
        px[0] = px[1] = px[2] = g;
        px[3] = 255;
    }
    return out;
}

Result<Image> composeRgbd(std::span<const Image> views, const ComposeOptions& options,
                          const std::string&) {
    // compose() reversed the two for swapEyes: undo it, colour and depth are no pair of eyes.
    const Image& colour = views[options.swapEyes ? 1 : 0];
    const Image& depth = views[options.swapEyes ? 0 : 1];
    const int w = colour.width, h = colour.height;
    const bool across = options.rgbdDepth == DepthPosition::Right ||
                        options.rgbdDepth == DepthPosition::Left;
    Image out(across ? 2 * w : w, across ? h : 2 * h);
    const bool depthFirst = options.rgbdDepth == DepthPosition::Left ||
                            options.rgbdDepth == DepthPosition::Top;
    const Image& first = depthFirst ? depth : colour;
    const Image& second = depthFirst ? colour : depth;
    const std::size_t row = std::size_t(w) * 4;
    const std::size_t outRow = std::size_t(out.width) * 4;
    for (int y = 0; y < h; ++y) {
        const std::uint8_t* a = &first.rgba[std::size_t(y) * row];
        const std::uint8_t* b = &second.rgba[std::size_t(y) * row];
        if (across) {
            std::memcpy(&out.rgba[std::size_t(y) * outRow], a, row);
            std::memcpy(&out.rgba[std::size_t(y) * outRow + row], b, row);
        } else {
            std::memcpy(&out.rgba[std::size_t(y) * outRow], a, row);
            std::memcpy(&out.rgba[std::size_t(y + h) * outRow], b, row);
        }
    }
    return out;
}

std::string rgbdSidecarJson(const ComposeOptions& o, const RgbdSidecar& s) {
    // By hand (the composite module has no JSON library): every value is a number or a
    // file name mvr chose.
    const double aspect = s.height > 0 ? double(s.width) / double(s.height) : 1.0;
    return fmt::format(
        "{{\n"
        "  \"type\": \"rgbd\",\n"
        "  \"uri\": \"{}\",\n"
        "  \"settings\": {{\n"
        "    \"depthiness\": {},\n"
        "    \"focus\": {},\n"
        "    \"depth_loc\": {},\n"
        "    \"depth_inversion\": 0,\n"
        "    \"chroma_depth\": 0,\n"
        "    \"depth_cutoff\": 0,\n"
        "    \"zoom\": 1,\n"
        "    \"aspect\": {}\n"
        "  }},\n"
        "  \"mvr\": {{\n"
        "    \"view\": {},\n"
        "    \"depth_position\": \"{}\",\n"
        "    \"near\": {},\n"
        "    \"far\": {},\n"
        "{}"
        "    \"depth\": \"grey g (0..255, white = near): distance along the view axis = far - g "
        "/ 255 * (far - near); 0 also where nothing was drawn\"\n"
        "  }}\n"
        "}}\n",
        s.image, o.depthiness, o.focus, bridgeDepthLoc(o.rgbdDepth), aspect, s.view,
        depthPositionName(o.rgbdDepth), s.near, s.far,
        s.convergence > 0.0 && s.fovYDegrees > 0.0
            ? fmt::format("    \"convergence\": {},\n    \"fov_y_degrees\": {},\n",
                          s.convergence, s.fovYDegrees)
            : std::string());
}

}  // namespace mvr::composite
