// Image lighting's once-per-map work (mvr/core/environment.h): the SH irradiance, the GGX
// prefiltered chain and the split sum's table.
#include "mvr/core/environment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "parallel.h"

namespace mvr {
namespace {

/// The i-th of n Hammersley points: (i / n, the radical inverse of i in base 2).
glm::vec2 hammersley(std::uint32_t i, std::uint32_t n) {
    std::uint32_t b = i;
    b = (b << 16u) | (b >> 16u);
    b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
    b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
    b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
    b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
    return {float(i) / float(n), float(double(b) * 0x1p-32)};
}

/// A GGX half vector about +Z for the sample ξ (α: GGX's α).
glm::vec3 ggxHalfVector(glm::vec2 xi, float alpha) {
    const float a2 = alpha * alpha;
    const float phi = 2.0f * kEnvPi * xi.x;
    const float cosTheta = std::sqrt((1.0f - xi.y) / (1.0f + (a2 - 1.0f) * xi.y));
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta};
}

/// An orthonormal frame (t, b, n) about unit n.
void frameOf(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const glm::vec3 up = std::abs(n.y) < 0.999f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    t = glm::normalize(glm::cross(up, n));
    b = glm::cross(n, t);
}

/// The unit direction through texel (i, j)'s centre of a w × h equirectangular image.
glm::vec3 texelDirection(int i, int j, int w, int h) {
    return equirectDirection((float(i) + 0.5f) / float(w), (float(j) + 0.5f) / float(h));
}

/// body(row) for rows [0, rows) on the machine's cores, or on this thread for 16 rows or fewer
/// (a small level: starting threads would cost more than it saves).
void parallelRows(int rows, const std::function<void(int)>& body) {
    detail::parallelFor(rows, rows > 16, body);
}

using Level = Environment::Level;

/// `map` resampled to w × h (a box of bilinear samples, ⌈map.width / w⌉² a texel), × scale.
Level resample(const RadianceMap& map, int w, int h, float scale) {
    Level src;
    src.width = map.width, src.height = map.height;
    src.texels.resize(map.texels.size());
    for (std::size_t k = 0; k < map.texels.size(); ++k)
        src.texels[k] = glm::vec4(glm::min(map.texels[k] * scale, glm::vec3(kMaxRadiance)), 1.0f);
    Level out;
    out.width = w, out.height = h;
    out.texels.resize(std::size_t(w) * std::size_t(h));
    const int ss = std::max(1, (map.width + w - 1) / w);
    parallelRows(h, [&](int j) {
        for (int i = 0; i < w; ++i) {
            glm::vec3 sum(0.0f);
            for (int b = 0; b < ss; ++b) {
                for (int a = 0; a < ss; ++a) {
                    const glm::vec2 uv((float(i) + (float(a) + 0.5f) / float(ss)) / float(w),
                                       (float(j) + (float(b) + 0.5f) / float(ss)) / float(h));
                    sum += environmentBilinear(src, uv);
                }
            }
            out.texels[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                glm::vec4(sum / float(ss * ss), 1.0f);
        }
    });
    return out;
}

/// The 2×2 box average of `l` (half its size, at least 1 × 1).
Level halve(const Level& l) {
    Level out;
    out.width = std::max(1, l.width / 2), out.height = std::max(1, l.height / 2);
    out.texels.resize(std::size_t(out.width) * std::size_t(out.height));
    for (int j = 0; j < out.height; ++j) {
        for (int i = 0; i < out.width; ++i) {
            glm::vec4 s(0.0f);
            for (int b = 0; b < 2; ++b) {
                for (int a = 0; a < 2; ++a) {
                    const int x = std::min(2 * i + a, l.width - 1);
                    const int y = std::min(2 * j + b, l.height - 1);
                    s += l.texels[std::size_t(y) * std::size_t(l.width) + std::size_t(x)];
                }
            }
            out.texels[std::size_t(j) * std::size_t(out.width) + std::size_t(i)] = s * 0.25f;
        }
    }
    return out;
}

/// Trilinear in a box-filtered chain at level of detail `lod`.
glm::vec3 chainSample(const std::vector<Level>& chain, glm::vec3 d, float lod) {
    const glm::vec2 uv = equirectUv(d);
    const float top = float(chain.size() - 1);
    lod = std::clamp(lod, 0.0f, top);
    const int l0 = int(lod);
    const int l1 = std::min(l0 + 1, int(chain.size()) - 1);
    const float t = lod - float(l0);
    const glm::vec3 a = environmentBilinear(chain[std::size_t(l0)], uv);
    return t == 0.0f ? a : a * (1.0f - t) + environmentBilinear(chain[std::size_t(l1)], uv) * t;
}

/// GGX's D at α² and n·h: α² / (π ((n·h)² (α² − 1) + 1)²).
float ggxD(float a2, float nh) {
    const float d = nh * nh * (a2 - 1.0f) + 1.0f;
    return a2 / (kEnvPi * d * d);
}

}  // namespace

Environment buildEnvironment(const RadianceMap& map, float scale) {
    Environment env;
    env.name = map.name;
    int w = 32;
    while (w * 2 <= std::min(map.width, Environment::kMaxWidth)) w *= 2;
    const int h = w / 2;
    env.levels[0] = resample(map, w, h, scale);

    // Diffuse: SH projection with each texel's solid angle (2π / w)(π / h) cos(lat).
    std::array<glm::dvec3, 9> acc{};
    const Level& base = env.levels[0];
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            const glm::vec3 d = texelDirection(i, j, w, h);
            const double lat = (0.5 - (j + 0.5) / h) * 3.14159265358979323846;
            const double dOmega = (2.0 * 3.14159265358979323846 / w) *
                                  (3.14159265358979323846 / h) * std::cos(lat);
            const glm::dvec3 c =
                glm::dvec3(glm::vec3(base.texels[std::size_t(j) * std::size_t(w) + std::size_t(i)])) *
                dOmega;
            const double y[9] = {0.282095,
                                 0.488603 * d.y,
                                 0.488603 * d.z,
                                 0.488603 * d.x,
                                 1.092548 * d.x * d.y,
                                 1.092548 * d.y * d.z,
                                 0.315392 * (3.0 * d.z * d.z - 1.0),
                                 1.092548 * d.x * d.z,
                                 0.546274 * (d.x * d.x - d.y * d.y)};
            for (int k = 0; k < 9; ++k) acc[std::size_t(k)] += c * y[k];
        }
    }
    const double band[9] = {1.0, 2.0 / 3, 2.0 / 3, 2.0 / 3, 0.25, 0.25, 0.25, 0.25, 0.25};
    for (int k = 0; k < 9; ++k) env.sh[std::size_t(k)] = glm::vec3(acc[std::size_t(k)] * band[k]);

    // Specular: the box chain of level 0, then GGX filtered importance sampling per level.
    std::vector<Level> chain{base};
    while (chain.back().width > 2) chain.push_back(halve(chain.back()));
    // A level-0 texel's solid angle at the equator (cos(lat) times it elsewhere).
    const float texelOmega = (2.0f * kEnvPi / float(w)) * (kEnvPi / float(h));
    for (int k = 1; k < Environment::kLevels; ++k) {
        // More samples for the rougher, smaller levels: the same work a level, finer lobes.
        const int n = std::min(Environment::kPrefilterSamples << (k - 1), 1024);
        const float r = float(k) / float(Environment::kLevels - 1);
        const float alpha = std::max(r * r, 1e-3f), a2 = alpha * alpha;
        Level& out = env.levels[std::size_t(k)];
        out.width = std::max(1, w >> k), out.height = std::max(1, h >> k);
        out.texels.resize(std::size_t(out.width) * std::size_t(out.height));
        parallelRows(out.height, [&](int j) {
            for (int i = 0; i < out.width; ++i) {
                const glm::vec3 nrm = texelDirection(i, j, out.width, out.height);
                glm::vec3 t, b;
                frameOf(nrm, t, b);
                glm::vec3 sum(0.0f);
                float weight = 0.0f;
                for (int s = 0; s < n; ++s) {
                    const glm::vec3 hz = ggxHalfVector(hammersley(std::uint32_t(s), std::uint32_t(n)), alpha);
                    const glm::vec3 hv = t * hz.x + b * hz.y + nrm * hz.z;
                    const float vh = glm::dot(nrm, hv);
                    const glm::vec3 l = hv * (2.0f * vh) - nrm;
                    const float nl = glm::dot(nrm, l);
                    if (!(nl > 0.0f)) continue;
                    // pdf of l = D · n·h / (4 v·h), n = v: D / 4.
                    const float pdf = ggxD(a2, hz.z) * 0.25f;
                    const float sampleOmega = 1.0f / (float(n) * pdf + 1e-6f);
                    const glm::vec3 ln = glm::normalize(l);
                    const float cosLat = std::sqrt(std::max(1.0f - ln.y * ln.y, 1e-6f));
                    const float lod = 0.5f * std::log2(sampleOmega / (texelOmega * cosLat));
                    sum += chainSample(chain, ln, lod) * nl;
                    weight += nl;
                }
                out.texels[std::size_t(j) * std::size_t(out.width) + std::size_t(i)] =
                    glm::vec4(weight > 0.0f ? sum / weight : glm::vec3(0.0f), 1.0f);
            }
        });
    }
    return env;
}

