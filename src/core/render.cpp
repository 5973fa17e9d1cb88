#include "mvr/core/render.h"

#include <cmath>

#include <fmt/core.h>

namespace mvr {

Status validateSettings(const RenderSettings& s) {
    constexpr int kMaxSize = 16384;
    if (s.width < 1 || s.height < 1 || s.width > kMaxSize || s.height > kMaxSize) {
        return usageError(fmt::format("image size {}x{} is out of range (expected 1..{} each)",
                                      s.width, s.height, kMaxSize));
    }
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(s.clearColor[i])) return usageError("clear color is not finite");
    }
    return {};
}

Result<Shading> parseShading(const std::string& name) {
    if (name == "flat") return Shading::Flat;
    if (name == "vertex") return Shading::Vertex;
    if (name == "pixel") return Shading::Pixel;
    return usageError(fmt::format("unknown shading '{}' (expected flat, vertex or pixel)", name));
}

const char* shadingName(Shading shading) {
    switch (shading) {
        case Shading::Flat: return "flat";
        case Shading::Vertex: return "vertex";
        case Shading::Pixel: return "pixel";
    }
    return "?";
}

}  // namespace mvr
