// mvr/core/environment.h — image lighting (issue 39 item 2, `--environment MAP`): an
// environment map lights the scene as glTF viewers light it, with the split-sum approximation
// (Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes), every part computed
// ONCE per map, never per view or per frame:
//
//  - Diffuse: the map's irradiance as 9 spherical-harmonic coefficients (Ramamoorthi and
//    Hanrahan, "An Efficient Representation for Irradiance Environment Maps", SIGGRAPH 2001):
//    the radiance projected on the real SH basis up to l = 2 with each texel's solid angle,
//    convolved with the clamped cosine (Â_l / π = 1, 2/3, 1/4) and divided by π, so that
//    diffuseLight(n) is the light a white Lambertian surface of normal n shows (a uniform map of
//    radiance c gives c; a map lit in its upper half gives (1 + n.y) / 2, exactly: a step's
//    bands above 0 are odd and the cosine removes odd bands above 1). Clamped at 0 (ringing).
//  - Specular: the map prefiltered with the GGX lobe for kLevels roughnesses r_k = k /
//    (kLevels − 1), stored as a mip chain of equirectangular images (level k is level 0's size
//    halved k times; level 0, r = 0, is the map itself resampled). Each texel of level k ≥ 1
//    integrates the map around its direction R with N = V = R (the split sum's assumption),
//    kPrefilterSamples · 2^(k − 1) GGX importance samples (at most 1024; Hammersley points)
//    weighted by n·l, each read from the map's box-filtered chain at the level the sample's
//    solid angle covers, ½ log2(Ω_sample / Ω_texel) with the level-0 texel's solid angle at the
//    sample's latitude ("filtered importance sampling", Colbert and Křivánek, GPU Gems 3 ch.
//    20, without their +1 bias, which blurred a rough level's lobe measurably: the test holds
//    the levels to a quadrature of the lobe within 3 %).
//  - The BRDF's scale and bias (A, B) of F0 over (n·v, roughness): splitSumTable(), computed
//    once per process from the same V · D as lighting.h's metallicRoughnessSpecular, so
//    ∫ f · cos = F0 · A + B for the environment's light.
//
// Lookups, which every backend mirrors (the gl / vk GLSL line by line, GL sampler state for the
// filtering):
//  - equirectUv(d): the sky's layout (stereo_surfaces.h): u = 0.5 + atan2(d.x, −d.z) / 2π,
//    v = 0.5 − asin(d.y) / π (row 0 straight up).
//  - prefiltered(env, R, r): GL's textureLod(map, equirectUv(R), r · (kLevels − 1)) with
//    LINEAR_MIPMAP_LINEAR, REPEAT in u and CLAMP_TO_EDGE in v: bilinear at texel centres in
//    levels floor(λ) and floor(λ) + 1 (clamped), mixed by frac(λ).
//  - splitSum(n·v, r): GL's texture() of the kBrdfSize² table (u = n·v, v = r, row 0 = r 0),
//    bilinear, CLAMP_TO_EDGE.
// How the terms enter lighting.h's D / S split: lighting.h's header ("Image lighting").
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace mvr {

/// An environment map's radiance: linear RGB, equirectangular (width = 2 · height), row 0
/// straight up (as the sky's map; stereo_surfaces.h). What mvr::io's loadEnvironmentMap reads.
struct RadianceMap {
    int width = 0, height = 0;
    std::vector<glm::vec3> texels;  ///< width · height, row-major
    std::string name;               ///< the file (for messages)
    std::uint64_t contentHash = 0;  ///< FNV-1a of the file's bytes (0: not from a file)
};

/// The brightest radiance a map keeps (a texel above it reads it; buildEnvironment clamps the
/// scaled radiance too): every sum the build makes stays finite, and 16-bit float uploads
/// (65504 at most) are the only other limit (vk clamps there).
inline constexpr float kMaxRadiance = 1.0e8f;
/// The most texels an environment map may have (8192 × 4096).
inline constexpr std::size_t kMaxEnvironmentTexels = std::size_t(8192) * 4096;

/// A map prepared for lighting (see the header): built by buildEnvironment, shared by every
/// view, frame and backend of a render.
struct Environment {
    static constexpr int kLevels = 6;             ///< prefiltered roughnesses 0, 0.2, …, 1
    static constexpr int kMaxWidth = 512;         ///< level 0's width at most (a power of two)
    static constexpr int kPrefilterSamples = 64;  ///< GGX samples a level-1 texel (× 2 a level)
    /// One prefiltered level: linear RGB, a = 1 (RGBA for the GPUs' upload), row-major.
    struct Level {
        int width = 0, height = 0;
        std::vector<glm::vec4> texels;
    };
    /// The irradiance's SH coefficients, convolved and divided by π (diffuseLight), in the
    /// order (l, m) = (0, 0), (1, −1), (1, 0), (1, 1), (2, −2), (2, −1), (2, 0), (2, 1), (2, 2).
    std::array<glm::vec3, 9> sh{};
    std::array<Level, kLevels> levels;
    std::string name;  ///< the map's file
};

/// Builds the environment of `map` with its radiance scaled by `scale` (--exposure: 2^EV, as
/// the lights). Level 0 is the largest power of two ≤ min(map.width, kMaxWidth), at least 32,
/// by 2:1. Deterministic (the same bits on every run and thread count). Precondition: a 2:1
/// map of at least 2 × 1 texels with finite, non-negative texels (loadEnvironmentMap checks).
Environment buildEnvironment(const RadianceMap& map, float scale = 1.0f);

/// The split sum's (A, B) table: kBrdfSize × kBrdfSize, row j = roughness (j + ½) / kBrdfSize,
/// column i = n·v (i + ½) / kBrdfSize; 512 GGX samples each, the BRDF's V · D as
/// metallicRoughnessSpecular's (α = max(r², 1e-3)), Schlick's (1 − v·h)^5.
inline constexpr int kBrdfSize = 32;
const std::array<glm::vec2, kBrdfSize * kBrdfSize>& splitSumTable();

inline constexpr float kEnvPi = 3.14159265358979f;

/// The sky's equirectangular coordinates of a unit direction (see the header).
inline glm::vec2 equirectUv(glm::vec3 d) {
    // Straight up or down, longitude 0 (atan2(0, ±0) is ±π or 0 by zeros' signs; GLSL's atan
    // is undefined there).
    const float lon = d.x == 0.0f && d.z == 0.0f ? 0.0f : std::atan2(d.x, -d.z);
    const float lat = std::asin(std::clamp(d.y, -1.0f, 1.0f));
    return {0.5f + lon * (0.5f / kEnvPi), 0.5f - lat * (1.0f / kEnvPi)};
}

/// The unit direction at equirectangular coordinates (u, v): equirectUv's inverse.
inline glm::vec3 equirectDirection(float u, float v) {
    const float lon = (u - 0.5f) * 2.0f * kEnvPi, lat = (0.5f - v) * kEnvPi;
    const float c = std::cos(lat);
    return {c * std::sin(lon), std::sin(lat), -c * std::cos(lon)};
}

/// The light a white Lambertian surface of unit normal `n` shows (see the header), ≥ 0.
inline glm::vec3 diffuseLight(const Environment& env, glm::vec3 n) {
    const std::array<glm::vec3, 9>& c = env.sh;
    glm::vec3 e = c[0] * 0.282095f;
    e += (c[1] * n.y + c[2] * n.z + c[3] * n.x) * 0.488603f;
    e += (c[4] * (n.x * n.y) + c[5] * (n.y * n.z) + c[7] * (n.x * n.z)) * 1.092548f;
    e += c[6] * (0.315392f * (3.0f * n.z * n.z - 1.0f));
    e += c[8] * (0.546274f * (n.x * n.x - n.y * n.y));
    return glm::max(e, glm::vec3(0.0f));
}

/// A level's bilinear texel at (u, v) (REPEAT in u, CLAMP_TO_EDGE in v; texel centres).
inline glm::vec3 environmentBilinear(const Environment::Level& l, glm::vec2 uv) {
    const float x = uv.x * float(l.width) - 0.5f, y = uv.y * float(l.height) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    auto wrapX = [&](float i) {
        const int n = l.width;
        const int k = int(i) % n;  // i is within a few widths of 0
        return k < 0 ? k + n : k;
    };
    const int x0 = wrapX(fx), x1 = wrapX(fx + 1.0f);
    const int y0 = std::clamp(int(fy), 0, l.height - 1);
    const int y1 = std::clamp(int(fy) + 1, 0, l.height - 1);
    auto at = [&](int i, int j) {
        return glm::vec3(l.texels[std::size_t(j) * std::size_t(l.width) + std::size_t(i)]);
    };
    const glm::vec3 top = at(x0, y0) * (1.0f - ax) + at(x1, y0) * ax;
    const glm::vec3 bottom = at(x0, y1) * (1.0f - ax) + at(x1, y1) * ax;
    return top * (1.0f - ay) + bottom * ay;
}

/// The map prefiltered for `roughness` (clamped to [0, 1]) in unit direction `r` (see the
/// header).
inline glm::vec3 prefiltered(const Environment& env, glm::vec3 r, float roughness) {
    const glm::vec2 uv = equirectUv(r);
    const float lod = std::clamp(roughness, 0.0f, 1.0f) * float(Environment::kLevels - 1);
    const int l0 = std::min(int(lod), Environment::kLevels - 1);
    const int l1 = std::min(l0 + 1, Environment::kLevels - 1);
    const float t = lod - float(l0);
    const glm::vec3 a = environmentBilinear(env.levels[std::size_t(l0)], uv);
    if (t == 0.0f) return a;
    return a * (1.0f - t) + environmentBilinear(env.levels[std::size_t(l1)], uv) * t;
}

/// The split sum's (A, B) at n·v and roughness (see splitSumTable), bilinear, clamped.
inline glm::vec2 splitSum(float nv, float roughness) {
    const auto& t = splitSumTable();
    const float x = std::clamp(nv, 0.0f, 1.0f) * float(kBrdfSize) - 0.5f;
    const float y = std::clamp(roughness, 0.0f, 1.0f) * float(kBrdfSize) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = std::clamp(int(fx), 0, kBrdfSize - 1), x1 = std::clamp(int(fx) + 1, 0, kBrdfSize - 1);
    const int y0 = std::clamp(int(fy), 0, kBrdfSize - 1), y1 = std::clamp(int(fy) + 1, 0, kBrdfSize - 1);
    auto at = [&](int i, int j) { return t[std::size_t(j * kBrdfSize + i)]; };
    const glm::vec2 top = at(x0, y0) * (1.0f - ax) + at(x1, y0) * ax;
    const glm::vec2 bottom = at(x0, y1) * (1.0f - ax) + at(x1, y1) * ax;
    return top * (1.0f - ay) + bottom * ay;
}

/// Blinn-Phong's shininess s as a GGX roughness, for a Blinn-Phong material's reflection of the
/// environment: α² = 2 / (s + 2) (Walter et al. 2007's correspondence), r = √α.
inline float roughnessOfShininess(float s) {
    return std::sqrt(std::sqrt(2.0f / (std::max(s, 0.0f) + 2.0f)));
}

}  // namespace mvr
