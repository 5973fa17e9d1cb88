// src/gl/method_table.h — the gl backend's methods as one table. A row holds everything the
// renderer needs to know about a method: its traits (exact or a documented artifact), its
// target, what the driver must offer, its view limits, its shader #defines and its draw path.
// render() and supports() resolve the method name to a row once; nothing else in src/gl
// compares method names. Adding a method = a row in method_table.cpp + its draw function.
#pragma once

#include <string>
#include <vector>

#include "caps.h"
#include "gl_objects.h"
#include "mvr/core/render.h"
#include "shaders.h"

namespace mvr::gl::detail {

class Renderer;
struct Frame;

/// Where a method draws its views (and so how they are read back).
enum class TargetKind {
    Layered,  ///< one layer per view of a color + depth 2D-array texture
    Tiled,    ///< one tile per view in one color + depth texture (TileLayout)
    Mrt,      ///< sorbier2008's two color attachments, no depth read back
};

/// One driver limit on the view count, with the text that names it in a refusal.
struct ViewLimitTerm {
    int views = 0;
    std::string why;  ///< e.g. "GL_MAX_VIEWPORTS = 16"
};

struct GlMethod {
    const char* name = "";
    /// nullptr: exact — every view has its own depth buffer, the images are multipass's, and
    /// auto may pick it. Else the documented artifact: RenderOutput::note of every render.
    const char* artifact = nullptr;
    const char* artifactBrief = nullptr;  ///< auto's note says why it is excluded
    TargetKind target = TargetKind::Layered;
    /// What the driver lacks for this method ("" when nothing); nullptr: no requirement.
    std::string (*missing)(const GlCaps& caps) = nullptr;
    /// > 0: the method renders exactly this many views (Usage otherwise), whatever the driver.
    int fixedViews = 0;
    const char* fixedViewsWhy = nullptr;
    /// The driver's limits for this shading and view size, in the order a refusal names them
    /// (the first one exceeded); mvr::kMaxViews applies to all. normalMaps: a pixel-shading
    /// pass's program carries the world tangent (NORMAL_MAPS: 4 more varying components).
    std::vector<ViewLimitTerm> (*limits)(const GlCaps& caps, Shading shading, bool normalMaps,
                                         int width, int height) = nullptr;
    /// The method's #defines (after the shading one), vertex-shader extensions, GS flag.
    void (*defines)(ProgramDesc& d, const GlCaps& caps, int views) = nullptr;
    /// What the driver lacks for `--specular per-view` in pixel shading, the fragment's view as
    /// an output of the vertex stage ("" when nothing); nullptr: no requirement beyond `missing`.
    std::string (*perViewEyeMissing)(const GlCaps& caps) = nullptr;
    /// Flat shading draws the provoking-vertex arrays (FLAT_PROVOKING): no stage before the
    /// fragment shader sees the whole triangle.
    bool flatProvoking = false;
    /// Per-frame GPU data beyond the meshes, made before the timed draw (nullptr: none).
    Status (Renderer::*prepare)(const Frame& f) = nullptr;
    /// The draw path (methods.cpp): binds the target, clears it, draws every instance.
    Status (Renderer::*draw)(const Frame& f, GLuint program) = nullptr;
    /// "auto": measures the exact methods that run here and renders with the fastest.
    bool measuresExact = false;
    /// `--aa N` draws into multisampled targets (renderer.h) where the driver takes N samples;
    /// false: sub-pixel passes (antialias.h renderSampled), as on drivers without N.
    bool multisample = true;

    bool exact() const { return artifact == nullptr && !measuresExact; }
};

/// Every row, "multipass" first and "auto" last.
const std::vector<GlMethod>& glMethods();
/// The row named `name`; nullptr for an unknown name.
const GlMethod* findMethod(const std::string& name);
/// The rows' names, in table order.
const std::vector<std::string>& methodNames();
/// The backend's defaultMethod(): the row that measures the exact methods ("auto").
const GlMethod& defaultMethod();

/// Ok, or Unsupported "NAME: what the driver lacks".
Status driverSupport(const GlMethod& m, const GlCaps& caps);
/// The most views `m` draws in one pass on this driver for this shading and view size (0:
/// none); the renderer draws more in batches of this many (kalaiah2007 §3). At most kMaxViews.
/// normalMaps: the pass's program has NORMAL_MAPS (pixel shading with normal maps), whose
/// geometry shaders emit 4 components a vertex more.
int viewLimit(const GlMethod& m, const GlCaps& caps, Shading shading, int width, int height,
              bool normalMaps = false);
/// `views` against the method's own limits: Usage for a fixed-count method given another
/// count, Unsupported naming the limit when not even one view fits in a pass.
Status checkMethodViews(const GlMethod& m, const GlCaps& caps, int views, const RenderSettings& s,
                        bool normalMaps = false);
/// The passes (batches) `views` views take at `perPass` views a pass: ceil(views / perPass).
int passCount(int views, int perPass);

/// The program of `m` for this shading and view count (shading define, the row's defines,
/// FLAT_PROVOKING where the row draws the provoking-vertex arrays).
ProgramDesc methodProgram(const GlMethod& m, const GlCaps& caps, Shading shading, int views);
/// gs-depthmap's internal depth-only pre-pass program (a program variant, not a method), and
/// the name its build errors carry.
ProgramDesc depthPrepassProgram();
const char* depthPrepassName();

/// For auto's note: "A/B excluded (why)" over the artifact rows; "" when there are none.
std::string autoExclusions();

}  // namespace mvr::gl::detail
