#include "shaders.h"

#include <fmt/format.h>

#include "egl_context.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"

namespace mvr::gl::detail {

namespace {

// Shared by every stage: the per-frame block, the per-instance uniforms and lighting.h in GLSL.
// MAX_VIEWS / MAX_LIGHTS are defined before it (common()).
const char* const kCommon = R"glsl(
layout(std140, binding = 0) uniform Frame {
    mat4 uClipFromWorld[MAX_VIEWS];
    vec4 uTile[MAX_VIEWS];      // kalaiah: clip.xy' = clip.xy * uTile.xy + clip.w * uTile.zw
    vec4 uLightDir[MAX_LIGHTS]; // unit, toward the light, world space (spot: −axis)
    vec4 uLightColor[MAX_LIGHTS];
    vec4 uAmbient;
    vec4 uCenterEye;            // specular view vector target (lighting.h)
    ivec4 uCounts;              // x: lights, y: views, zw: per-view target size in pixels
    vec4 uLightPos[MAX_LIGHTS];  // xyz: position (point / spot), w: 0 directional, 1 point, 2 spot
    vec4 uLightCone[MAX_LIGHTS]; // x: range (0 = infinite), y: cos inner, z: cos outer
    vec4 uViewEye[MAX_VIEWS];    // each view's eye, world space (--specular per-view)
    vec4 uEnvSh[9];              // ENVIRONMENT: Environment::sh (rgb), environment.h's order
};
layout(location = 0) uniform int uView;
layout(location = 1) uniform mat4 uWorldFromModel;
layout(location = 2) uniform mat4 uNormalFromModel;  // inverse transpose (upper 3x3 used)
layout(location = 3) uniform mat4 uCofactor;         // det * inverse transpose: model edge cross -> world edge cross
layout(location = 4) uniform vec4 uMaterial;         // albedo rgb, specular
layout(location = 5) uniform float uShininess;
layout(location = 6) uniform ivec4 uMatFlags;        // x: texture slots (bits: 1 base colour, 2 metallic-roughness, 4 occlusion, 8 emissive, 16 normal; any: textured), y: alpha mode (0 opaque, 1 mask, 2 blend), z: double-sided, w: MaterialModel (0 Blinn-Phong, 1 metallic-roughness, 2 unlit)
layout(location = 7) uniform vec3 uMatFactors;       // x: material alpha, y: mask cutoff, z: occlusion strength
layout(location = 20) uniform vec2 uMetalRough;      // metallic, roughness (model 1)
layout(location = 21) uniform vec3 uEmissive;        // model 1
// Material::normalScale: read by NORMAL_MAPS programs only, declared in every one so that the
// location is a known (if inactive) uniform wherever setInstanceUniforms sets it.
layout(location = 22) uniform float uNormalScale;

// The eye shading looks from (lighting.h SpecularEye): the rig's centre eye, or (--specular
// per-view, pixel shading) the fragment's own view's, whose index main() finds first.
#if defined(PER_VIEW_EYE) && defined(FRAGMENT_STAGE) && !defined(DEPTH_ONLY)
int gEyeView;
#define SHADING_EYE (uViewEye[gEyeView].xyz)
#else
#define SHADING_EYE (uCenterEye.xyz)
#endif

// Lighting kept as D and S (below) for a base colour that varies across the triangle: a
// texture's (any slot, uMatFlags.x: the other maps change D and S per fragment), or
// (VERTEX_COLORS: some mesh of the frame has them, as the soft backend's
// FrameContext::colored) the interpolated vertex colour's, for every mesh of the frame.
#ifdef VERTEX_COLORS
#define SPLIT_LIGHTING true
#else
#define SPLIT_LIGHTING (uMatFlags.x != 0)
#endif

#ifdef SHADOWS
// shadows.h shadowFactor() (issue 15): linear distances in an R32F array, one layer per map.
layout(binding = 3) uniform sampler2DArray uShadowMaps;  // units 2, 4-7: the material's textures
layout(location = 8) uniform mat4 uShadowClip[MAX_LIGHTS];    // light clipFromWorld
layout(location = 12) uniform vec4 uShadowInfo[MAX_LIGHTS];   // layer (< 0: none), persp, near, far
layout(location = 16) uniform vec4 uShadowTexel[MAX_LIGHTS];  // texelWorld, size
float shadowFactor(int i, vec3 p, vec3 normal) {
    if (uShadowInfo[i].x < 0.0) return 1.0;
    vec4 c = uShadowClip[i] * vec4(p, 1.0);
    if (!(c.w > 0.0)) return 1.0;
    float iw = 1.0 / c.w;
    float nx = c.x * iw, ny = c.y * iw, nz = c.z * iw;
    if (!(abs(nx) <= 1.0 && abs(ny) <= 1.0 && nz <= 1.0)) return 1.0;
    bool persp = uShadowInfo[i].y > 0.5;
    float r = persp ? c.w : uShadowInfo[i].z + (nz * 0.5 + 0.5) * (uShadowInfo[i].w - uShadowInfo[i].z);
    float fs = uShadowTexel[i].y;
    int size = int(fs), layer = int(uShadowInfo[i].x);
    int tx = clamp(int(floor((nx * 0.5 + 0.5) * fs)), 0, size - 1);
    int ty = clamp(int(floor((ny * 0.5 + 0.5) * fs)), 0, size - 1);
    float len = length(normal);
    vec3 n = len > 0.0 ? normal / len : normal;
    vec3 l = uLightDir[i].xyz;
    if (uLightPos[i].w > 0.5) {  // Frame block: point / spot
        vec3 d = uLightPos[i].xyz - p;
        float dl = length(d);
        if (dl > 0.0) l = d / dl;
    }
    float cosT = clamp(dot(n, l), 1e-3, 1.0);
    float tanT = min(sqrt(1.0 - cosT * cosT) / cosT, 8.0);
    float texel = persp ? uShadowTexel[i].x * r : uShadowTexel[i].x;
    float ref = r - texel * (1.0 + 1.5 * tanT);
    int lit = 0;
    for (int j = -1; j <= 1; ++j) {
        int y = clamp(ty + j, 0, size - 1);
        for (int k = -1; k <= 1; ++k) {
            int x = clamp(tx + k, 0, size - 1);
            lit += texelFetch(uShadowMaps, ivec3(x, y, layer), 0).r >= ref ? 1 : 0;
        }
    }
    return float(lit) * (1.0 / 9.0);
}
#else
float shadowFactor(int i, vec3 p, vec3 n) { return 1.0; }
#endif

// lighting.h lightAt(): the direction toward light i from p and the light's color arriving
// there (directional: uLightDir, uLightColor unchanged; point / spot: KHR_lights_punctual's
// range falloff max(min(1 − (d/range)^4, 1), 0) / d² and the spot's squared cone ramp).
vec3 lightAt(int i, vec3 p, out vec3 l) {
    if (uLightPos[i].w == 0.0) {
        l = uLightDir[i].xyz;
        return uLightColor[i].rgb;
    }
    vec3 d = uLightPos[i].xyz - p;
    float d2 = dot(d, d);
    l = d2 > 0.0 ? d / sqrt(d2) : uLightDir[i].xyz;
    float dd = max(d2, 1e-8);
    float att = 1.0 / dd;
    float range = uLightCone[i].x;
    if (range > 0.0) {
        float r = dd / (range * range);
        att = clamp(1.0 - r * r, 0.0, 1.0) / dd;
    }
    if (uLightPos[i].w == 2.0) {
        float scale = 1.0 / max(0.001, uLightCone[i].y - uLightCone[i].z);
        float offset = -uLightCone[i].z * scale;
        float t = clamp(dot(uLightDir[i].xyz, l) * scale + offset, 0.0, 1.0);
        att *= t * t;
    }
    return uLightColor[i].rgb * att;
}

// lighting.h facingNormal(): a double-sided material's normal is flipped where it faces away
// from the shading eye (the centre eye, view-independent like the rest of shading; with
// PER_VIEW_EYE the fragment's view's).
vec3 facingNormal(vec3 n, vec3 p) {
    return (uMatFlags.z != 0 && dot(n, SHADING_EYE - p) < 0.0) ? -n : n;
}

// lighting.h finishColor(): tone mapped (uAmbient.w: Tonemap 0 none, 1 Khronos PBR Neutral,
// 2 ACES Narkowicz), then clamped.
vec3 finishColor(vec3 c) {
    int t = int(uAmbient.w);
    if (t == 1) {
        float x = min(c.r, min(c.g, c.b));
        float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
        c -= offset;
        float peak = max(c.r, max(c.g, c.b));
        if (peak >= 0.76) {
            float d = 1.0 - 0.76;
            float newPeak = 1.0 - d * d / (peak + d - 0.76);
            c *= newPeak / peak;
            float g = 1.0 - 1.0 / (0.15 * (peak - newPeak) + 1.0);
            c = mix(c, vec3(newPeak), g);
        }
    } else if (t == 2) {
        c = max(c, vec3(0.0));
        c = (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14);
    }
    return clamp(c, 0.0, 1.0);
}

// lighting.h flatSpecular(): flat's S, a metallic-roughness material's emissive.
vec3 flatSpecular() { return uMatFlags.w == 1 ? uEmissive : vec3(0.0); }

#ifdef ENVIRONMENT
// Image lighting (issue 39 item 2; environment.h, lighting.h environmentTerms): the map's
// irradiance as 9 SH coefficients (uEnvSh, the Frame block), its GGX-prefiltered levels as the
// mip levels 0..5 of one RGBA32F texture (LINEAR_MIPMAP_LINEAR, REPEAT in s, CLAMP_TO_EDGE in
// t) and the split sum's (A, B) table (32x32 RG32F, LINEAR, CLAMP_TO_EDGE; s = n·v, t =
// roughness). Units 8 and 9 (renderer.h kEnvironmentUnit, kSplitSumUnit).
layout(binding = 8) uniform sampler2D uEnvironmentMap;
layout(binding = 9) uniform sampler2D uSplitSumTable;

// environment.h equirectUv()
vec2 equirectUv(vec3 d) {
    float lon = (d.x == 0.0 && d.z == 0.0) ? 0.0 : atan(d.x, -d.z);  // straight up / down
    float lat = asin(clamp(d.y, -1.0, 1.0));
    return vec2(0.5 + lon * (0.5 / 3.14159265358979), 0.5 - lat * (1.0 / 3.14159265358979));
}

// environment.h diffuseLight()
vec3 diffuseLight(vec3 n) {
    vec3 e = uEnvSh[0].rgb * 0.282095;
    e += (uEnvSh[1].rgb * n.y + uEnvSh[2].rgb * n.z + uEnvSh[3].rgb * n.x) * 0.488603;
    e += (uEnvSh[4].rgb * (n.x * n.y) + uEnvSh[5].rgb * (n.y * n.z) +
          uEnvSh[7].rgb * (n.x * n.z)) * 1.092548;
    e += uEnvSh[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0));
    e += uEnvSh[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// environment.h prefiltered(): level roughness · (kLevels − 1), trilinear (explicit level: no
// derivatives, so it is the same in every stage and control flow).
vec3 prefiltered(vec3 r, float roughness) {
    return textureLod(uEnvironmentMap, equirectUv(r), clamp(roughness, 0.0, 1.0) * 5.0).rgb;
}

// environment.h splitSum() (the table has one level: textureLod 0 is texture()'s value)
vec2 splitSum(float nv, float roughness) {
    return textureLod(uSplitSumTable, vec2(clamp(nv, 0.0, 1.0), clamp(roughness, 0.0, 1.0)),
                      0.0).rg;
}

// environment.h roughnessOfShininess()
float roughnessOfShininess(float s) { return sqrt(sqrt(2.0 / (max(s, 0.0) + 2.0))); }

// lighting.h environmentTerms(): the environment's D and S at unit lit normal n and unit v
// (toward the shading eye); metal, rough: a metallic-roughness material's (maps applied),
// occlusion: the occlusion map's.
void environmentTerms(vec3 n, vec3 v, float metal, float rough, float occlusion,
                      out vec3 diffuse, out vec3 specular) {
    float ndotv = dot(n, v);
    vec3 r = n * (2.0 * ndotv) - v;
    bool blinnPhong = uMatFlags.w != 1;
    float roughness = blinnPhong ? roughnessOfShininess(uShininess) : rough;
    vec3 e = diffuseLight(n);
    vec3 p = prefiltered(r, roughness);
    vec2 ab = splitSum(abs(ndotv), roughness);
    float fd = 0.04 * ab.x + ab.y;
    if (blinnPhong) {
        diffuse = e * occlusion;
        specular = p * (occlusion * uMaterial.w * fd);
    } else {
        diffuse = ((1.0 - metal) * (1.0 - fd) * e + (metal * ab.x) * p) * occlusion;
        specular = p * (occlusion * ((1.0 - metal) * fd + metal * ab.y));
    }
}
#endif

// lighting.h shadeFlat() (p: the triangle's centroid, for point / spot lights)
// Shadows (issue 15): each light's term × shadowFactor at p, with the unflipped normal (as the
// soft backend's shadowFactors).
vec3 shadeFlat(vec3 faceNormal, vec3 p) {
    if (uMatFlags.w == 2) return finishColor(uMaterial.rgb);
    vec3 n0 = faceNormal;
    faceNormal = facingNormal(faceNormal, p);
    vec3 albedo = uMaterial.rgb;
    vec3 c = uAmbient.rgb * albedo;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, p, l);
        c += (max(dot(faceNormal, l), 0.0) * albedo * lc) * shadowFactor(i, p, n0);
    }
#ifdef ENVIRONMENT
    c += diffuseLight(faceNormal) * albedo;
#endif
    return finishColor(c + flatSpecular());
}

// lighting.h metallicRoughnessTerms(): glTF 2.0 Appendix B's BRDF as D (× base colour) and S
// (added, with the emissive), π folded in as mvr's light convention. metalRough: the material's
// metallic, roughness (uMetalRough, or mappedMaterial's: × the metallic-roughness texel).
// shadowNormal: the normal the shadows are looked up with, the surface's own (`normal` but
// where a normal map bent it: pipeline.h's texturedFragment). occlusion: the occlusion map's,
// for the environment's light (ENVIRONMENT; 1 without a map, and per vertex).
void metallicRoughnessTerms(vec2 metalRough, vec3 normal, vec3 shadowNormal, vec3 worldPos,
                            float occlusion, out vec3 diffuse, out vec3 specular) {
    vec3 n = normalize(facingNormal(normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    float metal = clamp(metalRough.x, 0.0, 1.0);
    float rough = clamp(metalRough.y, 0.0, 1.0);
    float alpha = max(rough * rough, 1e-3);
    float a2 = alpha * alpha;
    float nv = abs(dot(n, v));
    diffuse = uAmbient.rgb;
    specular = vec3(0.0);
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, worldPos, l);
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + v);
            float nh = max(dot(n, h), 0.0);
            float vh = clamp(dot(v, h), 0.0, 1.0);
            float d = nh * nh * (a2 - 1.0) + 1.0;
            float kl = nl + sqrt(a2 + (1.0 - a2) * (nl * nl));
            float kv = nv + sqrt(a2 + (1.0 - a2) * (nv * nv));
            float spec = a2 / ((d * d) * (kl * kv));
            float w1 = 1.0 - vh, w2 = w1 * w1;
            float w = w2 * w2 * w1;
            float f = 0.04 + 0.96 * w;
            lc = lc * shadowFactor(i, worldPos, shadowNormal) * nl;  // C++'s order
            diffuse += ((1.0 - metal) * (1.0 - f) + metal * spec * (1.0 - w)) * lc;
            specular += (spec * ((1.0 - metal) * f + metal * w)) * lc;
        }
    }
