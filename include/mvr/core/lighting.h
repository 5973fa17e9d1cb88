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
// pass or multipass, produces the same colors. RenderSettings::specular PerView (SpecularEye,
// `--specular per-view`) sets centerEye to each view's own eye, per pixel, instead.
// Output is linear [0, 1] per channel, clamped, alpha 1; quantized to 8 bits as
// uint8(clamp(c, 0, 1) * 255 + 0.5).
//
// Lights (issue 14, glTF KHR_lights_punctual semantics): a directional light shines along
// −towardLight with no falloff (the functions below are bit for bit what they were before point
// and spot lights). Point and spot lights: l = normalize(position − p), scaled by
//   range attenuation  max(min(1 − (d / range)^4, 1), 0) / d²   (range > 0; 1 / d² when range
//                      = 0, i.e. infinite), d = ‖position − p‖, d² at least 1e-8 — the formula
//                      KHR_lights_punctual's README recommends ("Range Property");
//   spot attenuation   t = saturate(cd · scale + offset), t², with cd = dot(−towardLight, −l)
//                      (the cosine between the spot axis and the direction to p), scale =
//                      1 / max(0.001, innerConeCos − outerConeCos), offset = −outerConeCos ·
//                      scale — the spec's reference implementation ("Inner and Outer Cone
//                      Angles"); 0 outside the outer cone, 1 inside the inner one, a squared
//                      ramp between (the spec's choice; not GLSL smoothstep).
// Flat shading evaluates point / spot lights at the triangle's CENTROID (world space, the mean
// of its three vertices): one position per triangle, like its one normal.
//
// Textures (issue 14): the base color is albedo × texel (texel: texture_sampling.h's linear RGBA)
// and it multiplies the DIFFUSE and ambient terms only (specular stays white), i.e. the
// textured color is clamp(base ⊙ D + S) with LightTerms D (ambient + Σ att·max(n·l, 0)·color)
// and S (Σ att·specular·max(n·h, 0)^shininess·color, Blinn-Phong only). Flat: D from the face
// normal at the centroid, per triangle, S = 0. Vertex: D and S at each vertex, interpolated
// perspective-correctly, combined with the texel per fragment. Pixel: D and S per fragment.
// Alpha = material.alpha × texel alpha: AlphaMode::Mask discards alpha < alphaCutoff (the
// fragment writes neither color nor depth); Blend: color = src·alpha + dst·(1 − alpha) over
// the framebuffer's value, depth tested but not written; blended instances are drawn after
// all others, in instance order, unsorted (the backends' draw order).
//
// Material models (issue 39, Material::model): everything above is MaterialModel::BlinnPhong.
// MetallicRoughness is glTF 2.0's BRDF as its specification's Appendix B writes it, in the same
// D / S split (so textures and vertex colours combine with it as above): per light with n·l > 0,
// h = normalize(l + v), α = max(roughness², 1e-3) (a mirror's delta is a 0/0), w = (1 − v·h)^5,
//   specular_brdf = V · D,  D = α² / (π ((n·h)² (α² − 1) + 1)²),
//                   V = 1 / ((n·l + √(α² + (1 − α²)(n·l)²)) (|n·v| + √(α² + (1 − α²)(n·v)²))),
//   dielectric    = mix(base / π, specular_brdf, f),  f = 0.04 + 0.96 w,
//   metal         = specular_brdf · (base + (1 − base) w),
//   f(l, v)       = mix(dielectric, metal, metallic),
// which is affine in base: D += π · n·l · lc · ((1 − m)(1 − f)/π + m · V·D · (1 − w)) and
// S += π · n·l · lc · V·D · ((1 − m) f + m w) (lc: the light's colour × attenuation × shadow).
// The factor π is mvr's light convention: a light's colour is the irradiance it gives at normal
// incidence over π, so a white Lambertian surface facing a light of colour 1 is 1 in either
// model, and a glTF file and an OBJ of the same lights are equally bright. The ambient term is
// ambient · base, as Blinn-Phong's; emissive (Material::emissive) is added to S once. v is the
// centre eye's, as for Blinn-Phong: computed once for all views. Flat shading stays Lambert of
// the base colour (no specular) for Blinn-Phong and metallic-roughness alike, plus the
// emissive (flatSpecular). Unlit: D = 1, S = 0 (the base colour), in every shading.
//
// Texture maps (issue 39; Material's metallicRoughnessTexture, occlusionTexture,
// emissiveTexture, normalTexture, SurfaceMaps): sampled with the material's one set of texture
// coordinates (Mesh::texcoords) and its sampler; the metallic-roughness texel scales the
// factors of the BRDF evaluated per pixel (metallicRoughnessTerms' `maps`; vertex and flat
// shading evaluate the factors alone), the occlusion scales the ambient term and the emissive
// texel the emissive, in every shading (applySurfaceMaps); the normal map bends
// the interpolated normal per pixel (perturbedNormal, with Mesh::tangents), before lighting.
//
// Image lighting (issue 39 item 2, ShadingContext::environment from Scene::environment;
// environment.h computes its parts once per map): the environment adds to D and S, after the
// lights, in the split sum's form (environmentTerms), with n the lit normal (double-sided flip
// and normal map applied), v the shading eye's, R = 2 (n·v) n − v (signed n·v), E =
// diffuseLight(n), P = prefiltered(R, roughness), (A, B) = splitSum(|n·v|, roughness), Fd =
// 0.04 A + B (a dielectric's Fresnel over the lobe) and o the occlusion (SurfaceMaps::occlusion, 1
// without a map; glTF's occlusion acts on this indirect light):
//   metallic-roughness  D += o ((1 − m)(1 − Fd) E + m A P),  S += o P ((1 − m) Fd + m B)
//                       (the glTF sample viewer's mix(diffuse, specular, Fd) for the dielectric
//                       and P (base A + B) for the metal, mixed by metallic m, affine in base);
//   Blinn-Phong         D += o E,  S += o · specular · Fd · P with roughness
//                       roughnessOfShininess(shininess);
//   flat                D += E(face normal) (no specular, no occlusion: the map is per pixel
//                       and flat's D per triangle); unlit: nothing.
// Vertex shading evaluates it per vertex like the rest (once for all views). The constant
// ambient stays as it is; the session sets it to 0 under --environment (the map is the
// ambient light).
//
// Tone mapping (issue 39 item 2; ShadingContext::tonemap, from Scene::tonemap): finishColor() is
// the last step of every lit colour, where the clamp to [0, 1] was: Khronos PBR Neutral or ACES
// (Narkowicz's fit), then the clamp; Tonemap::None is the clamp alone (the same bits as before).
// Where the clamp was is where it is: per vertex for untextured vertex shading (the colours
// are interpolated after), per fragment for textured (base ⊙ D + S) and pixel shading, before
// blending.
// Double-sided materials (Material::doubleSided): never back-face culled; the normal used for
// lighting is flipped when it faces away from the rig's CENTER eye (facingNormal) — a
// view-independent rule like the rest of shading, so vertex lighting is still done once for
// all views (with --specular per-view, pixel shading, each view's own eye: ctx.centerEye). Single-sided materials keep their normal (back faces are only drawn when culling
// is off).
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "mvr/core/environment.h"
#include "mvr/core/scene.h"

