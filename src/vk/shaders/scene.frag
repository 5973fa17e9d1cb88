#version 450
#define FRAGMENT_STAGE
#include "common.glsl"

layout(location = 3) in vec4 iVertexColor;
layout(location = 5) in vec2 iTexcoord;
// Set 1: the material's texture slots, all with its sampler and the base colour's coordinates
// (a white texel where it has none: white changes nothing in any slot).
layout(set = 1, binding = 0) uniform sampler2D uBaseColor;          // sRGB: sampled in linear
layout(set = 1, binding = 1) uniform sampler2D uMetallicRoughness;  // data: G roughness, B metallic
layout(set = 1, binding = 2) uniform sampler2D uOcclusion;          // data: R
layout(set = 1, binding = 3) uniform sampler2D uEmissive;           // sRGB: sampled in linear
// data: a tangent-space normal; white is no neutral normal, so SLOT_NORMAL selects it
layout(set = 1, binding = 4) uniform sampler2D uNormalMap;
#if defined(SHADING_PIXEL)
layout(location = 0) in vec3 iWorld;
layout(location = 1) in vec3 iNormal;
layout(location = 6) flat in int iView;  // the request's index of the fragment's view
layout(location = 7) in vec4 iTangent;   // world tangent, handedness ((0, 0, 0, 1): none)
#elif defined(SHADING_FLAT)
layout(location = 2) flat in vec3 iColor;
#else
layout(location = 2) in vec3 iColor;
layout(location = 4) in vec3 iSpecular;
#endif
layout(location = 0) out vec4 oColor0;

void main() {
#if defined(SHADING_PIXEL)
    gShadingEye = uCounts.z != 0 ? uViewEye[iView].xyz : uCenterEye.xyz;
#else
    gShadingEye = uCenterEye.xyz;
#endif
    InstanceData m = uInstances[pc.instance];
    // Every slot is sampled in uniform control flow, before the mask's discard (their
    // derivatives choose the mip level), then selected by the material's slots.
    int slots = m.flags.x;
    vec4 vc = texture(uBaseColor, iTexcoord);
    vec4 mrTexel = texture(uMetallicRoughness, iTexcoord);
    float occlusionTexel = texture(uOcclusion, iTexcoord).r;
    vec3 emissiveTexel = texture(uEmissive, iTexcoord).rgb;
    vec3 normalTexel = texture(uNormalMap, iTexcoord).rgb;
    // The base colour texture times glTF's COLOR_0, times the material's colour and alpha (gl's
    // and the soft backend's order).
    bool colored = m.flags.w != 0;
    bool split = slots != 0 || colored;
    if ((slots & SLOT_BASE_COLOR) == 0) vc = vec4(1.0);
    if (colored) vc *= iVertexColor;
    float alpha = m.params.y * vc.a;
    if (m.flags.y == 1 && alpha < m.params.z) discard;
    alpha = m.flags.y == 2 ? alpha : 1.0;
    vec3 base = m.material.rgb * vc.rgb;
    // lighting.h SurfaceMaps: an absent slot's defaults change nothing.
    bool mapped = (slots & SLOT_METALLIC_ROUGHNESS) != 0;
    float mapRoughness = mapped ? mrTexel.g : 1.0;
    float mapMetallic = mapped ? mrTexel.b : 1.0;
    float occlusion = (slots & SLOT_OCCLUSION) != 0
                          ? 1.0 + m.params.w * (occlusionTexel - 1.0)  // lighting.h occlusionOf
                          : 1.0;
    vec3 emissive = (slots & SLOT_EMISSIVE) != 0 ? emissiveTexel : vec3(1.0);
#if defined(SHADING_PIXEL)
    vec3 c;
    if (split) {
        // lighting.h metallicRoughnessTerms' `maps`: pixel shading lights the factors × the
        // metallic-roughness texel (vertex and flat shading the factors alone).
        InstanceData mm = m;
        mm.pbr.x = m.pbr.x * mapMetallic;
        mm.pbr.y = m.pbr.y * mapRoughness;
        // The normal map (lighting.h perturbedNormal, pixel shading only) bends the normal
        // the lighting sees; shadows look up with the surface's own (raster/pipeline.h).
        vec3 lit = iNormal;
        if ((slots & SLOT_NORMAL) != 0)
            lit = perturbedNormal(iNormal, iTangent, normalTexel, m.pbr.w);
        // The occlusion (1 without the slot) also scales the environment's light
        // (lighting.h environmentTerms; raster/pipeline.h passes the maps with either slot).
        vec3 d, sp;
        blinnPhongTerms(mm, lit, iNormal, iWorld, occlusion, d, sp);
        applySurfaceMaps(m, occlusion, emissive, d, sp);
        c = finishColor(base * d + sp);
    } else {
        c = shadeBlinnPhong(m, iNormal, iWorld);
    }
#else
    vec3 c = iColor;
    if (split) {
        vec3 d = iColor;
#if defined(SHADING_FLAT)
        vec3 sp = flatSpecular(m);
#else
        vec3 sp = iSpecular;
#endif
        applySurfaceMaps(m, occlusion, emissive, d, sp);
        c = finishColor(base * d + sp);
    }
#endif
    oColor0 = vec4(c, alpha);
}
