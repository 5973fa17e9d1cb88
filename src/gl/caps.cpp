#include "caps.h"

#include <algorithm>
#include <vector>

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace mvr::gl::detail {

namespace {
int getInt(GLenum e) {
    GLint v = 0;
    glGetIntegerv(e, &v);
    while (glGetError() != GL_NO_ERROR) {
    }  // an enum the driver lacks reads as 0
    return v;
}
// The sample counts `target` takes for `format` (glGetInternalformativ; none on error).
std::set<int> sampleCountsOf(GLenum target, GLenum format) {
    GLint n = 0;
    glGetInternalformativ(target, format, GL_NUM_SAMPLE_COUNTS, 1, &n);
    std::vector<GLint> counts(std::size_t(std::max(n, 0)));
    if (n > 0) glGetInternalformativ(target, format, GL_SAMPLES, n, counts.data());
    std::set<int> out;
    if (glGetError() != GL_NO_ERROR) {
        while (glGetError() != GL_NO_ERROR) {
        }
        return out;
    }
    for (GLint c : counts) {
        if (c > 1) out.insert(c);
    }
    return out;
}
std::string getString(GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? reinterpret_cast<const char*>(s) : "?";
}
}  // namespace

bool GlCaps::vertexLayer() const { return !vertexLayerExtension().empty(); }

std::string GlCaps::vertexLayerExtension() const {
    if (has("GL_ARB_shader_viewport_layer_array")) return "GL_ARB_shader_viewport_layer_array";
    if (has("GL_AMD_vertex_shader_layer")) return "GL_AMD_vertex_shader_layer";
    return {};
}

bool GlCaps::softwareRenderer() const {
    for (const char* name : {"llvmpipe", "softpipe", "lavapipe", "LLVMPIPE", "SwiftShader"}) {
        if (renderer.find(name) != std::string::npos) return true;
    }
    return false;
}

GlCaps GlCaps::query() {
    GlCaps c;
    c.vendor = getString(GL_VENDOR);
    c.renderer = getString(GL_RENDERER);
    c.version = getString(GL_VERSION);
    c.glslVersion = getString(GL_SHADING_LANGUAGE_VERSION);
    const int n = getInt(GL_NUM_EXTENSIONS);
    for (int i = 0; i < n; ++i) {
        if (const GLubyte* e = glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i))) {
            c.extensions.insert(reinterpret_cast<const char*>(e));
        }
    }
    c.maxTextureSize = getInt(GL_MAX_TEXTURE_SIZE);
    c.maxArrayLayers = getInt(GL_MAX_ARRAY_TEXTURE_LAYERS);
    c.maxFramebufferLayers = getInt(GL_MAX_FRAMEBUFFER_LAYERS);
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, c.maxViewportDims);
    c.maxViewports = getInt(GL_MAX_VIEWPORTS);
    c.maxDrawBuffers = getInt(GL_MAX_DRAW_BUFFERS);
    c.maxColorAttachments = getInt(GL_MAX_COLOR_ATTACHMENTS);
    c.maxGsOutputVertices = getInt(GL_MAX_GEOMETRY_OUTPUT_VERTICES);
    c.maxGsTotalOutputComponents = getInt(GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS);
    c.maxGsOutputComponents = getInt(GL_MAX_GEOMETRY_OUTPUT_COMPONENTS);
    c.maxGsInvocations = getInt(GL_MAX_GEOMETRY_SHADER_INVOCATIONS);
    c.maxClipDistances = getInt(GL_MAX_CLIP_DISTANCES);
    c.maxUniformBlockSize = getInt(GL_MAX_UNIFORM_BLOCK_SIZE);
    if (c.has("GL_OVR_multiview")) c.maxViewsOvr = getInt(GL_MAX_VIEWS_OVR);
    GLint bits = 0;
    glGetQueryiv(GL_TIME_ELAPSED, GL_QUERY_COUNTER_BITS, &bits);
    while (glGetError() != GL_NO_ERROR) {
    }
    c.timerBits = bits;
    bool first = true;
    for (GLenum target : {GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_2D_MULTISAMPLE_ARRAY}) {
        for (GLenum format : {GL_RGBA8, GL_DEPTH_COMPONENT32F}) {
            std::set<int> counts = sampleCountsOf(target, format);
            if (first) {
                c.sampleCounts = std::move(counts);
                first = false;
                continue;
            }
            std::erase_if(c.sampleCounts, [&](int n) { return counts.count(n) == 0; });
        }
    }
    return c;
}

std::vector<std::string> GlCaps::describe() const {
    auto yesNo = [&](const char* e) { return fmt::format("{}: {}", e, has(e) ? "yes" : "no"); };
    return {
        fmt::format("GL_VENDOR: {}", vendor),
        fmt::format("GL_RENDERER: {}", renderer),
        fmt::format("GL_VERSION: {}", version),
        fmt::format("GL_SHADING_LANGUAGE_VERSION: {}", glslVersion),
        fmt::format("GL_MAX_TEXTURE_SIZE: {}", maxTextureSize),
        fmt::format("GL_MAX_ARRAY_TEXTURE_LAYERS: {}", maxArrayLayers),
        fmt::format("GL_MAX_FRAMEBUFFER_LAYERS: {}", maxFramebufferLayers),
        fmt::format("GL_MAX_VIEWPORT_DIMS: {}x{}", maxViewportDims[0], maxViewportDims[1]),
        fmt::format("GL_MAX_VIEWPORTS: {}", maxViewports),
        fmt::format("GL_MAX_DRAW_BUFFERS: {}", maxDrawBuffers),
        fmt::format("GL_MAX_GEOMETRY_OUTPUT_VERTICES: {}", maxGsOutputVertices),
        fmt::format("GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS: {}", maxGsTotalOutputComponents),
        fmt::format("GL_MAX_GEOMETRY_SHADER_INVOCATIONS: {}", maxGsInvocations),
        fmt::format("GL_MAX_CLIP_DISTANCES: {}", maxClipDistances),
        fmt::format("GL_MAX_VIEWS_OVR: {}", maxViewsOvr),
        fmt::format("GL_TIME_ELAPSED counter bits: {}", timerBits),
        fmt::format("multisample counts (RGBA8 and DEPTH32F targets): {}",
                    sampleCounts.empty() ? "none" : fmt::format("{}", fmt::join(sampleCounts, ", "))),
        yesNo("GL_ARB_shader_viewport_layer_array"),
        yesNo("GL_AMD_vertex_shader_layer"),
        yesNo("GL_OVR_multiview"),
        yesNo("GL_OVR_multiview2"),
    };
}

}  // namespace mvr::gl::detail