namespace mvr {

struct ShadowSet;  // shadows.h

enum class Shading { Flat, Vertex, Pixel };

/// Whose eye shading looks from (issue 39, `--specular`): Center, the rig's centre eye for every
/// view (the default: shading is view-independent, computed once for all views); PerView, each
/// view's own eye (View::eyeWorld) as ShadingContext::centerEye, so highlights and the
/// double-sided flip move between views as they do on a real surface. PerView is per pixel
/// (shadedSettings); flat shading has no highlight and keeps the centre eye's flip.
enum class SpecularEye { Center, PerView };

/// Everything shading needs that does not depend on the view.
struct ShadingContext {
    std::span<const DirectionalLight> lights;
    glm::vec3 ambient{0.12f};
    glm::vec3 centerEye{0.0f};           ///< world-space eye used for the specular view vector
    const ShadowSet* shadows = nullptr;  ///< issue 15: shadow maps, or none (every light lit)
    Tonemap tonemap = Tonemap::None;     ///< Scene::tonemap (finishColor)
    const Environment* environment = nullptr;  ///< Scene::environment (image lighting), or none
};

/// Khronos PBR Neutral (the KhronosGroup/ToneMapping specification's reference function):
/// linear in, linear [0, 1] out; colours whose peak is below 0.76 only lose the small offset.
inline glm::vec3 khrPbrNeutral(glm::vec3 c) {
    constexpr float kStart = 0.8f - 0.04f, kDesaturation = 0.15f;
    const float x = std::min(c.x, std::min(c.y, c.z));
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    c -= offset;
    const float peak = std::max(c.x, std::max(c.y, c.z));
    if (peak < kStart) return c;
    constexpr float d = 1.0f - kStart;
    const float newPeak = 1.0f - d * d / (peak + d - kStart);
    c *= newPeak / peak;
    const float g = 1.0f - 1.0f / (kDesaturation * (peak - newPeak) + 1.0f);
    return glm::mix(c, glm::vec3(newPeak), g);
}

/// ACES filmic, Narkowicz's fit of the RRT + ODT (2016): x (2.51 x + 0.03) / (x (2.43 x +
/// 0.59) + 0.14), per channel, x ≥ 0.
inline glm::vec3 acesNarkowicz(glm::vec3 c) {
    c = glm::max(c, glm::vec3(0.0f));
    return (c * (2.51f * c + 0.03f)) / (c * (2.43f * c + 0.59f) + 0.14f);
}

/// The last step of every lit colour: tone mapped (ctx.tonemap), then clamped to [0, 1]. With
/// Tonemap::None, the clamp alone (the pixels of before tone mapping, bit for bit).
inline glm::vec3 finishColor(const ShadingContext& ctx, glm::vec3 c) {
    if (ctx.tonemap == Tonemap::KhrNeutral) c = khrPbrNeutral(c);
    else if (ctx.tonemap == Tonemap::Aces) c = acesNarkowicz(c);
    return glm::clamp(c, 0.0f, 1.0f);
}

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

/// Direction toward a light from `worldPos` and the light's attenuation there (1 for
/// directional lights; range × spot attenuation for point / spot lights, see the header).
struct LightSample {
    glm::vec3 toLight{0.0f, 0.0f, 1.0f};  ///< unit
    float attenuation = 1.0f;
};

/// KHR_lights_punctual's recommended range falloff: max(min(1 − (d/range)^4, 1), 0) / d²;
/// 1 / d² for range ≤ 0 (infinite). d² is taken at least 1e-8.
inline float rangeAttenuation(float distance2, float range) {
    const float d2 = std::max(distance2, 1e-8f);
    if (!(range > 0.0f)) return 1.0f / d2;
    const float r = d2 / (range * range);  // (d / range)²
    const float f = std::clamp(1.0f - r * r, 0.0f, 1.0f);
    return f / d2;
}

/// KHR_lights_punctual's spot cone falloff: saturate(cd · scale + offset)², scale = 1 /
/// max(0.001, innerCos − outerCos), offset = −outerCos · scale; cd = cos(angle to the axis).
inline float spotAttenuation(float cd, float innerConeCos, float outerConeCos) {
    const float scale = 1.0f / std::max(0.001f, innerConeCos - outerConeCos);
    const float offset = -outerConeCos * scale;
    const float t = std::clamp(cd * scale + offset, 0.0f, 1.0f);
    return t * t;
}

inline LightSample lightAt(const Light& l, glm::vec3 worldPos) {
    LightSample s;
    if (l.type == LightType::Directional) {
        s.toLight = l.towardLight;
        return s;
    }
    const glm::vec3 d = l.position - worldPos;
    const float d2 = glm::dot(d, d);
    s.toLight = d2 > 0.0f ? d / std::sqrt(d2) : l.towardLight;
    s.attenuation = rangeAttenuation(d2, l.range);
    if (l.type == LightType::Spot) {
        // the spot axis is −towardLight; the direction from the light to p is −toLight
        s.attenuation *=
            spotAttenuation(glm::dot(l.towardLight, s.toLight), l.innerConeCos, l.outerConeCos);
    }
    return s;
}

/// The normal lighting uses: `n` itself, or −n for a double-sided material when n faces away
/// from the shading eye (dot(n, centerEye − p) < 0: the rig's centre eye, or the view's own
/// with --specular per-view). `n` need not be unit.
inline glm::vec3 facingNormal(const ShadingContext& ctx, const Material& m, glm::vec3 n,
                              glm::vec3 worldPos) {
    if (m.doubleSided && glm::dot(n, ctx.centerEye - worldPos) < 0.0f) return -n;
    return n;
}

/// Light `l`'s shadow factor (issue 15, shadows.h) in the per-light array `shadow` (indexed like
/// ctx.lights); 1 (lit) when `shadow` is null.
inline float shadowFactor(const ShadingContext& ctx, const DirectionalLight& l,
                          const float* shadow) {
    return shadow ? shadow[&l - ctx.lights.data()] : 1.0f;
}

/// The lighting of a textured surface before its base color is known: `diffuse` D multiplies
/// the base color (albedo × texel), `specular` S is added (see the header). Not clamped.
struct LightTerms {
    glm::vec3 diffuse{0.0f};
    glm::vec3 specular{0.0f};
};

/// What a material's texture slots beyond the base colour give one fragment (issue 39,
/// glTF 2.0's material definitions): the metallic-roughness texel's G (roughness) and B
/// (metallic), the occlusion = 1 + strength · (R − 1) of the occlusion texel, the emissive
/// texel (linear). The defaults are an absent slot's: they change nothing.
struct SurfaceMaps {
    float roughness = 1.0f, metallic = 1.0f;  ///< multiply the material's factors
    float occlusion = 1.0f;
    glm::vec3 emissive{1.0f};  ///< multiplies Material::emissive
};

/// glTF 2.0 Appendix B's specular_brdf times π (V · D · π, the light convention of the header):
/// α = max(roughness², 1e-3); nl > 0; nv is |n·v|.
inline float metallicRoughnessSpecular(float alpha, float nh, float nl, float nv) {
    const float a2 = alpha * alpha;
    const float d = nh * nh * (a2 - 1.0f) + 1.0f;
    const float gl = nl + std::sqrt(a2 + (1.0f - a2) * (nl * nl));
    const float gv = nv + std::sqrt(a2 + (1.0f - a2) * (nv * nv));
    return a2 / ((d * d) * (gl * gv));  // (1 / (gl gv)) · (α² / (π d²)) · π
}

/// Image lighting's D and S (see the header) at unit lit normal `n` and unit `v` (toward the
/// shading eye): `metal` and `rough` a metallic-roughness material's (its maps applied; ignored
/// for Blinn-Phong, which reflects with roughnessOfShininess), `occlusion` the occlusion map's.
inline LightTerms environmentTerms(const Environment& env, const Material& m, glm::vec3 n,
                                   glm::vec3 v, float metal, float rough, float occlusion) {
    const float ndotv = glm::dot(n, v);
    const glm::vec3 r = n * (2.0f * ndotv) - v;
    const bool blinnPhong = m.model != MaterialModel::MetallicRoughness;
    const float roughness = blinnPhong ? roughnessOfShininess(m.shininess) : rough;
    const glm::vec3 e = diffuseLight(env, n);
    const glm::vec3 p = prefiltered(env, r, roughness);
    const glm::vec2 ab = splitSum(std::abs(ndotv), roughness);
    const float fd = 0.04f * ab.x + ab.y;
    LightTerms t;
    if (blinnPhong) {
        t.diffuse = e * occlusion;
        t.specular = p * (occlusion * m.specular * fd);
    } else {
        t.diffuse = ((1.0f - metal) * (1.0f - fd) * e + (metal * ab.x) * p) * occlusion;
        t.specular = p * (occlusion * ((1.0f - metal) * fd + metal * ab.y));
    }
    return t;
}

/// The D / S terms of a MaterialModel::MetallicRoughness surface (see the header): D multiplies
/// the base colour (albedo × texel × vertex colour), S is added; S includes the emissive.
/// `normal` need not be unit. `shadow`: per-light factors (issue 15), null = lit. `maps`: the
/// metallic-roughness texel's factors (SurfaceMaps; pixel shading), null = the factors alone.
inline LightTerms metallicRoughnessTerms(const ShadingContext& ctx, const Material& m,
                                         glm::vec3 normal, glm::vec3 worldPos,
                                         const float* shadow = nullptr,
                                         const SurfaceMaps* maps = nullptr) {
    const glm::vec3 n = glm::normalize(facingNormal(ctx, m, normal, worldPos));
    const glm::vec3 v = glm::normalize(ctx.centerEye - worldPos);
    const float metal = std::clamp(maps ? m.metallic * maps->metallic : m.metallic, 0.0f, 1.0f);
    const float rough =
        std::clamp(maps ? m.roughness * maps->roughness : m.roughness, 0.0f, 1.0f);
    const float alpha = std::max(rough * rough, 1e-3f);
    const float nv = std::abs(glm::dot(n, v));
    LightTerms t;
    t.diffuse = ctx.ambient;
    for (const DirectionalLight& l : ctx.lights) {
        const LightSample s = lightAt(l, worldPos);
        const float nl = glm::dot(n, s.toLight);
        if (nl > 0.0f) {
            const glm::vec3 h = glm::normalize(s.toLight + v);
            const float nh = std::max(glm::dot(n, h), 0.0f);
            const float vh = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
            const float spec = metallicRoughnessSpecular(alpha, nh, nl, nv);
            const float w1 = 1.0f - vh, w2 = w1 * w1;
            const float w = w2 * w2 * w1;
            const float f = 0.04f + 0.96f * w;
            const glm::vec3 lc = l.color * s.attenuation * shadowFactor(ctx, l, shadow) * nl;
            t.diffuse += ((1.0f - metal) * (1.0f - f) + metal * spec * (1.0f - w)) * lc;
            t.specular += (spec * ((1.0f - metal) * f + metal * w)) * lc;
        }
    }
    if (ctx.environment) {
        const LightTerms e = environmentTerms(*ctx.environment, m, n, v, metal, rough,
                                              maps ? maps->occlusion : 1.0f);
        t.diffuse += e.diffuse;
        t.specular += e.specular;
    }
    t.specular += m.emissive;
    return t;
}

/// Unlit's terms: the base colour as it is (D = 1, S = 0).
inline LightTerms unlitTerms() { return {glm::vec3(1.0f), glm::vec3(0.0f)}; }

/// Flat's S: a metallic-roughness material's emissive (flat shading has no highlight), else 0.
inline glm::vec3 flatSpecular(const Material& m) {
    return m.model == MaterialModel::MetallicRoughness ? m.emissive : glm::vec3(0.0f);
}

/// Flat at `worldPos` (the triangle's centroid; only point / spot lights use it): ambient +
/// Σ att · max(dot(n, l), 0) · albedo · lightColor (+ the emissive: flatSpecular). `faceNormal`
/// unit, world space.
/// `shadow` (issue 15): per light, the factor (shadows.h) multiplying its term; null = lit.
inline glm::vec3 shadeFlat(const ShadingContext& ctx, const Material& m, glm::vec3 faceNormal,
                           glm::vec3 worldPos, const float* shadow = nullptr) {
    if (m.model == MaterialModel::Unlit) return finishColor(ctx, m.albedo);
    faceNormal = facingNormal(ctx, m, faceNormal, worldPos);
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        const float sf = shadowFactor(ctx, l, shadow);
        if (l.type == LightType::Directional) {
            c += (std::max(glm::dot(faceNormal, l.towardLight), 0.0f) * m.albedo * l.color) * sf;
        } else {
            const LightSample s = lightAt(l, worldPos);
            c += (std::max(glm::dot(faceNormal, s.toLight), 0.0f) * m.albedo *
                  (l.color * s.attenuation)) *
                 sf;
        }
    }
    if (ctx.environment) c += diffuseLight(*ctx.environment, faceNormal) * m.albedo;
    return finishColor(ctx, c + flatSpecular(m));
}
/// Flat with directional lights only (the position is not needed).
inline glm::vec3 shadeFlat(const ShadingContext& ctx, const Material& m, glm::vec3 faceNormal,
                           const float* shadow = nullptr) {
    return shadeFlat(ctx, m, faceNormal, glm::vec3(0.0f), shadow);
}

