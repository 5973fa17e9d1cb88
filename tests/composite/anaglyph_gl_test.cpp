// The GPU anaglyph must equal the CPU one within rounding: every method composed by
// mvr::gl::composeGpu() (anaglyphGlsl() compiled on whatever GL the machine has — Mesa llvmpipe
// on CPU-only machines; anaglyph-color by sorbier2008's colour masks) against anaglyphPixel().
// Skips itself when no EGL display / GL 4.5 context can be made.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mvr/composite/anaglyph.h"
#include "mvr/gl/composite_gpu.h"
#include "mvr_test_support.h"

namespace mvr::composite {
namespace {

TEST(AnaglyphGl, MatchesTheCpuAnaglyphForEveryMethod) {
    constexpr int kW = 64, kH = 64;
    std::vector<Image> views = {Image(kW, kH), Image(kW, kH)};
    auto& left = views[0].rgba;
    auto& right = views[1].rgba;
    for (int i = 0; i < kW * kH; ++i)
        for (int c = 0; c < 4; ++c) {
            left[i * 4 + c] = static_cast<std::uint8_t>(i * 7 + c * 91);
            right[i * 4 + c] = static_cast<std::uint8_t>(i * 13 + c * 37 + 5);
        }
    const AnaglyphMethod methods[] = {
        AnaglyphMethod::Color,          AnaglyphMethod::HalfColor,
        AnaglyphMethod::Gray,           AnaglyphMethod::True,
        AnaglyphMethod::Dubois,         AnaglyphMethod::DuboisGreenMagenta,
        AnaglyphMethod::DuboisAmberBlue};
    for (AnaglyphMethod method : methods) {
        Result<Image> composed = gl::composeGpu(std::string(anaglyphFormatName(method)), views);
        if (!composed && composed.status().code() == ErrorCode::Unsupported)
            MVR_SKIP(MethodUnsupportedByDriver) << composed.status().message();
        ASSERT_TRUE(composed) << composed.status().message();
        const auto& gpu = composed->rgba;
        ASSERT_EQ(gpu.size(), left.size());
        int worst = 0;
        for (int i = 0; i < kW * kH; ++i) {
            const Rgba8 cpu =
                anaglyphPixel(anaglyphMatrices(method),
                              {left[i * 4], left[i * 4 + 1], left[i * 4 + 2], left[i * 4 + 3]},
                              {right[i * 4], right[i * 4 + 1], right[i * 4 + 2], right[i * 4 + 3]});
            worst = std::max({worst, std::abs(cpu.r - gpu[i * 4]), std::abs(cpu.g - gpu[i * 4 + 1]),
                              std::abs(cpu.b - gpu[i * 4 + 2])});
        }
        // One step: float pow() of a GPU and of the CPU may round to the two sides of a code.
        EXPECT_LE(worst, 1) << "method " << static_cast<int>(method);
    }
}

}  // namespace
}  // namespace mvr::composite
