// The gl method table's per-view specular requirement (src/gl/method_table.h
// GlMethod::perViewEyeMissing), against capabilities written here: gl:multiview passes the
// fragment's view on from the vertex shader, which GL_OVR_multiview alone does not allow; every
// other method finds its view without the vertex stage's help. No context needed.
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

}  // namespace
}  // namespace mvr::gl::detail