/// Blinn-Phong: ambient + Σ att · [max(n·l, 0) · albedo + specular · max(n·h, 0)^shininess
/// (only where n·l > 0)] · lightColor, with h = normalize(l + v), v = normalize(centerEye − p).
/// `normal` need not be unit (it is normalized here). `shadow` (issue 15): per light, the
/// factor (shadows.h) multiplying its diffuse + specular; null = lit.
/// The smooth (Vertex / Pixel) colour of every model: the others as clamp(albedo ⊙ D + S) of
/// their terms, the formula of textured surfaces (shadeTextured), so the two agree.
inline glm::vec3 shadeBlinnPhong(const ShadingContext& ctx, const Material& m, glm::vec3 normal,
                                 glm::vec3 worldPos, const float* shadow = nullptr) {
    if (m.model == MaterialModel::MetallicRoughness) {
        const LightTerms t = metallicRoughnessTerms(ctx, m, normal, worldPos, shadow);
        return finishColor(ctx, m.albedo * t.diffuse + t.specular);
    }
    if (m.model == MaterialModel::Unlit) return finishColor(ctx, m.albedo);
    const glm::vec3 n = glm::normalize(facingNormal(ctx, m, normal, worldPos));
    const glm::vec3 v = glm::normalize(ctx.centerEye - worldPos);
    glm::vec3 c = ctx.ambient * m.albedo;
    for (const DirectionalLight& l : ctx.lights) {
        const LightSample s = lightAt(l, worldPos);
        const float nl = glm::dot(n, s.toLight);
        if (nl > 0.0f) {
            const glm::vec3 h = glm::normalize(s.toLight + v);
            const float spec =
                m.specular * specularPow(std::max(glm::dot(n, h), 0.0f), m.shininess);
            const float sf = shadowFactor(ctx, l, shadow);
            if (l.type == LightType::Directional) {
                c += ((nl * m.albedo + glm::vec3(spec)) * l.color) * sf;
            } else {
                c += ((nl * m.albedo + glm::vec3(spec)) * (l.color * s.attenuation)) * sf;
            }
        }
    }
    if (ctx.environment) {
        const LightTerms e = environmentTerms(*ctx.environment, m, n, v, 0.0f, 0.0f, 1.0f);
        c += m.albedo * e.diffuse + e.specular;
    }
    return finishColor(ctx, c);
}

