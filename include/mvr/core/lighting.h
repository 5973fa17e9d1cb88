// mvr/core/lighting.h — the one shading model every backend implements (the soft backend
// calls these functions; the gl backend's GLSL mirrors them line by line), so that images
// from different backends and methods are comparable.
//
// Shading modes, after sorbier2008 Table 1:
//   Flat   — one color per triangle: ambient + Σ lights diffuse (Lambert) with the face
//            normal (normalize(cross(p1 - p0, p2 - p0)) in world space). No specular.
//   Vertex — Blinn-Phong evaluated at each vertex (smooth normal), colors interpolated
//            perspective-correctly ("vertex lighting", Gouraud).
//   Pixel  — the same Blinn-Phong evaluated per fragment with the interpolated, renormalized
//            normal and world position ("shader lighting").
// The view vector for the specular term points from the surface to the rig's CENTER eye
// (Rig::centerEye), not to each view's eye: shading is view-independent, so it can be done
// once for all views (kalaiah2007's view-independent attributes) and every method, single
// pass or multipass, produces the same colors.
// Output is linear [0, 1] per channel, clamped, alpha 1; quantized to 8 bits as
// uint8(clamp(c, 0, 1) * 255 + 0.5).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "mvr/core/scene.h"

namespace mvr {

struct ShadowSet;  // shadows.h

enum class Shading { Flat, Vertex, Pixel };

/// Everything shading needs that does not depend on the view.
struct ShadingContext {
    std::span<const DirectionalLight> lights;
    glm::vec3 ambient{0.12f};
    glm::vec3 centerEye{0.0f};           ///< world-space eye used for the specular view vector
    const ShadowSet* shadows = nullptr;  ///< issue 15: shadow maps, or none (every light lit)
};

/// Constants of specularPow (shared with the soft backend's SIMD kernels, which evaluate the
/// same operations lane by lane).
namespace pow_detail {
/// √½ as float bits: the mantissa m of x = 2^e·m is reduced to [√½, √2).
inline constexpr std::int32_t kSqrtHalfBits = 0x3f3504f3;
/// log2(1 + f) ≈ f · P(f), f ∈ [√½ − 1, √2 − 1]: P's coefficients c0..c8 (near-minimax,
/// relative error 5e-8 before float rounding).
inline constexpr float kLog2[9] = {0x1.715476p+0f,  -0x1.715474p-1f, 0x1.ec73dep-2f,
                                   -0x1.715994p-2f, 0x1.26d01cp-2f,  -0x1.e9d1e6p-3f,
                                   0x1.ba8738p-3f,  -0x1.a59aeap-3f, 0x1.f841dcp-4f};
/// 2^r ≈ 1 + r · Q(r), r ∈ [−½, ½]: Q's coefficients d0..d5.
inline constexpr float kExp2[6] = {0x1.62e430p-1f, 0x1.ebfbe0p-3f,  0x1.c6af6cp-5f,
                                   0x1.3b2a54p-7f, 0x1.5f0890p-10f, 0x1.44138ap-13f};
/// y = s·log2(x) is clamped to [−kYMax, kYMax] (2^±160 under/overflows float; NaN → −kYMax).
inline constexpr float kYMax = 160.0f;
/// 1.5·2^23: (y + kRound) − kRound rounds |y| < 2^22 to the nearest integer (ties to even).
inline constexpr float kRound = 0x1.8p23f;
/// pow(0, s): 0 for s > 0, 1 for s = 0, +inf for s < 0 (as std::pow).
inline float powOfZero(float s) { return s > 0.0f ? 0.0f : s == 0.0f ? 1.0f : HUGE_VALF; }
}  // namespace pow_detail

/// x^s for x ≥ 0 — the specular power of shadeBlinnPhong, as exp2(s · log2(x)) with fixed float
/// operations (no libm call), so that the soft backend's AVX2 / AVX-512 kernels compute the very
/// same bits 8 / 16 lanes at a time (simd/kernels_*.cpp mirror this function operation for
/// operation; keep them in sync). Relative error vs std::pow: see tests/core/lighting_test.cpp
/// (≈ 1e-6 for results ≥ 2^-24, grows as |s·log2 x| · 1e-7 toward the bottom of the float range).
/// Exact: pow(x, 0) = 1, pow(1, s) = 1, pow(0, s) = std::pow(0, s); denormal x, denormal and
/// zero results handled; NaN x → NaN, x = +inf → NaN (not +inf: x is a clamped cosine here).
inline float specularPow(float x, float s) {
    using namespace pow_detail;
    // log2(x) = e + log2(m), m ∈ [√½, √2); a denormal (or zero) x is scaled by 2^23 first.
    const bool tiny = x < 0x1p-126f;
    const float xs = tiny ? x * 0x1p23f : x;
    // The subtraction wraps in uint32 (the same bits; as int32 it overflowed for x = -0.0,
    // which UBSan reports: tests/core/lighting_test.cpp SpecularPowSpecialValues).
    const std::int32_t t = std::bit_cast<std::int32_t>(std::bit_cast<std::uint32_t>(xs) -
                                                       std::uint32_t(kSqrtHalfBits));
    const std::int32_t e = (t >> 23) - (tiny ? 23 : 0);
    const float f = std::bit_cast<float>((t & 0x007fffff) + kSqrtHalfBits) - 1.0f;  // exact
    float p = kLog2[8];
    for (int k = 7; k >= 0; --k) p = p * f + kLog2[k];
    const float l = float(e) + f * p;
    // 2^y = 2^n · 2^r, n = round(y), r = y − n ∈ [−½, ½] (exact).
    float y = s * l;
    y = -kYMax < y ? y : -kYMax;
    y = y < kYMax ? y : kYMax;
    const float nf = (y + kRound) - kRound;
    const float r = y - nf;
    float q = kExp2[5];
    for (int k = 4; k >= 0; --k) q = q * r + kExp2[k];
    const float m = 1.0f + r * q;
    // m · 2^n in two exact-or-once-rounded steps: 2^a, 2^b normal for |n| ≤ 160.
    const std::int32_t n = std::int32_t(nf);
    const std::int32_t a = n >> 1, b = n - a;
    float res = (m * std::bit_cast<float>((a + 127) << 23)) * std::bit_cast<float>((b + 127) << 23);
    res = x == 0.0f ? powOfZero(s) : res;
    return res + (x - x);  // + 0, or NaN for x = NaN / inf
}

/// Flat: ambient + Σ max(dot(n, l), 0) · albedo · lightColor. `faceNormal` unit, world space.
/// `shadow` (issue 15): per light, the factor (shadows.h) multiplying its term; null = lit.
inline glm::vec3 shadeFlat(const ShadingContext& ctx, const Material& m, glm::vec3 faceNormal,
                           const float* shadow = nullptr) {
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        const float s = shadow ? shadow[&l - ctx.lights.data()] : 1.0f;
        c += (std::max(glm::dot(faceNormal, l.towardLight), 0.0f) * m.albedo * l.color) * s;
    }
    return glm::clamp(c, 0.0f, 1.0f);
}

