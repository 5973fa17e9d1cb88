// src/gl/caps.h — what the current GL context offers: strings, extensions, limits.
#pragma once

#include <set>
#include <string>
#include <vector>

namespace mvr::gl::detail {

struct GlCaps {
    std::string vendor, renderer, version, glslVersion;
    std::set<std::string> extensions;
    int maxTextureSize = 0, maxArrayLayers = 0, maxFramebufferLayers = 0;
    int maxViewportDims[2] = {0, 0};
    int maxViewports = 0;
    int maxDrawBuffers = 0, maxColorAttachments = 0;
    int maxGsOutputVertices = 0, maxGsTotalOutputComponents = 0, maxGsOutputComponents = 0;
    int maxGsInvocations = 0;
    int maxClipDistances = 0;
    int maxUniformBlockSize = 0;
    int maxViewsOvr = 0;  ///< GL_MAX_VIEWS_OVR, 0 without GL_OVR_multiview
    int timerBits = 0;    ///< GL_QUERY_COUNTER_BITS of GL_TIME_ELAPSED (0 = no timer)
    /// The sample counts (> 1) every multisampled target of the backend takes here: RGBA8 and
    /// DEPTH_COMPONENT32F, as 2D and 2D-array multisample textures (glGetInternalformativ's
    /// GL_SAMPLES, intersected). `--aa N` multisamples where N is one of them.
    std::set<int> sampleCounts;

    bool multisamples(int samples) const { return sampleCounts.count(samples) != 0; }

    /// A rasteriser on the CPU (Mesa llvmpipe / softpipe, or zink over lavapipe): a pixel-pack
    /// buffer is a second CPU copy there, so the views are read straight into their images.
    bool softwareRenderer() const;

    bool has(const std::string& ext) const { return extensions.count(ext) != 0; }
    /// gl_Layer from the vertex shader (ARB_shader_viewport_layer_array or AMD_vertex_shader_layer).
    bool vertexLayer() const;
    std::string vertexLayerExtension() const;

    /// Queries the current context.
    static GlCaps query();
    /// Lines for `mvr info`.
    std::vector<std::string> describe() const;
};

}  // namespace mvr::gl::detail