/// Flat's terms: D = ambient + Σ att · max(n·l, 0) · lightColor at `worldPos` (the centroid),
/// S = flatSpecular (the emissive). `faceNormal` unit. `shadow`: per-light factors (issue 15), null = lit.
inline LightTerms flatTerms(const ShadingContext& ctx, const Material& m, glm::vec3 faceNormal,
                            glm::vec3 worldPos, const float* shadow = nullptr) {
    if (m.model == MaterialModel::Unlit) return unlitTerms();
    faceNormal = facingNormal(ctx, m, faceNormal, worldPos);
    LightTerms t;
    t.diffuse = ctx.ambient;
    for (const DirectionalLight& l : ctx.lights) {
        const LightSample s = lightAt(l, worldPos);
        t.diffuse += (std::max(glm::dot(faceNormal, s.toLight), 0.0f) * (l.color * s.attenuation)) *
                     shadowFactor(ctx, l, shadow);
    }
    if (ctx.environment) t.diffuse += diffuseLight(*ctx.environment, faceNormal);
    t.specular = flatSpecular(m);
    return t;
}

/// Blinn-Phong's terms: D = ambient + Σ att · max(n·l, 0) · lightColor, S = Σ att · specular ·
/// max(n·h, 0)^shininess · lightColor (where n·l > 0). `normal` need not be unit. `shadow`:
/// per-light factors (issue 15) multiplying each light's D and S terms, null = lit. `maps`: a
/// metallic-roughness material's texel factors (metallicRoughnessTerms), and the occlusion of
/// the environment's light (environmentTerms); null = none.
inline LightTerms blinnPhongTerms(const ShadingContext& ctx, const Material& m, glm::vec3 normal,
                                  glm::vec3 worldPos, const float* shadow = nullptr,
                                  const SurfaceMaps* maps = nullptr) {
    if (m.model == MaterialModel::MetallicRoughness)
        return metallicRoughnessTerms(ctx, m, normal, worldPos, shadow, maps);
    if (m.model == MaterialModel::Unlit) return unlitTerms();
    const glm::vec3 n = glm::normalize(facingNormal(ctx, m, normal, worldPos));
    const glm::vec3 v = glm::normalize(ctx.centerEye - worldPos);
    LightTerms t;
    t.diffuse = ctx.ambient;
    for (const DirectionalLight& l : ctx.lights) {
        const LightSample s = lightAt(l, worldPos);
        const float nl = glm::dot(n, s.toLight);
        if (nl > 0.0f) {
            const glm::vec3 h = glm::normalize(s.toLight + v);
            const float spec =
                m.specular * specularPow(std::max(glm::dot(n, h), 0.0f), m.shininess);
            const glm::vec3 lc = l.color * s.attenuation * shadowFactor(ctx, l, shadow);
            t.diffuse += nl * lc;
            t.specular += spec * lc;
        }
    }
    if (ctx.environment) {
        const LightTerms e = environmentTerms(*ctx.environment, m, n, v, 0.0f, 0.0f,
                                              maps ? maps->occlusion : 1.0f);
        t.diffuse += e.diffuse;
        t.specular += e.specular;
    }
    return t;
}