#ifdef ENVIRONMENT
    {
        vec3 ed, es;
        environmentTerms(n, v, metal, rough, occlusion, ed, es);
        diffuse += ed;
        specular += es;
    }
#endif
    specular += uEmissive;
}

// lighting.h shadeBlinnPhong(): the smooth colour of every model
vec3 shadeBlinnPhong(vec3 normal, vec3 worldPos) {
    if (uMatFlags.w == 1) {
        vec3 d, sp;
        metallicRoughnessTerms(uMetalRough, normal, normal, worldPos, 1.0, d, sp);
        return finishColor(uMaterial.rgb * d + sp);
    }
    if (uMatFlags.w == 2) return finishColor(uMaterial.rgb);
    vec3 albedo = uMaterial.rgb;
    vec3 n = normalize(facingNormal(normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    vec3 c = uAmbient.rgb * albedo;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, worldPos, l);
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + v);
            float spec = uMaterial.w * pow(max(dot(n, h), 0.0), uShininess);
            c += ((nl * albedo + vec3(spec)) * lc) * shadowFactor(i, worldPos, normal);
        }
    }
#ifdef ENVIRONMENT
    {
        vec3 ed, es;
        environmentTerms(n, v, 0.0, 0.0, 1.0, ed, es);
        c += albedo * ed + es;
    }
