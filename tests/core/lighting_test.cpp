// lighting.h: specularPow (the Blinn-Phong specular power every soft path uses) against std::pow.
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "mvr/core/lighting.h"

namespace mvr {
namespace {

struct PowError {
    double maxRel = 0.0;     ///< results ≥ 2^-24 (everything that can show in an 8-bit image)
    double maxRelAll = 0.0;  ///< every normal result
    double maxAbs = 0.0;     ///< every result (denormal and flushed results included)
};

/// Dense sweep: every `stride`-th float bit pattern in [0, 1] (the domain: a clamped cosine).
PowError sweep(float s, std::uint32_t stride) {
    PowError e;
    const std::uint32_t end = std::bit_cast<std::uint32_t>(1.0f);
    for (std::uint32_t b = 0; b <= end; b += stride) {
        const float x = std::bit_cast<float>(b);
        const double ref = std::pow(double(x), double(s));
        const double got = specularPow(x, s);
        const double abs = std::fabs(got - ref);
        e.maxAbs = std::max(e.maxAbs, abs);
        if (ref >= FLT_MIN) e.maxRelAll = std::max(e.maxRelAll, abs / ref);
        if (ref >= 0x1p-24) e.maxRel = std::max(e.maxRel, abs / ref);
    }
    return e;
}

TEST(Lighting, SpecularPowMatchesStdPow) {
    for (float s : {1.0f, 2.0f, 4.5f, 8.0f, 16.0f, 32.0f, 64.0f, 100.0f, 128.0f, 256.0f, 500.0f,
                    1000.0f, 0.5f}) {
        const PowError e = sweep(s, 251);
        // (not "s" + std::to_string(...) + ...: GCC 12 -Wrestrict false positive under -O2.)
        RecordProperty(fmt::format("s{}_maxRel", int(s)), std::to_string(e.maxRel));
        EXPECT_LT(e.maxRel, 1e-5) << "s " << s;
        EXPECT_LT(e.maxRelAll, 2e-5) << "s " << s;
        EXPECT_LT(e.maxAbs, 2e-6) << "s " << s;
        std::printf(
            "specularPow s=%-6g max rel error %.2e (results >= 2^-24), %.2e (normal results), max abs %.2e\n",
            double(s), e.maxRel, e.maxRelAll, e.maxAbs);
    }
}

TEST(Lighting, SpecularPowSpecialValues) {
    for (float s : {0.5f, 1.0f, 32.0f, 1000.0f}) {
        EXPECT_EQ(specularPow(0.0f, s), 0.0f);
        EXPECT_EQ(specularPow(-0.0f, s), 0.0f);
        EXPECT_EQ(specularPow(1.0f, s), 1.0f);
        EXPECT_TRUE(std::isnan(specularPow(std::numeric_limits<float>::quiet_NaN(), s)));
    }
    for (float x : {0.0f, 0x1p-149f, 0.3f, 1.0f}) EXPECT_EQ(specularPow(x, 0.0f), 1.0f) << x;
    EXPECT_EQ(specularPow(0.0f, -1.0f), std::numeric_limits<float>::infinity());
    // Denormal x: as accurate as normal x.
    for (float x : {0x1p-149f, 0x1.8p-140f, 0x1.fffffep-127f}) {
        EXPECT_NEAR(specularPow(x, 0.5f), std::pow(double(x), 0.5), 1e-5 * std::pow(double(x), 0.5))
            << x;
        EXPECT_EQ(specularPow(x, 32.0f), 0.0f);  // underflows, as std::pow
    }
    // x^1 is x to a few ulps, x^2 is x·x; large exponents underflow to exactly 0.
    for (float x : {0.25f, 0.5f, 0.9f, 0.999f}) {
        EXPECT_NEAR(specularPow(x, 1.0f), x, 4e-7 * x);
        EXPECT_NEAR(specularPow(x, 2.0f), x * x, 1e-6 * x * x);
    }
    EXPECT_EQ(specularPow(0.5f, 1000.0f), 0.0f);
    EXPECT_GT(specularPow(0.99f, 1000.0f), 0.0f);
}

}  // namespace
}  // namespace mvr
