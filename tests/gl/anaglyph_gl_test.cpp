// The GPU red-cyan anaglyph (sorbier2008 §4.3) against the CPU mapping R ← left, G B ← right.
#include <random>

#include <gtest/gtest.h>

#include "gl_test_util.h"

namespace mvr::gl::test {
namespace {

Image randomImage(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    Image img(w, h);
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xFF);
    return img;
}

TEST(AnaglyphGpu, MatchesCpuMappingExactly) {
    const Image left = randomImage(37, 23, 1), right = randomImage(37, 23, 2);
    auto r = composeAnaglyphGpu(left, right);
    if (!r && r.status().code() == ErrorCode::Unsupported) GTEST_SKIP() << r.status().message();
    ASSERT_TRUE(r) << r.status().message();
    ASSERT_EQ(r->width, 37);
    ASSERT_EQ(r->height, 23);
    for (int y = 0; y < 23; ++y) {
        for (int x = 0; x < 37; ++x) {
            const Rgba8 l = left.at(x, y), rr = right.at(x, y), o = r->at(x, y);
            ASSERT_EQ(o.r, l.r) << x << "," << y;
            ASSERT_EQ(o.g, rr.g) << x << "," << y;
            ASSERT_EQ(o.b, rr.b) << x << "," << y;
            ASSERT_EQ(o.a, 255);
        }
    }
}

TEST(AnaglyphGpu, RejectsMismatchedSizes) {
    auto r = composeAnaglyphGpu(Image(4, 4), Image(5, 4));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);
    EXPECT_NE(r.status().message().find("same size"), std::string::npos);
    auto e = composeAnaglyphGpu(Image(), Image());
    ASSERT_FALSE(e);
    EXPECT_EQ(e.status().code(), ErrorCode::Usage);
}

}  // namespace
}  // namespace mvr::gl::test