#endif
    return finishColor(c);
}

// Textured surfaces (lighting.h LightTerms): the texel varies across the triangle, so the
// lighting is kept as D (ambient + Σ max(n·l, 0) · light, multiplies the base color albedo ×
// texel) and S (the specular sum, added): clamp(base · D + S), in the fragment shader.
// lighting.h flatTerms(): D only.
vec3 flatDiffuse(vec3 faceNormal, vec3 p) {
    if (uMatFlags.w == 2) return vec3(1.0);
    vec3 n0 = faceNormal;
    faceNormal = facingNormal(faceNormal, p);
    vec3 d = uAmbient.rgb;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, p, l);
        d += (max(dot(faceNormal, l), 0.0) * lc) * shadowFactor(i, p, n0);
    }
#ifdef ENVIRONMENT
    d += diffuseLight(faceNormal);
#endif
    return d;
}

// lighting.h blinnPhongTerms() (metalRough, shadowNormal, occlusion: metallicRoughnessTerms')
void blinnPhongTerms(vec2 metalRough, vec3 normal, vec3 shadowNormal, vec3 worldPos,
                     float occlusion, out vec3 diffuse, out vec3 specular) {
    if (uMatFlags.w == 1) {
        metallicRoughnessTerms(metalRough, normal, shadowNormal, worldPos, occlusion, diffuse,
                               specular);
        return;
    }
    if (uMatFlags.w == 2) {
        diffuse = vec3(1.0);
        specular = vec3(0.0);
        return;
    }
    vec3 n = normalize(facingNormal(normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    diffuse = uAmbient.rgb;
    specular = vec3(0.0);
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, worldPos, l);
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + v);
            float spec = uMaterial.w * pow(max(dot(n, h), 0.0), uShininess);
            lc *= shadowFactor(i, worldPos, shadowNormal);
            diffuse += nl * lc;
            specular += spec * lc;
        }
    }