/// A textured surface's color: clamp(base ⊙ D + S, 0, 1), base = albedo × texel (linear), not
/// tone mapped (Tonemap::None; the backends call the ShadingContext overload below).
inline glm::vec3 shadeTextured(glm::vec3 base, const LightTerms& t) {
    return glm::clamp(base * t.diffuse + t.specular, 0.0f, 1.0f);
}
/// The same, tone mapped as ctx says (finishColor).
inline glm::vec3 shadeTextured(const ShadingContext& ctx, glm::vec3 base, const LightTerms& t) {
    return finishColor(ctx, base * t.diffuse + t.specular);
}

/// A lit fragment's terms under its maps, in every shading (D and S computed without them):
/// the occlusion scales the ambient term only (glTF: "indirect lighting"), D − ambient · (1 −
/// occlusion); a metallic-roughness material's S holds its emissive once, which the emissive
/// texel scales: S + emissive · (texel − 1). Unlit terms are left as they are.
inline LightTerms applySurfaceMaps(const ShadingContext& ctx, const Material& m, LightTerms t,
                                   const SurfaceMaps& maps) {
    if (m.model == MaterialModel::Unlit) return t;
    t.diffuse -= ctx.ambient * (1.0f - maps.occlusion);
    if (m.model == MaterialModel::MetallicRoughness)
        t.specular += m.emissive * (maps.emissive - glm::vec3(1.0f));
    return t;
}