/// Blinn-Phong: ambient + Σ [max(n·l, 0) · albedo + specular · max(n·h, 0)^shininess (only
/// where n·l > 0)] · lightColor, with h = normalize(l + v), v = normalize(centerEye − p).
/// `normal` need not be unit (it is normalized here). `shadow` (issue 15): per light, the
/// factor (shadows.h) multiplying its diffuse + specular; null = lit.
inline glm::vec3 shadeBlinnPhong(const ShadingContext& ctx, const Material& m, glm::vec3 normal,
                                 glm::vec3 worldPos, const float* shadow = nullptr) {
    const glm::vec3 n = glm::normalize(normal);
    const glm::vec3 v = glm::normalize(ctx.centerEye - worldPos);
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        const float nl = glm::dot(n, l.towardLight);
        if (nl > 0.0f) {
            const glm::vec3 h = glm::normalize(l.towardLight + v);
            const float spec =
                m.specular * specularPow(std::max(glm::dot(n, h), 0.0f), m.shininess);
            const float s = shadow ? shadow[&l - ctx.lights.data()] : 1.0f;
            c += ((nl * m.albedo + glm::vec3(spec)) * l.color) * s;
        }
    }
    return glm::clamp(c, 0.0f, 1.0f);
}

inline std::uint8_t quantizeUnorm8(float c) {
    return static_cast<std::uint8_t>(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f);
}

}  // namespace mvr