#ifdef ENVIRONMENT
    {
        vec3 ed, es;
        environmentTerms(n, v, 0.0, 0.0, occlusion, ed, es);
        diffuse += ed;
        specular += es;
    }
#endif
}

// lighting.h applySurfaceMaps(): a lit fragment's D and S under its maps, in every shading —
// the occlusion scales the ambient term, the emissive texel a metallic-roughness material's
// emissive (held once in S); unlit terms are left as they are. The defaults (occlusion 1,
// texel 1: absent slots) change nothing.
void applySurfaceMaps(inout vec3 diffuse, inout vec3 specular, float occlusion,
                      vec3 emissiveTexel) {
    if (uMatFlags.w == 2) return;
    diffuse -= uAmbient.rgb * (1.0 - occlusion);
    if (uMatFlags.w == 1) specular += uEmissive * (emissiveTexel - vec3(1.0));
}
)glsl";

// The shared source with its array sizes from the C++ constants (FrameBlock has the same).
std::string common() {
    return fmt::format("#define MAX_VIEWS {}\n#define MAX_LIGHTS {}\n", kMaxViews, kMaxLights) +
           kCommon;
}

const char* const kVertex = R"glsl(
#ifdef VS_KALAIAH
// kalaiah2007 §4: the vertex is a dummy (corner i, view j); the triangle's real corners
// arrive as attributes (per instance = per triangle).
layout(location = 0) in ivec2 aDummy;
layout(location = 1) in vec3 aP0;
layout(location = 2) in vec3 aP1;
layout(location = 3) in vec3 aP2;
layout(location = 4) in vec3 aN0;
layout(location = 5) in vec3 aN1;
layout(location = 6) in vec3 aN2;
layout(location = 7) in vec2 aT0;
layout(location = 8) in vec2 aT1;
layout(location = 9) in vec2 aT2;
#ifdef VERTEX_COLORS
layout(location = 10) in vec4 aC0;
layout(location = 11) in vec4 aC1;
layout(location = 12) in vec4 aC2;
#endif
#ifdef NORMAL_MAPS
layout(location = 13) in vec4 aTa0;  // the corners' tangents ((0, 0, 0, 1): the mesh has none)
layout(location = 14) in vec4 aTa1;
layout(location = 15) in vec4 aTa2;
#endif
out float gl_ClipDistance[4];
#else
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aTexcoord;
layout(location = 3) in vec3 aFaceCenter;  // FLAT_PROVOKING: the face's model-space centroid
#ifdef VERTEX_COLORS
layout(location = 4) in vec4 aColor;       // linear RGBA (mesh.h Mesh::colors; white if none)
#endif
#ifdef NORMAL_MAPS
layout(location = 5) in vec4 aTangent;     // mesh.h Mesh::tangents ((0, 0, 0, 1) if none)
#endif
#endif
#ifdef VERTEX_COLORS
layout(location = 7) out vec4 oVertexColor;
#endif