/// glTF's normal map: the texel's RGB (linear, [0, 1]) read as a tangent-space normal
/// c = 2·rgb − 1 with c.x, c.y × `scale`, in the frame of the interpolated normal n, the tangent
/// t = tangent.xyz made orthogonal to n (Gram-Schmidt) and the bitangent b = tangent.w ·
/// cross(n, t): normalize(t · c.x + b · c.y + n · c.z), as the glTF sample viewer does. A
/// degenerate frame (a zero tangent, or one along n) keeps n. The double-sided flip
/// (facingNormal) then applies to the result: negating it is flipping the whole frame.
inline glm::vec3 perturbedNormal(glm::vec3 n, glm::vec4 tangent, glm::vec3 texel, float scale) {
    n = glm::normalize(n);
    glm::vec3 t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
    const float tl = glm::length(t);
    if (!(tl > 1e-6f)) return n;
    t /= tl;
    const glm::vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, t);
    const glm::vec3 c((2.0f * texel.x - 1.0f) * scale, (2.0f * texel.y - 1.0f) * scale,
                      2.0f * texel.z - 1.0f);
    const glm::vec3 p = (t * c.x + b * c.y) + n * c.z;
    const float pl = glm::length(p);
    return pl > 0.0f ? p / pl : n;
}

/// The occlusion of an occlusion texel's R channel (linear, [0, 1]) at `strength`.
inline float occlusionOf(float r, float strength) { return 1.0f + strength * (r - 1.0f); }

/// The base color and alpha of a fragment: (albedo, alpha) × texel (linear RGBA).
inline glm::vec4 baseColor(const Material& m, glm::vec4 texel) {
    return glm::vec4(m.albedo, m.alpha) * texel;
}

inline std::uint8_t quantizeUnorm8(float c) {
    // max(0, c) first: a NaN reads 0 (std::clamp would pass it on to an undefined cast).
    return static_cast<std::uint8_t>(std::min(std::max(0.0f, c), 1.0f) * 255.0f + 0.5f);
}

}  // namespace mvr
