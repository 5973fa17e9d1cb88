// The GPU anaglyphs of composeGpu(): sorbier2008 §4.3's red-cyan (anaglyph-color, colour
// masks) against the CPU mapping R ← left, G B ← right, and every anaglyph against the CPU.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "gl_test_util.h"
#include "mvr/composite/anaglyph.h"
#include "mvr/gl/composite_gpu.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

Image randomImage(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    Image img(w, h);
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xFF);
    return img;
}

// composeGpu() of two views (a stereo pair: left, right).
Result<Image> composePair(const std::string& format, const Image& left, const Image& right,
                          const GpuComposeOptions& gpu = {}) {
    const std::vector<Image> views = {left, right};
    return composeGpu(format, views, {}, gpu);
}

TEST(AnaglyphGpu, MatchesCpuMappingExactly) {
    const Image left = randomImage(37, 23, 1), right = randomImage(37, 23, 2);
    auto r = composePair("anaglyph-color", left, right);
    if (!r && r.status().code() == ErrorCode::Unsupported) MVR_SKIP(MethodUnsupportedByDriver) << r.status().message();
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
    auto r = composePair("anaglyph-color", Image(4, 4), Image(5, 4));
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);
    EXPECT_NE(r.status().message().find("views differ in size"), std::string::npos)
        << r.status().message();
    auto e = composePair("anaglyph-color", Image(), Image());
    ASSERT_FALSE(e);
    EXPECT_EQ(e.status().code(), ErrorCode::Usage);
}

TEST(AnaglyphGpu, BrokenMixGlslIsAUsageErrorWithTheLog) {
    auto r = composePair("anaglyph-color", Image(4, 4), Image(4, 4),
                         {.anaglyphMix = "vec3 mvrAnaglyph(vec3 l) { oops }"});
    if (!r && r.status().code() == ErrorCode::Unsupported) MVR_SKIP(MethodUnsupportedByDriver) << r.status().message();
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Usage);
    EXPECT_NE(r.status().message().find("does not compile"), std::string::npos)
        << r.status().message();
}

// Every anaglyph of the composite module, composed on the GPU from the same formula
// (composite::anaglyphGlsl; anaglyph-color by colour masks), against the CPU composite. Tolerance: 1/255 per channel — the
// GPU's pow() (exp2/log2 approximations in llvmpipe) and the CPU's table-driven sRGB curve
// can round an output to the neighbouring 8-bit value; nothing more.
TEST(AnaglyphGpu, EveryCompositeAnaglyphMatchesTheCpuWithin1) {
    const Image left = randomImage(64, 48, 3), right = randomImage(64, 48, 4);
    using composite::AnaglyphMethod;
    for (AnaglyphMethod m : {AnaglyphMethod::Color, AnaglyphMethod::HalfColor, AnaglyphMethod::Gray,
                             AnaglyphMethod::True, AnaglyphMethod::Dubois,
                             AnaglyphMethod::DuboisGreenMagenta, AnaglyphMethod::DuboisAmberBlue}) {
        auto gpu = composePair(std::string(composite::anaglyphFormatName(m)), left, right);
        if (!gpu && gpu.status().code() == ErrorCode::Unsupported)
            MVR_SKIP(MethodUnsupportedByDriver) << gpu.status().message();
        ASSERT_TRUE(gpu) << gpu.status().message();
        auto cpu = composite::anaglyph(left, right, m);
        ASSERT_TRUE(cpu) << cpu.status().message();
        const ImageDiff d = compareImages(*gpu, *cpu, 1);
        std::printf("[ measured ] %s: GPU vs CPU max delta %d, %ld pixels off by 1\n",
                    std::string(composite::anaglyphFormatName(m)).c_str(), d.maxDelta,
                    static_cast<long>(compareImages(*gpu, *cpu, 0).differingPixels));
        EXPECT_LE(d.maxDelta, 1) << composite::anaglyphFormatName(m);
    }
}

// A replacement mix (GpuComposeOptions::anaglyphMix) is what runs: anaglyphGlsl() of another
// method given for anaglyph-color gives that method's image.
TEST(AnaglyphGpu, AnaglyphMixReplacesTheFormatsMix) {
    const Image left = randomImage(16, 8, 5), right = randomImage(16, 8, 6);
    using composite::AnaglyphMethod;
    auto own = composePair("anaglyph-gray", left, right);
    if (!own && own.status().code() == ErrorCode::Unsupported)
        MVR_SKIP(MethodUnsupportedByDriver) << own.status().message();
    ASSERT_TRUE(own) << own.status().message();
    auto mixed = composePair("anaglyph-color", left, right,
                             {.anaglyphMix = composite::anaglyphGlsl(AnaglyphMethod::Gray)});
    ASSERT_TRUE(mixed) << mixed.status().message();
    EXPECT_EQ(compareImages(*mixed, *own, 0).maxDelta, 0);
}

}  // namespace
}  // namespace mvr::gl::test