#if !defined(DEPTH_ONLY)
layout(location = 0) out vec3 oWorld;
layout(location = 1) out vec3 oNormal;
#if defined(SHADING_FLAT) && (defined(VS_KALAIAH) || defined(FLAT_PROVOKING))
layout(location = 2) flat out vec3 oColor;
layout(location = 6) flat out vec3 oSpecular;
#else
layout(location = 2) out vec3 oColor;
layout(location = 6) out vec3 oSpecular;
#endif
#endif
layout(location = 5) out vec2 oTexcoord;
#if defined(PER_VIEW_EYE) && (defined(VS_KALAIAH) || defined(VS_MULTIVIEW))
layout(location = 8) flat out int oEyeView;  // the fragment's view (PER_VIEW_EYE)
#endif
#if defined(NORMAL_MAPS) && !defined(DEPTH_ONLY)
layout(location = 9) out vec4 oTangent;  // world tangent, w the handedness
#endif

#ifdef VS_MULTIVIEW
layout(num_views = NUM_VIEWS) in;
#endif

void main() {
#ifdef VS_KALAIAH
    int corner = aDummy.x;
    int view = aDummy.y;
    vec3 p = corner == 0 ? aP0 : (corner == 1 ? aP1 : aP2);
    vec3 n = corner == 0 ? aN0 : (corner == 1 ? aN1 : aN2);
    oTexcoord = corner == 0 ? aT0 : (corner == 1 ? aT1 : aT2);
#ifdef NORMAL_MAPS
    vec4 tangent = corner == 0 ? aTa0 : (corner == 1 ? aTa1 : aTa2);
#endif
#ifdef VERTEX_COLORS
    oVertexColor = corner == 0 ? aC0 : (corner == 1 ? aC1 : aC2);
#endif
#else
    vec3 p = aPosition;
    vec3 n = aNormal;
    oTexcoord = aTexcoord;
#ifdef NORMAL_MAPS
    vec4 tangent = aTangent;
#endif
#ifdef VERTEX_COLORS
    oVertexColor = aColor;
#endif
#endif
    vec4 world = uWorldFromModel * vec4(p, 1.0);
#if !defined(DEPTH_ONLY)
    oWorld = world.xyz;
    oNormal = mat3(uNormalFromModel) * n;
#ifdef NORMAL_MAPS
    // pipeline.h worldTangent(): the direction through the model's linear part, the handedness
    // flipped by a mirroring one (the bitangent is a cross product).
    mat3 worldLinear = mat3(uWorldFromModel);
    oTangent = vec4(worldLinear * tangent.xyz,
                    determinant(worldLinear) < 0.0 ? -tangent.w : tangent.w);
#endif
    oColor = vec3(0.0);
    oSpecular = vec3(0.0);
#if defined(SHADING_VERTEX)
    if (SPLIT_LIGHTING) {
        // factors only
        blinnPhongTerms(uMetalRough, oNormal, oNormal, world.xyz, 1.0, oColor, oSpecular);
    } else {
        oColor = shadeBlinnPhong(oNormal, world.xyz);
    }
#elif defined(SHADING_FLAT) && defined(VS_KALAIAH)
    vec3 w0 = (uWorldFromModel * vec4(aP0, 1.0)).xyz;
    vec3 w1 = (uWorldFromModel * vec4(aP1, 1.0)).xyz;
    vec3 w2 = (uWorldFromModel * vec4(aP2, 1.0)).xyz;
    vec3 centre = (w0 + w1 + w2) / 3.0;
    vec3 fn = normalize(cross(w1 - w0, w2 - w0));
    oColor = SPLIT_LIGHTING ? flatDiffuse(fn, centre) : shadeFlat(fn, centre);
#elif defined(SHADING_FLAT) && defined(FLAT_PROVOKING)
    // Only the provoking vertex's value is used: its "normal" is the face's model-space edge
    // cross product; the cofactor matrix maps it to the world-space edge cross product.
    vec3 fn = normalize(mat3(uCofactor) * n);
    vec3 centre = (uWorldFromModel * vec4(aFaceCenter, 1.0)).xyz;
    oColor = SPLIT_LIGHTING ? flatDiffuse(fn, centre) : shadeFlat(fn, centre);
#endif
#endif

#if defined(VS_DIRECT)
    gl_Position = uClipFromWorld[uView] * world;
#elif defined(VS_TO_GS)
    gl_Position = world;
#elif defined(VS_INSTANCED_LAYER)
    gl_Layer = gl_InstanceID;
    gl_Position = uClipFromWorld[gl_InstanceID] * world;
#elif defined(VS_MULTIVIEW)
    gl_Position = uClipFromWorld[int(gl_ViewID_OVR)] * world;
#ifdef PER_VIEW_EYE
#ifndef GL_OVR_multiview2
#error "--specular per-view on gl:multiview needs GL_OVR_multiview2 (the view index as an output)"
#endif
    oEyeView = int(gl_ViewID_OVR);
#endif
#elif defined(VS_KALAIAH)
    vec4 clip = uClipFromWorld[view] * world;
#ifdef PER_VIEW_EYE
    oEyeView = view;
#endif
    // Per-view clipping: the view's own frustum sides, since the partitioned buffer's
    // viewport would otherwise let a triangle spill into the neighbouring view.
    gl_ClipDistance[0] = clip.w + clip.x;
    gl_ClipDistance[1] = clip.w - clip.x;
    gl_ClipDistance[2] = clip.w + clip.y;
    gl_ClipDistance[3] = clip.w - clip.y;
    // The viewport transform into this view's partition, done here (kalaiah2007 §4).
    gl_Position = vec4(clip.xy * uTile[view].xy + clip.w * uTile[view].zw, clip.z, clip.w);
#endif
}
)glsl";

