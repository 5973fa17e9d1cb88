// The gl method table's per-view specular requirement (src/gl/method_table.h
// GlMethod::perViewEyeMissing), against capabilities written here: gl:multiview passes the
// fragment's view on from the vertex shader, which GL_OVR_multiview alone does not allow; every
// other method finds its view without the vertex stage's help. The geometry-shader methods'
// views per pass with normal maps (the world tangent's 4 components a vertex). No context
// needed.
#include <gtest/gtest.h>

#include "method_table.h"

namespace mvr::gl::detail {
namespace {

TEST(GlMethodTable, PerViewSpecularOnMultiviewNeedsMultiview2) {
    GlCaps caps;
    caps.renderer = "a multiview GPU";
    caps.extensions = {"GL_OVR_multiview"};
    const GlMethod* multiview = findMethod("multiview");
    ASSERT_TRUE(multiview && multiview->perViewEyeMissing);
    const std::string why = multiview->perViewEyeMissing(caps);
    EXPECT_NE(why.find("needs GL_OVR_multiview2"), std::string::npos) << why;
    caps.extensions.insert("GL_OVR_multiview2");
    EXPECT_EQ(multiview->perViewEyeMissing(caps), "");
    for (const GlMethod& m : glMethods()) {
        if (&m != multiview) EXPECT_EQ(m.perViewEyeMissing, nullptr) << m.name;
    }
}

// A geometry shader's views per pass count the components each view's 3 vertices emit:
// gl_Position 4 + the layer / viewport 1 + the varyings (flat and vertex 3, pixel 6, pixel
// with normal maps 10: the world tangent and its handedness) out of
// GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS; flat and vertex shading never carry the tangent.
TEST(GlMethodTable, NormalMapsCountTheTangentInGeometryShaderLimits) {
    GlCaps caps;
    caps.maxArrayLayers = caps.maxFramebufferLayers = 2048;
    caps.maxTextureSize = caps.maxViewportDims[0] = caps.maxViewportDims[1] = 16384;
    caps.maxViewports = 64;
    caps.maxGsOutputVertices = 1024;
    caps.maxGsTotalOutputComponents = 1024;
    caps.maxGsInvocations = 32;
    for (const char* name : {"gs-layered", "viewport-array"}) {
        const GlMethod* m = findMethod(name);
        ASSERT_TRUE(m) << name;
        EXPECT_EQ(viewLimit(*m, caps, Shading::Vertex, 64, 48), 1024 / (3 * 8)) << name;
        EXPECT_EQ(viewLimit(*m, caps, Shading::Vertex, 64, 48, true), 1024 / (3 * 8)) << name;
        EXPECT_EQ(viewLimit(*m, caps, Shading::Pixel, 64, 48), 1024 / (3 * 11)) << name;
        EXPECT_EQ(viewLimit(*m, caps, Shading::Pixel, 64, 48, true), 1024 / (3 * 15)) << name;
    }
    // gs-invocations: one view's triangle a invocation, none at all where it does not fit.
    const GlMethod* invocations = findMethod("gs-invocations");
    ASSERT_TRUE(invocations);
    caps.maxGsTotalOutputComponents = 40;  // 3 × 11 fits, 3 × 15 does not
    EXPECT_EQ(viewLimit(*invocations, caps, Shading::Pixel, 64, 48), 32);
    EXPECT_EQ(viewLimit(*invocations, caps, Shading::Pixel, 64, 48, true), 0);
    RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.shading = Shading::Pixel;
    EXPECT_TRUE(checkMethodViews(*invocations, caps, 2, s));
    const Status refused = checkMethodViews(*invocations, caps, 2, s, true);
    EXPECT_EQ(refused.code(), ErrorCode::Unsupported) << refused.message();
    // Methods without a geometry shader are not limited by it.
    const GlMethod* multipass = findMethod("multipass");
    ASSERT_TRUE(multipass);
    EXPECT_EQ(viewLimit(*multipass, caps, Shading::Pixel, 64, 48, true), kMaxViews);
}

}  // namespace
}  // namespace mvr::gl::detail
