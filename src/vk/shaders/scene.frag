#version 450
#include "common.glsl"

#if defined(SHADING_PIXEL)
layout(location = 0) in vec3 iWorld;
layout(location = 1) in vec3 iNormal;
#elif defined(SHADING_FLAT)
layout(location = 2) flat in vec3 iColor;
#else
layout(location = 2) in vec3 iColor;
#endif
layout(location = 0) out vec4 oColor0;

void main() {
    InstanceData m = uInstances[pc.instance];
    float alpha = m.params.y;
    if (m.flags.y == 1 && alpha < m.params.z) discard;
    alpha = m.flags.y == 2 ? alpha : 1.0;
#if defined(SHADING_PIXEL)
    vec3 c = shadeBlinnPhong(m, iNormal, iWorld);
#else
    vec3 c = iColor;
#endif
    oColor0 = vec4(c, alpha);
}
