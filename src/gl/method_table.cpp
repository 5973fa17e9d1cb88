// src/gl/method_table.cpp — the rows of the gl backend's method table (method_table.h).
#include "method_table.h"

#include <algorithm>
#include <climits>

#include <fmt/format.h>

#include "renderer.h"

namespace mvr::gl::detail {

namespace {

std::string driverName(const GlCaps& c) { return fmt::format("{} ({})", c.renderer, c.version); }

// Components a GS emits per vertex: gl_Position, the layer/viewport/flag, the varyings
// (gs-depthmap's DEPTHMAP adds 4; it renders exactly 2 views, not limited by this); a pixel
// shading pass with normal maps (NORMAL_MAPS) the world tangent and its handedness (4).
int gsComponentsPerVertex(Shading s, bool normalMaps) {
    const int varyings = s == Shading::Pixel ? 6 + (normalMaps ? 4 : 0) : 3;
    return 4 + 1 + varyings;
}

const char* shadingDefine(Shading s) {
    switch (s) {
        case Shading::Flat: return "SHADING_FLAT";
        case Shading::Vertex: return "SHADING_VERTEX";
        case Shading::Pixel: return "SHADING_PIXEL";
    }
    return "SHADING_VERTEX";
}

// ---- view limits, one term each --------------------------------------------------------------

ViewLimitTerm layers(const GlCaps& c) {
    return {std::min(c.maxArrayLayers, c.maxFramebufferLayers),
            fmt::format("GL_MAX_ARRAY_TEXTURE_LAYERS = {}, GL_MAX_FRAMEBUFFER_LAYERS = {}",
                        c.maxArrayLayers, c.maxFramebufferLayers)};
}

ViewLimitTerm gsLoopOutput(const GlCaps& c, Shading s, bool normalMaps) {
    const int comps = gsComponentsPerVertex(s, normalMaps);
    return {std::min(c.maxGsOutputVertices / 3, c.maxGsTotalOutputComponents / (3 * comps)),
            fmt::format("the geometry shader emits 3 vertices x {} components per view: "
                        "GL_MAX_GEOMETRY_OUTPUT_VERTICES = {}, "
                        "GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS = {}",
                        comps, c.maxGsOutputVertices, c.maxGsTotalOutputComponents)};
}

ViewLimitTerm gsInvocations(const GlCaps& c, Shading s, bool normalMaps) {
    // One invocation emits one view's triangle; none at all if that does not fit.
    const bool fits = 3 * gsComponentsPerVertex(s, normalMaps) <= c.maxGsTotalOutputComponents;
    return {fits ? c.maxGsInvocations : 0,
            fmt::format("GL_MAX_GEOMETRY_SHADER_INVOCATIONS = {}", c.maxGsInvocations)};
}

ViewLimitTerm viewports(const GlCaps& c) {
    return {c.maxViewports, fmt::format("GL_MAX_VIEWPORTS = {}", c.maxViewports)};
}

ViewLimitTerm viewsOvr(const GlCaps& c) {
    return {c.maxViewsOvr, fmt::format("GL_MAX_VIEWS_OVR = {}", c.maxViewsOvr)};
}

// Tiles of width × height in one target (TileLayout): GL_MAX_TEXTURE_SIZE / GL_MAX_VIEWPORT_DIMS.
ViewLimitTerm tiles(const GlCaps& c, int width, int height) {
    const int maxW = std::min(c.maxTextureSize, c.maxViewportDims[0]);
    const int maxH = std::min(c.maxTextureSize, c.maxViewportDims[1]);
    const long n = static_cast<long>(maxW / std::max(width, 1)) * (maxH / std::max(height, 1));
    return {static_cast<int>(std::min<long>(n, INT_MAX)),
            fmt::format("the views' tiles must fit GL_MAX_TEXTURE_SIZE = {}", c.maxTextureSize)};
}

// ---- shader defines ----------------------------------------------------------------------------

// The geometry shader's loop over the views, each copy sent to `out`.
void gsLoop(ProgramDesc& d, int views, const char* out) {
    addDefine(d, "VS_TO_GS");
    addDefine(d, "GS_VIEWS", views);
    addDefine(d, "GS_MAX_VERTICES", 3 * views);
    d.gsMaxVertices = 3 * views;
    addDefine(d, out);
    d.geometry = true;
}

const char* const kSorbierBrief = "painter's-order artifacts";
const char* const kSorbierPair = "sorbier2008's stereo pair: one MRT attachment per eye";

std::string needsDrawBuffers(const GlCaps& c) {
    if (c.maxDrawBuffers >= 2) return {};
    return fmt::format("needs 2 draw buffers, GL_MAX_DRAW_BUFFERS = {}", c.maxDrawBuffers);
}

}  // namespace

const std::vector<GlMethod>& glMethods() {
    static const std::vector<GlMethod> kRows = {
        {
            // The reference: one full pass of the scene per view, each into its own layer.
            .name = "multipass",
            .target = TargetKind::Layered,
            .limits = [](const GlCaps& c, Shading, bool, int,
                         int) { return std::vector<ViewLimitTerm>{layers(c)}; },
            .defines = [](ProgramDesc& d, const GlCaps&, int) { addDefine(d, "VS_DIRECT"); },
            .flatProvoking = true,
            .draw = &Renderer::drawMultipass,
        },
        {
            // sorbier2008 §4: GS clones to left/right with a flag, MRT, alpha-0 blend, depth
            // test off, instances back to front.
            .name = "gs-mrt",
            .artifact = "sorbier2008 one-pass stereo: depth test off, instances in painter's "
                        "order (back to front); no per-view depth; hidden faces of concave "
                        "objects may show",
            .artifactBrief = kSorbierBrief,
            .target = TargetKind::Mrt,
            .missing = needsDrawBuffers,
            .fixedViews = 2,
            .fixedViewsWhy = kSorbierPair,
            .defines = [](ProgramDesc& d, const GlCaps&, int n) { gsLoop(d, n, "GS_OUT_FLAG"); },
            .draw = &Renderer::drawGsMrt,
        },
        {
            // sorbier2008 §5.2: left-eye depth pre-pass, then gs-mrt tested against it.
            .name = "gs-depthmap",
            .artifact = "sorbier2008 §5.2: left-eye depth pre-pass, both eyes tested against "
                        "it; no per-view depth; the right eye may lose surfaces the left eye "
                        "cannot see",
            .artifactBrief = kSorbierBrief,
            .target = TargetKind::Mrt,
            .missing = needsDrawBuffers,
            .fixedViews = 2,
            .fixedViewsWhy = kSorbierPair,
            .defines =
                [](ProgramDesc& d, const GlCaps&, int n) {
                    gsLoop(d, n, "GS_OUT_FLAG");
                    addDefine(d, "DEPTHMAP");
                },
            .draw = &Renderer::drawGsDepthMap,
        },
        {
            // GS loop over the views → gl_Layer.
            .name = "gs-layered",
            .target = TargetKind::Layered,
            .limits =
                [](const GlCaps& c, Shading s, bool normalMaps, int, int) {
                    return std::vector<ViewLimitTerm>{layers(c), gsLoopOutput(c, s, normalMaps)};
                },
            .defines = [](ProgramDesc& d, const GlCaps&, int n) { gsLoop(d, n, "GS_OUT_LAYER"); },
            .draw = &Renderer::drawLayeredGs,
        },
        {
            // layout(invocations = N): one GS invocation per view → gl_Layer.
            .name = "gs-invocations",
            .target = TargetKind::Layered,
            .limits =
                [](const GlCaps& c, Shading s, bool normalMaps, int, int) {
                    return std::vector<ViewLimitTerm>{layers(c), gsInvocations(c, s, normalMaps)};
                },
            .defines =
                [](ProgramDesc& d, const GlCaps&, int n) {
                    addDefine(d, "VS_TO_GS");
                    addDefine(d, "GS_INVOCATIONS", n);
                    addDefine(d, "GS_OUT_LAYER");
                    d.geometry = true;
                },
            .draw = &Renderer::drawLayeredGs,
        },
        {
            // N instances of every draw; the vertex shader writes gl_Layer = instance.
            .name = "instanced-layer",
            .target = TargetKind::Layered,
            .missing = [](const GlCaps& c) -> std::string {
                if (c.vertexLayer()) return {};
                return fmt::format(
                    "needs GL_ARB_shader_viewport_layer_array or "
                    "GL_AMD_vertex_shader_layer (gl_Layer from the vertex "
                    "shader); {} has neither",
                    driverName(c));
            },
            .limits = [](const GlCaps& c, Shading, bool, int,
                         int) { return std::vector<ViewLimitTerm>{layers(c)}; },
            .defines =
                [](ProgramDesc& d, const GlCaps& c, int) {
                    addDefine(d, "VS_INSTANCED_LAYER");
                    d.vsExtensions =
                        fmt::format("#extension {} : require\n", c.vertexLayerExtension());
                },
            .flatProvoking = true,
            .draw = &Renderer::drawInstancedLayer,
        },
        {
            // GS loop → gl_ViewportIndex into one tiled target, scissored tiles.
            .name = "viewport-array",
            .target = TargetKind::Tiled,
            .missing = [](const GlCaps& c) -> std::string {
                if (c.maxViewports >= 2) return {};
                return fmt::format("GL_MAX_VIEWPORTS = {}", c.maxViewports);
            },
            .limits =
                [](const GlCaps& c, Shading s, bool normalMaps, int w, int h) {
                    return std::vector<ViewLimitTerm>{viewports(c), gsLoopOutput(c, s, normalMaps),
                                                      tiles(c, w, h)};
                },
            .defines = [](ProgramDesc& d, const GlCaps&,
                          int n) { gsLoop(d, n, "GS_OUT_VIEWPORT"); },
            .draw = &Renderer::drawViewportArray,
        },
        {
            // GL_OVR_multiview: the driver replicates the draw, gl_ViewID_OVR picks the view.
            .name = "multiview",
            .target = TargetKind::Layered,
            .missing = [](const GlCaps& c) -> std::string {
                if (c.has("GL_OVR_multiview")) return {};
                return fmt::format("GL_OVR_multiview is not supported by {}", driverName(c));
            },
            .limits =
                [](const GlCaps& c, Shading, bool, int, int) {
                    return std::vector<ViewLimitTerm>{layers(c), viewsOvr(c)};
                },
            .defines =
                [](ProgramDesc& d, const GlCaps& c, int n) {
                    addDefine(d, "VS_MULTIVIEW");
                    addDefine(d, "NUM_VIEWS", n);
                    d.vsExtensions = "#extension GL_OVR_multiview : require\n";
                    // The view index may reach outputs other than the position (--specular
                    // per-view's eye, shaders.cpp) only with GL_OVR_multiview2.
                    if (c.has("GL_OVR_multiview2"))
                        d.vsExtensions += "#extension GL_OVR_multiview2 : enable\n";
                },
            .perViewEyeMissing = [](const GlCaps& c) -> std::string {
                if (c.has("GL_OVR_multiview2")) return {};
                return fmt::format("needs GL_OVR_multiview2 (the view index as a vertex "
                                   "shader output); {} has only GL_OVR_multiview",
                                   driverName(c));
            },
            .flatProvoking = true,
            .draw = &Renderer::drawMultiview,
            // GL_OVR_multiview attaches 2D-array textures; multisampled views need
            // GL_OVR_multiview_multisampled_render_to_texture (GLES only): sub-pixel passes.
            .multisample = false,
        },
        {
            // kalaiah2007 §4: 3·N dummy vertices per triangle, viewport transform in the VS
            // into one partitioned target, per-view clipping by 4 clip distances.
            .name = "kalaiah-emulation",
            .target = TargetKind::Tiled,
            .missing = [](const GlCaps& c) -> std::string {
                if (c.maxClipDistances >= 4) return {};
                return fmt::format("needs 4 clip distances, GL_MAX_CLIP_DISTANCES = {}",
                                   c.maxClipDistances);
            },
            .limits = [](const GlCaps& c, Shading, bool, int w,
                         int h) { return std::vector<ViewLimitTerm>{tiles(c, w, h)}; },
            .defines = [](ProgramDesc& d, const GlCaps&, int) { addDefine(d, "VS_KALAIAH"); },
            .prepare = &Renderer::prepareKalaiah,
            .draw = &Renderer::drawKalaiah,
        },
        {
            // Measures the exact rows that run here and renders with the fastest (renderAuto).
            .name = "auto",
            .measuresExact = true,
        },
    };
    return kRows;
}

const GlMethod* findMethod(const std::string& name) {
    for (const GlMethod& m : glMethods()) {
        if (name == m.name) return &m;
    }
    return nullptr;
}

const std::vector<std::string>& methodNames() {
    static const std::vector<std::string> kNames = [] {
        std::vector<std::string> names;
        for (const GlMethod& m : glMethods()) names.emplace_back(m.name);
        return names;
    }();
    return kNames;
}

const GlMethod& defaultMethod() {
    static const GlMethod& kAuto = *std::find_if(glMethods().begin(), glMethods().end(),
                                                 [](const GlMethod& m) { return m.measuresExact; });
    return kAuto;
}

Status driverSupport(const GlMethod& m, const GlCaps& caps) {
    if (!m.missing) return Status::ok();
    const std::string why = m.missing(caps);
    if (why.empty()) return Status::ok();
    return unsupportedError(fmt::format("{}: {}", m.name, why));
}

int viewLimit(const GlMethod& m, const GlCaps& caps, Shading shading, int width, int height,
              bool normalMaps) {
    if (m.fixedViews > 0) return m.fixedViews;
    int limit = kMaxViews;
    if (m.limits) {
        for (const ViewLimitTerm& t : m.limits(caps, shading, normalMaps, width, height))
            limit = std::min(limit, t.views);
    }
    return std::max(limit, 0);
}

Status checkMethodViews(const GlMethod& m, const GlCaps& caps, int views, const RenderSettings& s,
                        bool normalMaps) {
    if (m.fixedViews > 0 && views != m.fixedViews) {
        return usageError(fmt::format("gl: {} renders exactly {} views ({}); the rig has {}",
                                      m.name, m.fixedViews, m.fixedViewsWhy, views));
    }
    // More views than one pass takes are drawn in batches (Renderer::renderOnce); only a method
    // that cannot draw a single view here is refused.
    if (viewLimit(m, caps, s.shading, s.width, s.height, normalMaps) >= 1) return Status::ok();
    std::string why = fmt::format("mvr::kMaxViews = {}", kMaxViews);
    if (m.limits) {
        for (ViewLimitTerm& t : m.limits(caps, s.shading, normalMaps, s.width, s.height)) {
            if (t.views < 1) {
                why = std::move(t.why);
                break;
            }
        }
    }
    return unsupportedError(fmt::format("gl: {}: cannot draw one view of {}x{} here ({})", m.name,
                                        s.width, s.height, why));
}

int passCount(int views, int perPass) { return perPass < 1 ? 0 : (views + perPass - 1) / perPass; }

ProgramDesc methodProgram(const GlMethod& m, const GlCaps& caps, Shading shading, int views) {
    ProgramDesc d;
    addDefine(d, shadingDefine(shading));
    if (m.defines) m.defines(d, caps, views);
    if (m.flatProvoking && shading == Shading::Flat) addDefine(d, "FLAT_PROVOKING");
    return d;
}

ProgramDesc depthPrepassProgram() {
    ProgramDesc d;
    addDefine(d, "DEPTH_ONLY");
    addDefine(d, "VS_DIRECT");
    return d;
}

const char* depthPrepassName() { return "depth-prepass"; }

std::string autoExclusions() {
    std::vector<std::string> names, briefs;
    for (const GlMethod& m : glMethods()) {
        if (!m.artifact) continue;
        names.emplace_back(m.name);
        const std::string brief = m.artifactBrief ? m.artifactBrief : m.artifact;
        if (std::find(briefs.begin(), briefs.end(), brief) == briefs.end()) briefs.push_back(brief);
    }
    if (names.empty()) return {};
    return fmt::format("{} excluded ({})", fmt::join(names, "/"), fmt::join(briefs, ", "));
}

}  // namespace mvr::gl::detail
