// mvr/core/shadows.h — shadow maps (issue 15): mono surfaces rendered ONCE per frame for all
// N views and sampled by every view (nvidia-gtc2010 "Stereo rendering surfaces": shadow maps
// are mono), and the shadow maps of several lights as ONE multi-view pass whose views are the
// lights (kalaiah2007 §3: "the lights are the views").
//
// Which lights cast: those with Light::castsShadow; when none is flagged, --shadows makes the
// key light (light 0, if directional) and every spot light cast (shadowCasters). Point lights
// cast none (they would need a cube map).
//
// The map of a light is an ordinary depth render through any Backend: a View per light
// (directional: orthographic, fitted to the scene bounds seen along the light; spot:
// perspective with the spot's outer cone) in an explicit view list (makeListRig), so K lights
// are one multi-view render (renderShadowSet) or K single-view renders (the bench compares).
// The window depths are turned into LINEAR distances along the light (ortho: near +
// d·(far − near); perspective: eye-space distance) once, rows bottom first (texel (x, y) is
// depth[y·size + x], GL texture order), so every backend samples the same numbers.
//
// Lookup (shadowFactor; the gl backend's GLSL mirrors it line by line): project the world
// point p with the light's clipFromWorld; outside the map's x/y/z range → lit (1). Else the
// receiver distance r (the same linear distance), and a 3×3 percentage-closer filter of
// nearest texels around the texel containing p (clamped to the map's edge): the factor is the
// fraction of the 9 texels whose stored distance ≥ r − bias.
// Bias (world units, on the receiver side so every backend applies the same one):
//     bias = texel · (kShadowBiasConstant + kShadowBiasSlope · min(tan θ, kShadowBiasMaxTan))
// θ the angle between the normal and the light direction, texel the world size of one map
// texel at p (ortho: extent / size; perspective: distance · 2·tan(fov/2) / size). The slope
// term: the 3×3 kernel compares p with surface samples up to 1.5 texels away (one texel of
// kernel radius + half a texel from p to its texel centre), where a plane tilted by θ differs
// in depth by 1.5 · texel · tan θ, hence 1.5. The constant 1 texel covers rasterization
// differences (sub-pixel snapping, float rounding of interpolated depth, a gl vs soft texel).
// tan θ is capped at 8 (grazing light: at most 13 texels of offset; the light's n·l → 0 there
// anyway, so the little peter-panning it causes is dim).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/core/status.h"