const std::array<glm::vec2, kBrdfSize * kBrdfSize>& splitSumTable() {
    static const std::array<glm::vec2, kBrdfSize * kBrdfSize> table = [] {
        std::array<glm::vec2, kBrdfSize * kBrdfSize> out{};
        constexpr int kSamples = 512;
        for (int j = 0; j < kBrdfSize; ++j) {
            const float r = (float(j) + 0.5f) / float(kBrdfSize);
            const float alpha = std::max(r * r, 1e-3f), a2 = alpha * alpha;
            for (int i = 0; i < kBrdfSize; ++i) {
                const float nv = (float(i) + 0.5f) / float(kBrdfSize);
                const glm::vec3 v(std::sqrt(1.0f - nv * nv), 0.0f, nv);
                double a = 0.0, b = 0.0;
                for (int s = 0; s < kSamples; ++s) {
                    const glm::vec3 hv =
                        ggxHalfVector(hammersley(std::uint32_t(s), kSamples), alpha);
                    const float vh = glm::dot(v, hv);
                    const glm::vec3 l = hv * (2.0f * vh) - v;
                    const float nl = l.z, nh = hv.z;
                    if (!(nl > 0.0f) || !(vh > 0.0f)) continue;
                    // f · cos / pdf with pdf = D n·h / (4 v·h): 4 V n·l v·h / n·h, V the
                    // separable Smith term of lighting.h's metallicRoughnessSpecular.
                    const float gl = nl + std::sqrt(a2 + (1.0f - a2) * nl * nl);
                    const float gv = nv + std::sqrt(a2 + (1.0f - a2) * nv * nv);
                    const double g = 4.0 * nl * vh / (double(gl) * gv * nh);
                    const double fc = std::pow(1.0 - vh, 5.0);
                    a += (1.0 - fc) * g;
                    b += fc * g;
                }
                out[std::size_t(j * kBrdfSize + i)] =
                    glm::vec2(float(a / kSamples), float(b / kSamples));
            }
        }
        return out;
    }();
    return table;
}

}  // namespace mvr