const char* const kGeometry = R"glsl(
#ifdef GS_INVOCATIONS
layout(triangles, invocations = GS_INVOCATIONS) in;
layout(triangle_strip, max_vertices = 3) out;
#else
layout(triangles) in;
layout(triangle_strip, max_vertices = GS_MAX_VERTICES) out;
#endif

layout(location = 0) in vec3 gWorld[];
layout(location = 1) in vec3 gNormal[];
layout(location = 2) in vec3 gColor[];
layout(location = 5) in vec2 gTexcoord[];
layout(location = 6) in vec3 gSpecular[];
#ifdef VERTEX_COLORS
layout(location = 7) in vec4 gVertexColor[];
layout(location = 7) out vec4 oVertexColor;
#endif
#ifdef NORMAL_MAPS
// Pixel shading with normal maps: 4 more components a vertex (method_table.cpp's limits).
layout(location = 9) in vec4 gTangent[];
layout(location = 9) out vec4 oTangent;
#endif

#if defined(SHADING_PIXEL)
layout(location = 0) out vec3 oWorld;
layout(location = 1) out vec3 oNormal;
#elif defined(SHADING_FLAT)
layout(location = 2) flat out vec3 oColor;
layout(location = 6) flat out vec3 oSpecular;
#else
layout(location = 2) out vec3 oColor;
layout(location = 6) out vec3 oSpecular;
#endif
#ifdef DEPTHMAP
layout(location = 3) out vec4 oLeftClip;
#endif
#ifdef GS_OUT_FLAG
layout(location = 4) flat out int oFlag;
#endif
layout(location = 5) out vec2 oTexcoord;

void emitView(int view, vec4 w[3], vec3 faceColor) {
    for (int i = 0; i < 3; ++i) {
        gl_Position = uClipFromWorld[view] * w[i];
        oTexcoord = gTexcoord[i];
#ifdef VERTEX_COLORS
        oVertexColor = gVertexColor[i];
#endif
#if defined(SHADING_PIXEL)
        oWorld = gWorld[i];
        oNormal = gNormal[i];
#ifdef NORMAL_MAPS
        oTangent = gTangent[i];
#endif
#elif defined(SHADING_FLAT)
        oColor = faceColor;
        oSpecular = vec3(0.0);
#else
        oColor = gColor[i];
        oSpecular = gSpecular[i];
#endif
#ifdef DEPTHMAP
        oLeftClip = uClipFromWorld[0] * w[i];
#endif
#if defined(GS_OUT_LAYER)
        gl_Layer = view;
#elif defined(GS_OUT_VIEWPORT)
        gl_ViewportIndex = view;
#elif defined(GS_OUT_FLAG)
        oFlag = view;
#endif
        EmitVertex();
    }
    EndPrimitive();
}

void main() {
    vec4 w[3] = vec4[3](vec4(gWorld[0], 1.0), vec4(gWorld[1], 1.0), vec4(gWorld[2], 1.0));
    vec3 faceColor = vec3(0.0);
#ifdef SHADING_FLAT
    // Shaded once per triangle for every view (view-independent work).
    vec3 fn = normalize(cross(gWorld[1] - gWorld[0], gWorld[2] - gWorld[0]));
    vec3 centre = (gWorld[0] + gWorld[1] + gWorld[2]) / 3.0;
    faceColor = SPLIT_LIGHTING ? flatDiffuse(fn, centre) : shadeFlat(fn, centre);
#endif
#ifdef GS_INVOCATIONS
    emitView(gl_InvocationID, w, faceColor);
#else
    for (int view = 0; view < GS_VIEWS; ++view) emitView(view, w, faceColor);
#endif
}
)glsl";

const char* const kFragment = R"glsl(
// CENTROID (multisampled targets, multisample.cpp): the interpolated inputs at a covered
// sample, where the pixel centre may lie outside the primitive (extrapolated colours at a
// silhouette); the texture coordinates stay at the centre (their derivatives pick the level).
#ifdef CENTROID
#define SMOOTH centroid
#else
#define SMOOTH
#endif
layout(location = 5) in vec2 iTexcoord;
layout(binding = 2) uniform sampler2D uBaseColor;  // sRGB texture: sampled in linear
// The other slots (lighting.h SurfaceMaps; units: materials.cpp kSlotUnits, 3 is the shadow
// maps'), through the base colour's coordinates and sampler.
layout(binding = 4) uniform sampler2D uMetallicRoughnessMap;  // linear: G roughness, B metallic
layout(binding = 5) uniform sampler2D uOcclusionMap;          // linear: R
layout(binding = 6) uniform sampler2D uEmissiveMap;           // sRGB: sampled in linear
#ifdef VERTEX_COLORS
layout(location = 7) SMOOTH in vec4 iVertexColor;
#endif
#if !defined(DEPTH_ONLY)
layout(location = 0) SMOOTH in vec3 iWorld;
layout(location = 1) SMOOTH in vec3 iNormal;
#if defined(SHADING_FLAT)
layout(location = 2) flat in vec3 iColor;
layout(location = 6) flat in vec3 iSpecular;
#else
layout(location = 2) SMOOTH in vec3 iColor;
layout(location = 6) SMOOTH in vec3 iSpecular;
#endif
#ifdef DEPTHMAP
layout(location = 3) in vec4 iLeftClip;
layout(binding = 1) uniform sampler2D uDepthMap;
#endif
#ifdef GS_OUT_FLAG
layout(location = 4) flat in int iFlag;
layout(location = 1) out vec4 oColor1;
#endif
layout(location = 0) out vec4 oColor0;
#if defined(PER_VIEW_EYE) && (defined(VS_KALAIAH) || defined(VS_MULTIVIEW))
layout(location = 8) flat in int iEyeView;
#endif
#ifdef NORMAL_MAPS
// Pixel shading in a frame with normal maps (Renderer::mNormalMaps): the world tangent and the
// normal map (slot bit 16, unit 7: materials.cpp kSlotUnits), linear, through the base colour's
// coordinates and sampler.
layout(location = 9) SMOOTH in vec4 iTangent;
layout(binding = 7) uniform sampler2D uNormalMap;