namespace mvr {

class Backend;
struct RenderSettings;

inline constexpr float kShadowBiasConstant = 1.0f;  ///< texels
inline constexpr float kShadowBiasSlope = 1.5f;     ///< texels per unit of tan θ
inline constexpr float kShadowBiasMaxTan = 8.0f;
inline constexpr int kShadowPcfRadius = 1;  ///< 3×3 kernel
inline constexpr int kDefaultShadowMapSize = 1024;

/// One light's shadow map.
struct ShadowMap {
    int light = -1;  ///< index into Scene::lights
    View view;       ///< the light as a view (its clipFromWorld projects into the map)
    glm::mat4 clipFromWorld{1.0f};
    bool perspective = false;
    float near = 0.0f, far = 1.0f;
    /// Ortho: the world size of one texel; perspective: a texel's size at distance 1.
    float texelWorld = 0.0f;
    int size = 0;
    std::vector<float> depth;  ///< linear distances, size × size, rows bottom first
};

/// The maps of one frame; mapOfLight[k] is the index in `maps` of light k's map, or −1.
struct ShadowSet {
    std::vector<ShadowMap> maps;
    std::array<int, kMaxLights> mapOfLight{-1, -1, -1, -1};
    bool empty() const { return maps.empty(); }
};

/// The lights of `scene` that cast shadows (see the header comment).
std::vector<int> shadowCasters(const Scene& scene);

/// The light's map: view and projection fitted to `bounds` (directional: orthographic, square
/// texels; spot: perspective over the outer cone, far through the farthest bounds corner), no
/// depth yet. Precondition: the light is directional or spot and bounds are not empty.
ShadowMap makeShadowMapView(const Light& light, int lightIndex, const Bounds& bounds, int size);

/// Fills `map.depth` from a rendered window-depth image (rows top first, as DepthImage).
void setShadowDepth(ShadowMap& map, std::span<const float> windowDepthTopFirst);

/// The list rig whose views are the maps' lights (one multi-view pass for all of them).
Result<Rig> shadowRig(std::span<const ShadowMap> maps);

/// The settings of a shadow pass: size × size, flat shading (color unused), no culling, no
/// shadows.
RenderSettings shadowPassSettings(int size);

/// The shadow maps of the scene's casters through `backend`/`method`: one multi-view render
/// whose views are the lights (onePass), or one render per light. Empty set when nothing casts.
/// Errors: the backend's, or a method that returns no depth images.
Result<ShadowSet> renderShadowSet(Backend& backend, const Scene& scene, int size,
                                  const std::string& method, bool onePass = true);

/// Light-space projection with a fixed operation order (as the soft pipeline's transformPoint).
inline glm::vec4 shadowProject(const glm::mat4& m, const glm::vec3& p) {
    glm::vec4 r;
    for (int i = 0; i < 4; ++i) r[i] = ((m[0][i] * p.x + m[1][i] * p.y) + m[2][i] * p.z) + m[3][i];
    return r;
}

/// The fraction of light `map`'s light reaching world point p (1 lit, 0 shadowed); n: unit
/// surface normal, l: unit direction toward the light at p.
inline float shadowFactor(const ShadowMap& map, const glm::vec3& p, const glm::vec3& n,
                          const glm::vec3& l) {
    const glm::vec4 c = shadowProject(map.clipFromWorld, p);
    if (!(c.w > 0.0f)) return 1.0f;
    const float iw = 1.0f / c.w;
    const float nx = c.x * iw, ny = c.y * iw, nz = c.z * iw;
    if (!(std::fabs(nx) <= 1.0f && std::fabs(ny) <= 1.0f && nz <= 1.0f)) return 1.0f;
    const float r = map.perspective ? c.w : map.near + (nz * 0.5f + 0.5f) * (map.far - map.near);
    const float fs = float(map.size);
    const int tx = std::clamp(int(std::floor((nx * 0.5f + 0.5f) * fs)), 0, map.size - 1);
    const int ty = std::clamp(int(std::floor((ny * 0.5f + 0.5f) * fs)), 0, map.size - 1);
    const float cosT = std::clamp(glm::dot(n, l), 1e-3f, 1.0f);
    const float tanT = std::min(std::sqrt(1.0f - cosT * cosT) / cosT, kShadowBiasMaxTan);
    const float texel = map.perspective ? map.texelWorld * r : map.texelWorld;
    const float ref = r - texel * (kShadowBiasConstant + kShadowBiasSlope * tanT);
    int lit = 0;
    for (int j = -kShadowPcfRadius; j <= kShadowPcfRadius; ++j) {
        const int y = std::clamp(ty + j, 0, map.size - 1);
        for (int i = -kShadowPcfRadius; i <= kShadowPcfRadius; ++i) {
            const int x = std::clamp(tx + i, 0, map.size - 1);
            lit += map.depth[std::size_t(y) * std::size_t(map.size) + std::size_t(x)] >= ref;
        }
    }
    constexpr int kTaps = (2 * kShadowPcfRadius + 1) * (2 * kShadowPcfRadius + 1);
    return float(lit) * (1.0f / float(kTaps));
}

/// Unit direction toward light `l` from p (directional: towardLight; spot/point: to position).
inline glm::vec3 directionToLight(const Light& l, const glm::vec3& p) {
    if (l.type == LightType::Directional) return l.towardLight;
    const glm::vec3 d = l.position - p;
    const float len = glm::length(d);
    return len > 0.0f ? d / len : l.towardLight;
}

/// out[k] = the shadow factor of light k at p (1 for lights without a map); returns `out`,
/// or nullptr (= every light lit) when `set` is null or empty. n need not be unit.
inline const float* shadowFactors(const ShadowSet* set, std::span<const Light> lights,
                                  const glm::vec3& p, const glm::vec3& n, float* out) {
    if (!set || set->empty()) return nullptr;
    const float len = glm::length(n);
    const glm::vec3 un = len > 0.0f ? n / len : n;
    for (std::size_t k = 0; k < lights.size() && k < std::size_t(kMaxLights); ++k) {
        const int m = set->mapOfLight[k];
        out[k] =
            m < 0 ? 1.0f
                  : shadowFactor(set->maps[std::size_t(m)], p, un, directionToLight(lights[k], p));
    }
    return out;
}

}  // namespace mvr
