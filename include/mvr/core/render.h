// mvr/core/render.h — the interface every rendering backend implements.
//
// A backend renders one scene from every view of a rig into per-view color and depth images
// (see image.h: row 0 at the top, window depth in [0, 1], 1 where nothing was drawn).
// Method names are strings ("multipass", "unified", "gs-mrt", …) so that the CLI and bench can
// pass them through; `supports()` says why a method cannot run here.
#pragma once

#include <memory>
#include <optional>
#include <span>
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
    int width = 1024;  ///< pixels per view
    int height = 768;
    Shading shading = Shading::Vertex;
    bool cullBackFaces = false;              ///< cull clockwise (back) faces
    bool wireframe = false;                  ///< draw triangle edges instead of filled triangles
    glm::vec3 clearColor{0.0f, 0.0f, 0.0f};  ///< background, linear [0,1]; alpha is 1
    // Appended (issue 15, shadows.h): the casters' shadow maps, rendered once per frame for all
    // views and sampled by every view.
    bool shadows = false;
    int shadowMapSize = 1024;  ///< texels per side (kDefaultShadowMapSize)
    /// Where the views' pixels go, when the caller owns that memory (zero copy: the Python
    /// module renders into the numpy arrays it returns); nullptr: the images own their memory.
    /// Backends build view v's images with OutputBlock::colorMemory(v) / depthMemory(v); a
    /// backend that does not is still correct (the caller copies what is not in place).
    class OutputBlock* output = nullptr;
    /// Whether the caller wants the views' depth images. false lets a backend skip their
    /// read-back (gl: half the bytes; RenderOutput::depth is then empty); a backend for which
    /// depth costs nothing may still return it.
    bool depth = true;
    /// Samples a pixel (issue 38, `--aa N`: 1, 2, 4, 8; mvr/core/antialias.h): > 1 renders
    /// that many sub-pixel passes and resolves them (renderSampled()), in every backend.
    int samples = 1;
    /// The shading eye (issue 39, `--specular center|per-view`; lighting.h SpecularEye).
    SpecularEye specular = SpecularEye::Center;
};

/// Caller-owned memory for the images of one render: `views` colour images of width×height
/// RGBA8 back to back (view v at color() + v·width·height·4), and as many float depth images.
/// Each view's slice is handed out once, to a vector of exactly its size, by a memory resource
/// of its own; anything else (another size, a second allocation) comes from the heap, so a
/// backend or a post-process that reallocates stays correct and inPlace() tells the caller.
/// Not copyable or movable (the resources point into it); thread-safe per view.
class OutputBlock {
public:
    OutputBlock(int views, int width, int height);
    ~OutputBlock();
    OutputBlock(const OutputBlock&) = delete;
    OutputBlock& operator=(const OutputBlock&) = delete;

    int views() const { return views_; }
    int width() const { return width_; }
    int height() const { return height_; }
    std::uint8_t* color() { return color_; }
    float* depth() { return depth_; }
    std::pmr::memory_resource* colorMemory(int view);
    std::pmr::memory_resource* depthMemory(int view);
    /// Whether the image's pixels are view v's slice of the block.
    bool inPlace(const Image& image, int view) const;
    bool inPlace(const DepthImage& image, int view) const;

private:
    class Slice;
    int views_, width_, height_;
    std::uint8_t* color_ = nullptr;
    float* depth_ = nullptr;
    std::vector<std::unique_ptr<Slice>> slices_;  ///< [2v] color, [2v + 1] depth
};

/// Wall-clock time per pipeline stage of one render, where a backend measures it (soft does:
/// vertex = vertex stage, setup = primitive stage (cull, clip tests, binning), raster = triangle
/// setup + coverage + depth + shading, and the clear of each band's rows just before it is
/// drawn; fill = sizing and handing out the images).
struct StageTimes {
    double vertexMs = 0, setupMs = 0, rasterMs = 0, fillMs = 0;
};

/// Timings of a backend's last successful render() (Backend::lastStats()). Fields a backend
/// does not measure stay at their defaults: stages zero, gpuMs negative.
struct RenderStats {
    std::string method;           ///< the method that ran (for "auto": the one it picked)
    StageTimes stages;            ///< soft: per pipeline stage
    double gpuMs = -1.0;          ///< GPU timer of the draws (gl: GL_TIME_ELAPSED); <0 if none
    double drawWallMs = 0.0;      ///< wall time from the first draw to the finished frame
    double readbackWallMs = 0.0;  ///< wall time of handing the views' images back
    double totalWallMs = 0.0;     ///< the whole render() call
    /// gl: the batches of at most the method's per-pass view limit it drew the views in
    /// (kalaiah2007 §3); 1 when all views fit in one pass (and for soft).
    int passes = 1;
    /// The samples a pixel the last render drew into its targets: N where `--aa N` was
    /// multisampled on the device (gl), 1 for one sample and for each sub-pixel pass of
    /// renderSampled() (mvr/core/antialias.h).
    int samples = 1;
};

/// The window depth of the nearest and the farthest pixel a view drew (depth < 1).
struct DepthRange {
    float nearest = 1.0f, farthest = 0.0f;
    /// false: the view drew nothing of the scene.
    bool drew() const { return nearest <= farthest; }
};

