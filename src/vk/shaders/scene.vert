#version 450
// Defines: SHADING_FLAT | SHADING_VERTEX | SHADING_PIXEL and VIEW_PASS | VIEW_MULTIVIEW |
// VIEW_LAYER (where the view index comes from: the push constant, gl_ViewIndex, the instance).
#ifdef VIEW_MULTIVIEW
#extension GL_EXT_multiview : require
#endif
#ifdef VIEW_LAYER
#extension GL_ARB_shader_viewport_layer_array : require
#endif
#include "common.glsl"

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;      // flat: the face's model-space edge cross product
#ifdef SHADING_FLAT
layout(location = 2) in vec3 aFaceCenter;  // the face's model-space centroid
#endif
layout(location = 3) in vec4 aColor;       // linear RGBA (Mesh::colors; white if none)
layout(location = 4) in vec2 aTexcoord;    // Mesh::texcoords (0, 0 if none)
#ifdef SHADING_PIXEL
layout(location = 5) in vec4 aTangent;     // Mesh::tangents ((0, 0, 0, 1) if none: binding 1)
#endif

// Only what the fragment shader reads (validation: no output it does not consume).
layout(location = 3) out vec4 oVertexColor;
layout(location = 5) out vec2 oTexcoord;
#ifdef SHADING_PIXEL
layout(location = 0) out vec3 oWorld;
layout(location = 1) out vec3 oNormal;
layout(location = 6) flat out int oView;  // --specular per-view: the view's eye (scene.frag)
layout(location = 7) out vec4 oTangent;   // world tangent, handedness (the normal map's frame)
#elif defined(SHADING_FLAT)
layout(location = 2) flat out vec3 oColor;
#else
layout(location = 2) out vec3 oColor;
layout(location = 4) out vec3 oSpecular;
#endif

void main() {
    InstanceData m = uInstances[pc.instance];
    vec4 world = m.worldFromModel * vec4(aPosition, 1.0);
    oVertexColor = aColor;
    oTexcoord = aTexcoord;
    // Any texture slot (scene.h hasTexture) or vertex colours: the lighting split into D and S
    // (the base colour varies, or the maps apply to the terms: scene.frag).
    bool split = m.flags.x != 0 || m.flags.w != 0;
#if defined(SHADING_PIXEL)
    oWorld = world.xyz;
    oNormal = mat3(m.normalFromModel) * aNormal;
    // raster/pipeline.h worldTangent(): the direction through the model's linear part, the
    // handedness flipped by a mirroring one (emissive.w: the sign of its determinant).
    oTangent = vec4(mat3(m.worldFromModel) * aTangent.xyz,
                    m.emissive.w < 0.0 ? -aTangent.w : aTangent.w);
#elif defined(SHADING_VERTEX)
    if (split) {
        vec3 n = mat3(m.normalFromModel) * aNormal;
        blinnPhongTerms(m, n, n, world.xyz, 1.0, oColor, oSpecular);
    } else {
        oColor = shadeBlinnPhong(m, mat3(m.normalFromModel) * aNormal, world.xyz);
        oSpecular = vec3(0.0);
    }
#elif defined(SHADING_FLAT)
    // Every corner of a flat triangle carries the same face data (the vertices are unrolled).
    vec3 fn = normalize(mat3(m.cofactor) * aNormal);
    vec3 centre = (m.worldFromModel * vec4(aFaceCenter, 1.0)).xyz;
    oColor = split ? flatDiffuse(m, fn, centre) : shadeFlat(m, fn, centre);
#endif
#if defined(VIEW_PASS)
    int view = pc.viewBase;
#elif defined(VIEW_MULTIVIEW)
    int view = pc.viewBase + int(gl_ViewIndex);
#else
    int view = pc.viewBase + gl_InstanceIndex;
    gl_Layer = gl_InstanceIndex;
#endif
#ifdef SHADING_PIXEL
    oView = view;
#endif
    vec4 clip = uClipFromWorld[view] * world;
    // mvr's clip space is OpenGL's (z in [-w, w], +y up): Vulkan's y points down and its depth
    // is z in [0, w], so window depth = z/2w + 1/2 and row 0 is the top, as image.h wants.
    gl_Position = vec4(clip.x, -clip.y, 0.5 * (clip.z + clip.w), clip.w);
}
