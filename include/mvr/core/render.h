// mvr/core/render.h — the interface every rendering backend implements.
//
// A backend renders one scene from every view of a rig into per-view color and depth images
// (see image.h: row 0 at the top, window depth in [0, 1], 1 where nothing was drawn).
// Method names are strings ("multipass", "unified", "gs-mrt", …) so that the CLI and bench can
// pass them through; `supports()` says why a method cannot run here.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/image.h"
#include "mvr/core/lighting.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"

namespace mvr {

struct RenderSettings {
    int width = 1024;   ///< pixels per view
    int height = 768;
    Shading shading = Shading::Vertex;
    bool cullBackFaces = false;           ///< cull clockwise (back) faces
    bool wireframe = false;               ///< draw triangle edges instead of filled triangles
    glm::vec3 clearColor{0.0f, 0.0f, 0.0f};  ///< background, linear [0,1]; alpha is 1
};

/// Wall-clock time per pipeline stage of one render, where a backend measures it (soft does:
/// vertex = vertex stage, setup = primitive stage (cull, clip tests, binning), raster = triangle
/// setup + coverage + depth + shading, fill = clearing and handing out the images).
struct StageTimes {
    double vertexMs = 0, setupMs = 0, rasterMs = 0, fillMs = 0;
};

/// What one render produces: a color and a depth image per view, in rig view order.
struct RenderOutput {
    std::vector<Image> color;
    std::vector<DepthImage> depth;   ///< empty for methods without a per-view depth buffer
    std::string method;              ///< the method that actually ran (differs for "auto")
    std::string note;                ///< e.g. why "auto" picked that method
    StageTimes stages;               ///< per-stage times (zero where not measured)
};

class Backend {
public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    /// Every method this backend knows, supported here or not.
    virtual std::vector<std::string> methods() const = 0;
    /// ok, or why `method` cannot run (unknown: Usage; not on this driver/build: Unsupported).
    virtual Status supports(const std::string& method) const = 0;
    /// Renders the scene from every view of the rig.
    virtual Result<RenderOutput> render(const Scene& scene, const Rig& rig,
                                        const RenderSettings& settings,
                                        const std::string& method) = 0;
    /// Lines for `mvr info` (limits, driver strings).
    virtual std::vector<std::string> info() const { return {}; }
};

/// Validates settings (size within 1..16384, finite clear color). Errors: ErrorCode::Usage.
Status validateSettings(const RenderSettings& settings);

/// Parses "flat" | "vertex" | "pixel". Errors: ErrorCode::Usage listing the choices.
Result<Shading> parseShading(const std::string& name);
const char* shadingName(Shading shading);

}  // namespace mvr