/// What one render produces: a color and a depth image per view, in rig view order.
struct RenderOutput {
    std::vector<Image> color;
    std::vector<DepthImage> depth;  ///< empty for methods without a per-view depth buffer
    /// Per view, when `depth` is empty because RenderSettings::depth was false and the backend
    /// measured the range on its device instead (gl: a compute reduction, 8 bytes a view read
    /// back instead of 4 a pixel); else empty. Read it through depthRangeOf().
    std::vector<DepthRange> depthRange;
    std::string method;             ///< the method that actually ran (differs for "auto")
    std::string note;               ///< e.g. why "auto" picked that method
    StageTimes stages;              ///< per-stage times (zero where not measured)
};

class Backend {
public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;
    /// Every method this backend knows, supported here or not.
    virtual std::vector<std::string> methods() const = 0;
    /// The method used when none is asked for (its fastest exact one).
    virtual std::string defaultMethod() const = 0;
    /// ok, or why `method` cannot run (unknown: Usage; not on this driver/build: Unsupported).
    virtual Status supports(const std::string& method) const = 0;
    /// Renders the scene from every view of the rig.
    virtual Result<RenderOutput> render(const Scene& scene, const Rig& rig,
                                        const RenderSettings& settings,
                                        const std::string& method) = 0;
    /// render() into `out`: the same images, stats and errors, but a backend may reuse the
    /// storage of out's images when they already have the request's view count and size (the
    /// soft backend does: no allocation and no page faults, only the clear), so a caller that
    /// renders frame after frame keeps one RenderOutput. On error `out` is unspecified. The
    /// default: out = render(…).
    virtual Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                              const std::string& method, RenderOutput& out) {
        auto r = render(scene, rig, settings, method);
        if (!r) return r.status();
        out = std::move(r).value();
        return {};
    }
    /// Lines for `mvr info` (limits, driver strings).
    virtual std::vector<std::string> info() const { return {}; }
    /// Timings of the last successful render(); nullopt before the first.
    virtual std::optional<RenderStats> lastStats() const = 0;
};

/// render() of a backend whose renderInto() does the work (soft, gl, auto): a fresh output
/// filled by it. Such a backend's render() is `return renderThroughInto(*this, …);`.
inline Result<RenderOutput> renderThroughInto(Backend& backend, const Scene& scene, const Rig& rig,
                                             const RenderSettings& settings,
                                             const std::string& method) {
    RenderOutput out;
    if (Status s = backend.renderInto(scene, rig, settings, method, out); !s) return s;
    return out;
}

/// The settings a backend renders `s` with. Shadow maps are looked up where the lighting is
/// evaluated, and per vertex they vanish inside large triangles (a ground quad of four
/// vertices under a floating plate shows no shadow at all): vertex shading with shadows is
/// shaded per pixel. Flat keeps one shadow factor per triangle (at its centroid). Per-view
/// specular is per pixel too: vertex colours are computed once for all views.
inline RenderSettings shadedSettings(RenderSettings s) {
    if (s.shadows && s.shading == Shading::Vertex) s.shading = Shading::Pixel;
    if (s.specular == SpecularEye::PerView && s.shading == Shading::Vertex)
        s.shading = Shading::Pixel;
    return s;
}

/// Whether each view's fragments are shaded from that view's own eye: --specular per-view in
/// pixel shading (the one shading evaluated per view; flat keeps the centre eye).
inline bool shadesFromEachEye(const RenderSettings& s) {
    return s.specular == SpecularEye::PerView && s.shading == Shading::Pixel;
}

/// The range of the drawn pixels (depth < 1) of one window-depth image.
DepthRange depthRangeOfImage(std::span<const float> depth);

/// View `view`'s depth range: from its depth image when there is one, else from
/// RenderOutput::depthRange; nullopt when the output has neither (gl gs-mrt).
std::optional<DepthRange> depthRangeOf(const RenderOutput& out, int view);

/// Color + depth bytes a request of `views` views of width×height needs (8 bytes a pixel).
double framebufferBytes(int views, int width, int height);
/// The most any backend allocates for one request's color and depth images.
inline constexpr double kMaxFramebufferBytes = 8.0 * 1024 * 1024 * 1024;

/// The one validation of a render request, called by every backend's render() and by the
/// tools before rendering, so that the same request gets the same message and error code
/// whatever the backend: settings (validateSettings), scene (validateScene, finite instance
/// transforms), rig (1..kMaxViews views, finite matrices, shears and convergence) and the
/// memory the images need (Unsupported above kMaxFramebufferBytes). Backends add only their
/// own driver limits after it. Errors name the value ("view 3 has a non-finite matrix").
Status validateRequest(const Scene& scene, const Rig& rig, const RenderSettings& settings);

/// Validates settings (size within 1..16384, finite clear color). Errors: ErrorCode::Usage.
Status validateSettings(const RenderSettings& settings);

/// Parses "flat" | "vertex" | "pixel". Errors: ErrorCode::Usage listing the choices.
Result<Shading> parseShading(const std::string& name);
const char* shadingName(Shading shading);

}  // namespace mvr