// lighting.h perturbedNormal(): the texel as a tangent-space normal (2·rgb − 1, x and y ×
// scale) in the frame of n, the tangent made orthogonal to n and the bitangent sign(w) ·
// cross(n, t); a degenerate frame (no tangent: (0, 0, 0, 1)) keeps n.
vec3 perturbedNormal(vec3 n, vec4 tangent, vec3 texel, float scale) {
    n = normalize(n);
    vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
    float tl = length(t);
    if (!(tl > 1e-6)) return n;
    t /= tl;
    vec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    vec3 c = vec3((2.0 * texel.x - 1.0) * scale, (2.0 * texel.y - 1.0) * scale,
                  2.0 * texel.z - 1.0);
    vec3 p = (t * c.x + b * c.y) + n * c.z;
    float pl = length(p);
    return pl > 0.0 ? p / pl : n;
}
#endif
#endif

void main() {
#if defined(PER_VIEW_EYE) && !defined(DEPTH_ONLY)
    // The fragment's view in the frame block (a pass's views: uploadFrameBlock).
#if defined(GS_OUT_LAYER) || defined(VS_INSTANCED_LAYER)
    gEyeView = gl_Layer;
#elif defined(GS_OUT_VIEWPORT)
    gEyeView = gl_ViewportIndex;
#elif defined(GS_OUT_FLAG)
    gEyeView = iFlag;
#elif defined(VS_DIRECT)
    gEyeView = uView;
#else
    gEyeView = iEyeView;
#endif
#endif
    // The base color texture (sampled in uniform control flow: its derivatives choose the
    // mip level) times the material's color and alpha.
    vec4 tex = (uMatFlags.x & 1) != 0 ? texture(uBaseColor, iTexcoord) : vec4(1.0);
#if !defined(DEPTH_ONLY)
    // The other slots (lighting.h SurfaceMaps; an absent one gives its default), sampled here
    // too: in uniform control flow, before any discard. The metallic-roughness map in pixel
    // shading only (vertex and flat shading light the factors alone).
#if defined(SHADING_PIXEL)
    vec2 mapMetalRough = (uMatFlags.x & 2) != 0
                             ? texture(uMetallicRoughnessMap, iTexcoord).bg  // metallic, roughness
                             : vec2(1.0);
#ifdef NORMAL_MAPS
    vec3 mapNormal = (uMatFlags.x & 16) != 0 ? texture(uNormalMap, iTexcoord).rgb
                                             : vec3(0.5, 0.5, 1.0);  // (unused then)
#endif
#endif
    // lighting.h occlusionOf()
    float mapOcclusion = (uMatFlags.x & 4) != 0
                             ? 1.0 + uMatFactors.z * (texture(uOcclusionMap, iTexcoord).r - 1.0)
                             : 1.0;
    vec3 mapEmissive = (uMatFlags.x & 8) != 0 ? texture(uEmissiveMap, iTexcoord).rgb : vec3(1.0);
#endif
#ifdef VERTEX_COLORS
    tex *= iVertexColor;  // glTF's COLOR_0 multiplies the base colour (the soft backend's order)
#endif
    float alpha = uMatFactors.x * tex.a;
    if (uMatFlags.y == 1 && alpha < uMatFactors.y) discard;
    alpha = uMatFlags.y == 2 ? alpha : 1.0;
#if !defined(DEPTH_ONLY)
#ifdef DEPTHMAP
    // sorbier2008 §5.2. Left fragments: the depth map at their own pixel. Right fragments:
    // the depth map at the left-eye pixel of the same surface point (from the left clip
    // position the GS passed along), if it is inside the map; else accepted. The depth
    // compared is the point's left-eye depth (= its right-eye depth on an off-axis rig,
    // whose eyes share the image plane, as the paper says).
    float zLeft = (iLeftClip.z / iLeftClip.w) * 0.5 + 0.5;
    float slope = fwidth(zLeft);
    ivec2 texel;
    float bias;
    if (iFlag == 0) {
        texel = ivec2(gl_FragCoord.xy);
        bias = 1e-6;
    } else {
        vec2 ndc = iLeftClip.xy / iLeftClip.w;
        // Targets are drawn with an upper-left clip origin: window row 0 is NDC y = +1.
        texel = ivec2(floor(vec2(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2(uCounts.zw)));
        // The map holds the depth at the texel centre, the point is anywhere in the texel.
        bias = 1e-6 + slope;
    }
    if (all(greaterThanEqual(texel, ivec2(0))) && all(lessThan(texel, uCounts.zw))) {
        if (zLeft > texelFetch(uDepthMap, texel, 0).r + bias) discard;
    }
#endif
    vec3 c;
#if defined(SHADING_PIXEL)
    if (SPLIT_LIGHTING) {
        vec3 d, sp;
        // The normal map bends the normal lighting sees; shadows keep the surface's own
        // (pipeline.h texturedFragment).
        vec3 litNormal = iNormal;
#ifdef NORMAL_MAPS
        if ((uMatFlags.x & 16) != 0)
            litNormal = perturbedNormal(iNormal, iTangent, mapNormal, uNormalScale);
#endif
        // lighting.h mappedMaterial(): the factors × the metallic-roughness texel; the
        // occlusion texel reaches the environment's light (pipeline.h passes the maps)
        blinnPhongTerms(uMetalRough * mapMetalRough, litNormal, iNormal, iWorld, mapOcclusion, d,
                        sp);
        applySurfaceMaps(d, sp, mapOcclusion, mapEmissive);
        c = finishColor(uMaterial.rgb * tex.rgb * d + sp);
    } else {
        c = shadeBlinnPhong(iNormal, iWorld);
    }
#else
    // lighting.h shadeTextured(): base = albedo × texel.
#if defined(SHADING_FLAT)
    vec3 s = flatSpecular();  // flatTerms' S
#else
    vec3 s = iSpecular;
#endif
    vec3 d = iColor;
    applySurfaceMaps(d, s, mapOcclusion, mapEmissive);
    c = SPLIT_LIGHTING ? finishColor(uMaterial.rgb * tex.rgb * d + s) : iColor;
#endif
#ifdef GS_OUT_FLAG
    // sorbier2008 §4.2: every fragment is written to both MRT attachments; the other eye's
    // gets alpha 0, which the SRC_ALPHA / ONE_MINUS_SRC_ALPHA blend turns into "no change".
    if (iFlag == 0) {
        oColor0 = vec4(c, alpha);
        oColor1 = vec4(0.0);
    } else {
        oColor0 = vec4(0.0);
        oColor1 = vec4(c, alpha);
    }
#else
    oColor0 = vec4(c, alpha);
#endif
#endif
}
)glsl";

