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

namespace {

bool finiteMatrix(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

Status validateRig(const Rig& rig) {
    if (rig.viewCount() < 1 || rig.viewCount() > kMaxViews) {
        return usageError(
            fmt::format("the rig has {} views (expected 1..{})", rig.viewCount(), kMaxViews));
    }
    if (!std::isfinite(rig.convergence)) return usageError("the rig's convergence is not finite");
    for (int v = 0; v < rig.viewCount(); ++v) {
        const View& view = rig.views[std::size_t(v)];
        if (!finiteMatrix(view.clipFromWorld()) ||
            (view.clipShear &&
             !(std::isfinite(view.clipShear->x) && std::isfinite(view.clipShear->y)))) {
            return usageError(fmt::format("view {} has a non-finite matrix or shear", v));
        }
    }
    if (!finiteMatrix(rig.camera.clipFromView() * rig.camera.viewFromWorld())) {
        return usageError("the rig's center camera has a non-finite matrix");
    }
    return {};
}

}  // namespace

double framebufferBytes(int views, int width, int height) {
    return 8.0 * double(width) * double(height) * double(views);
}

Status validateRequest(const Scene& scene, const Rig& rig, const RenderSettings& settings) {
    if (Status s = validateSettings(settings); !s) return s;
    if (Status s = validateScene(scene); !s) return s;
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
        if (!finiteMatrix(scene.instances[i].worldFromModel)) {
            return usageError(fmt::format("scene instance {} has a non-finite transform", i));
        }
    }
    if (Status s = validateRig(rig); !s) return s;
    const double bytes = framebufferBytes(rig.viewCount(), settings.width, settings.height);
    if (bytes > kMaxFramebufferBytes) {
        return unsupportedError(fmt::format(
            "{} views of {}x{} need {:.1f} GiB of color and depth images (limit {:.0f} GiB)",
            rig.viewCount(), settings.width, settings.height, bytes / 1073741824.0,
            kMaxFramebufferBytes / 1073741824.0));
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
