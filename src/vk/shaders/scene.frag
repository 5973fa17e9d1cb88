#version 450
#define FRAGMENT_STAGE
#include "common.glsl"

layout(location = 3) in vec4 iVertexColor;
layout(location = 5) in vec2 iTexcoord;
layout(set = 1, binding = 0) uniform sampler2D uBaseColor;  // sRGB: sampled in linear
#if defined(SHADING_PIXEL)
layout(location = 0) in vec3 iWorld;
layout(location = 1) in vec3 iNormal;
layout(location = 6) flat in int iView;  // the request's index of the fragment's view
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
    // The base colour texture (sampled in uniform control flow: its derivatives choose the mip
    // level; untextured instances bind a white texel) times glTF's COLOR_0, times the
    // material's colour and alpha (gl's and the soft backend's order).
    bool colored = m.flags.w != 0;
    bool split = m.flags.x != 0 || colored;
    vec4 vc = texture(uBaseColor, iTexcoord);
    if (m.flags.x == 0) vc = vec4(1.0);
    if (colored) vc *= iVertexColor;
    float alpha = m.params.y * vc.a;
    if (m.flags.y == 1 && alpha < m.params.z) discard;
    alpha = m.flags.y == 2 ? alpha : 1.0;
    vec3 base = m.material.rgb * vc.rgb;
#if defined(SHADING_PIXEL)
    vec3 c;
    if (split) {
        vec3 d, sp;
        blinnPhongTerms(m, iNormal, iWorld, d, sp);
        c = finishColor(base * d + sp);
    } else {
        c = shadeBlinnPhong(m, iNormal, iWorld);
    }
#elif defined(SHADING_FLAT)
    vec3 c = split ? finishColor(base * iColor + flatSpecular(m)) : iColor;
#else
    vec3 c = split ? finishColor(base * iColor + iSpecular) : iColor;
#endif
    oColor0 = vec4(c, alpha);
}