const char* const kCompositeVertex = R"glsl(
// A full-screen quad as a 4-vertex triangle strip, no vertex buffer.
void main() {
    vec2 p = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
    gl_Position = vec4(p, 0.0, 1.0);
}
)glsl";

const char* stageName(GLenum stage) {
    switch (stage) {
        case GL_VERTEX_SHADER: return "vertex";
        case GL_GEOMETRY_SHADER: return "geometry";
        case GL_FRAGMENT_SHADER: return "fragment";
        case GL_COMPUTE_SHADER: return "compute";
        default: return "?";
    }
}

Result<Shader> compile(GLenum stage, const std::string& source) {
    Shader s(glCreateShader(stage));
    const char* src = source.c_str();
    glShaderSource(s.get(), 1, &src, nullptr);
    glCompileShader(s.get());
    GLint ok = 0;
    glGetShaderiv(s.get(), GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetShaderiv(s.get(), GL_INFO_LOG_LENGTH, &len);
        std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
        glGetShaderInfoLog(s.get(), len, nullptr, log.data());
        return internalError(
            fmt::format("mvr::gl: {} shader does not compile: {}", stageName(stage), log.c_str()));
    }
    return s;
}

Result<Program> link(std::initializer_list<const Shader*> shaders) {
    Program p(glCreateProgram());
    for (const Shader* s : shaders) glAttachShader(p.get(), s->get());
    glLinkProgram(p.get());
    GLint ok = 0;
    glGetProgramiv(p.get(), GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(p.get(), GL_INFO_LOG_LENGTH, &len);
        std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
        glGetProgramInfoLog(p.get(), len, nullptr, log.data());
        return internalError(fmt::format("mvr::gl: program does not link: {}", log.c_str()));
    }
    if (Status s = checkGlError("linking a program"); !s) return s;
    return p;
}

}  // namespace

void addDefine(ProgramDesc& d, const std::string& name, int value) {
    d.defines += fmt::format("#define {} {}\n", name, value);
}

Result<Program> buildProgram(const ProgramDesc& desc) {
    const std::string head = "#version 450 core\n";
    auto vs =
        compile(GL_VERTEX_SHADER, head + desc.vsExtensions + desc.defines + common() + kVertex);
    if (!vs) return vs.status();
    auto fs = compile(GL_FRAGMENT_SHADER,
                      head + desc.defines + "#define FRAGMENT_STAGE\n" + common() + kFragment);
    if (!fs) return fs.status();
    if (desc.geometry) {
        auto gs = compile(GL_GEOMETRY_SHADER, head + desc.defines + common() + kGeometry);
        if (!gs) return gs.status();
        return link({&vs.value(), &gs.value(), &fs.value()});
    }
    return link({&vs.value(), &fs.value()});
}

Result<Program> buildFullScreenProgram(const std::string& fragmentSource) {
    const std::string head = "#version 450 core\n";
    auto vs = compile(GL_VERTEX_SHADER, head + kCompositeVertex);
    if (!vs) return vs.status();
    auto fs = compile(GL_FRAGMENT_SHADER, head + fragmentSource);
    if (!fs) return fs.status();
    return link({&vs.value(), &fs.value()});
}

Result<Program> buildComputeProgram(const std::string& source) {
    auto cs = compile(GL_COMPUTE_SHADER, "#version 450 core\n" + source);
    if (!cs) return cs.status();
    return link({&cs.value()});
}

}  // namespace mvr::gl::detail
