// mvr/gl/gl_backend.h — the OpenGL 4.5 backend ("gl"), headless through EGL.
//
// Conventions (all OpenGL): right-handed world and eye space, eye looks down −Z; NDC z in
// [−1, 1]; window depth = ndc.z / 2 + 1/2 stored as 32-bit float, cleared to 1, depth test
// GL_LESS; counter-clockwise front faces; fill rule = the driver's (GL's top-left-like rule
// with the pixel-center sample). Images come back with row 0 at the TOP (GL's row 0 is the
// bottom: rows are flipped on readback), RGBA8 with alpha 255, as image.h requires.
//
// Context: created lazily on the first call that needs GL (supports(), render(), info()), never
// in makeGlBackend(). Platforms tried, in order: EGL_EXT_platform_device on a hardware device
// (a GPU; devices with EGL_MESA_device_software are skipped), then Mesa's surfaceless platform
// (EGL_MESA_platform_surfaceless: llvmpipe on machines without a GPU), then the default
// display. The environment variable MVR_EGL_PLATFORM=device|surfaceless|default forces one.
// Each backend owns its context and makes it current on the calling thread at every call; use
// one backend from one thread at a time (a context current on another thread cannot be made
// current: that is an Internal "eglMakeCurrent: EGL_BAD_ACCESS" error, not a crash).
// When none gives an OpenGL 4.5 core context every GL call returns ErrorCode::Unsupported with
// "no EGL display: EGL_…" or "…: OpenGL 4.5 core context not available: EGL_…".
//
// Methods (render()'s `method`), each producing per-view color and, where it has a depth
// buffer per view, per-view depth:
//   multipass          one draw of the scene per view into its own layer. The reference.
//   gs-mrt             sorbier2008 §4: the geometry shader clones each triangle to the left and
//                      right eye with a flag; the fragment shader writes its eye's MRT attachment
//                      and alpha 0 to the other; blending SRC_ALPHA/ONE_MINUS_SRC_ALPHA; depth
//                      test off; instances drawn back to front. No depth output. 2 views only.
//                      Visibility errors inside concave objects are the paper's (Fig. 4, 5).
//   gs-depthmap        sorbier2008 §5.2: left-eye depth pre-pass into a depth texture, then the
//                      gs-mrt pass with each fragment tested against it (the right eye through
//                      its left-eye coordinates). No depth output. 2 views only.
//   gs-layered         GS loop over N views writing gl_Layer of a layered color + depth target.
//   gs-invocations     the same with layout(invocations = N): one GS invocation per view.
//   instanced-layer    N instances; the vertex shader writes gl_Layer
//                      (GL_ARB_shader_viewport_layer_array or GL_AMD_vertex_shader_layer).
//   viewport-array     GS loop writing gl_ViewportIndex into one tiled target (scissored tiles).
//   multiview          GL_OVR_multiview (gl_ViewID_OVR) where the driver has it.
//   kalaiah-emulation  kalaiah2007 §4: 3·N dummy vertices (i = corner, j = view) drawn once per
//                      triangle (instanced: the triangle's corners are per-instance attributes),
//                      viewport transform done in the vertex shader into one partitioned
//                      offscreen buffer, per-view clipping through gl_ClipDistance.
//   auto               measures the exact (per-view depth) methods this driver supports for this
//                      scene, view count and size, and uses the fastest (RenderOutput::method,
//                      ::note say which and the times measured). Measurements are cached. The
//                      backend's defaultMethod().
// gs-mrt and gs-depthmap put their artifact in RenderOutput::note on every render.
// Each method's view limit depends on the driver; info() lists it and render() explains a
// refusal ("gs-invocations: 40 views exceed GL_MAX_GEOMETRY_SHADER_INVOCATIONS = 32").
//
// Shading: exactly lighting.h (Flat / Vertex / Pixel), with the specular view vector toward
// rig.centerEye(). Flat shading uses the world-space face normal: computed from the three
// world-space corners where a geometry shader or the kalaiah vertex shader sees them, and for
// multipass / instanced-layer / multiview the way glShadeModel(GL_FLAT) did it: each
// triangle's provoking (last) vertex is its own and carries the model-space face normal, which
// the vertex shader maps with the cofactor matrix (= the cross product of the world-space
// edges) and shades; the colour is interpolated `flat`.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/status.h"

namespace mvr::gl {

/// Creates the gl backend (name "gl"). Makes no GL or EGL call: safe without a display/GPU.
std::unique_ptr<mvr::Backend> makeGlBackend();

/// Every method name of the gl backend, in a stable order ("multipass" first, "auto" last).
const std::vector<std::string>& glMethodNames();

/// Timings of the last successful render() of a gl backend.
struct GlFrameStats {
    std::string method;           ///< the method that ran
    double gpuMs = 0.0;           ///< GL_TIME_ELAPSED of the draws (readback excluded); <0 if none
    double drawWallMs = 0.0;      ///< wall time from first draw to glFinish()
    double readbackWallMs = 0.0;  ///< wall time of reading back every view's color (+ depth)
    double totalWallMs = 0.0;     ///< the whole render() call
    int passes = 1;               ///< batches of at most the method's per-pass view limit
    int samples = 1;              ///< samples a pixel of its targets (RenderStats::samples)
};

/// `backend.lastStats()` in the gl backend's terms (kept for callers of the gl API; every
/// backend reports through Backend::lastStats()).
std::optional<GlFrameStats> lastFrameStats(const mvr::Backend& backend);

/// (GPU composites — every image format of the composite module, the sorbier2008 §4.3
/// colour-mask anaglyph among them: mvr::gl::composeGpu() in mvr/gl/composite_gpu.h.)

}  // namespace mvr::gl
