// Shared by scene.vert and scene.frag: the frame and instance buffers and lighting.h in GLSL
// (the gl backend's shaders.cpp, line for line).
#define MAX_VIEWS 128
#define MAX_LIGHTS 4

layout(std430, set = 0, binding = 0) readonly buffer FrameData {
    vec4 uLightDir[MAX_LIGHTS];    // unit, toward the light (spot: −axis)
    vec4 uLightColor[MAX_LIGHTS];
    vec4 uLightPos[MAX_LIGHTS];    // xyz position, w: 0 directional, 1 point, 2 spot
    vec4 uLightCone[MAX_LIGHTS];   // x range (0 = infinite), y cos inner, z cos outer
    vec4 uAmbient;
    vec4 uCenterEye;
    ivec4 uCounts;                 // x lights, y views, z per-view eye, w image lighting
    mat4 uClipFromWorld[MAX_VIEWS];
    // Shadows (shadows.h, gl's uShadowClip / uShadowInfo / uShadowTexel): per light its map's
    // clipFromWorld, (layer (< 0: none), perspective, near, far), (texelWorld, size).
    mat4 uShadowClip[MAX_LIGHTS];
    vec4 uShadowInfo[MAX_LIGHTS];
    vec4 uShadowTexel[MAX_LIGHTS];
    vec4 uViewEye[MAX_VIEWS];      // each view's eye (--specular per-view: uCounts.z = 1)
    // Image lighting (environment.h Environment::sh, uCounts.w = 1): the 9 SH coefficients
    // of diffuseLight, rgb, in Environment::sh's order.
    vec4 uEnvSh[9];
};

// The eye shading looks from (lighting.h SpecularEye): the rig's centre eye, or in the fragment
// shader (pixel shading, --specular per-view) the fragment's view's, which main() sets first.
#ifdef FRAGMENT_STAGE
vec3 gShadingEye;
#define SHADING_EYE gShadingEye
#else
#define SHADING_EYE (uCenterEye.xyz)
#endif
// Linear distances, one layer per map (a 1x1 layer no light reads when there are none).
layout(set = 0, binding = 2) uniform sampler2DArray uShadowMaps;
// Image lighting (environment.h; uCounts.w = 1, else a 1x1 image bound to both, never read):
// Environment::levels as mip levels 0..5 of one equirectangular image (linear, linear mipmaps,
// REPEAT in u, CLAMP_TO_EDGE in v) and splitSumTable() as a 32x32 RG image (linear, clamped;
// u = n.v, v = roughness, row 0 = roughness 0).
layout(set = 0, binding = 3) uniform sampler2D uEnvironment;
layout(set = 0, binding = 4) uniform sampler2D uSplitSum;

struct InstanceData {
    mat4 worldFromModel;
    mat4 normalFromModel;  // inverse transpose (upper 3x3)
    mat4 cofactor;         // model edge cross -> world edge cross
    vec4 material;         // albedo rgb, specular
    vec4 params;           // x shininess, y alpha, z mask cutoff, w occlusion strength
    ivec4 flags;           // x texture slots (SLOT_* bits; any: the lighting split into D and S),
                           // y alpha mode (0 opaque, 1 mask, 2 blend), z double-sided,
                           // w vertex colours (lighting split into D and S, as gl's SPLIT_LIGHTING)
    vec4 pbr;              // x metallic, y roughness, z MaterialModel (0 Blinn-Phong, 1
                           // metallic-roughness, 2 unlit), w the normal map's scale
    vec4 emissive;         // rgb (model 1), w: −1 where worldFromModel mirrors (its linear
                           // part's determinant < 0: the tangent's handedness flips), else 1
};
layout(std430, set = 0, binding = 1) readonly buffer Instances { InstanceData uInstances[]; };
// InstanceData.flags.x: the texture slots a material samples (batches.cpp kSlot*; set 1's
// bindings 0 to 4 in this order).
#define SLOT_BASE_COLOR 1
#define SLOT_METALLIC_ROUGHNESS 2
#define SLOT_OCCLUSION 4
#define SLOT_EMISSIVE 8
#define SLOT_NORMAL 16

layout(push_constant) uniform Push {
    int instance;
    int viewBase;  // the request's index of this pass's view 0 (multipass: the view)
} pc;

// shadows.h shadowFactor(), as gl's shaders.cpp has it line for line.
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
    if (uLightPos[i].w > 0.5) {  // point / spot
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

vec3 facingNormal(InstanceData m, vec3 n, vec3 p) {
    return (m.flags.z != 0 && dot(n, SHADING_EYE - p) < 0.0) ? -n : n;
}

// Image lighting, environment.h's lookups and lighting.h environmentTerms() line for line.
#define ENV_LEVELS 6  // Environment::kLevels
#define ENV_PI 3.14159265358979

bool hasEnvironment() { return uCounts.w != 0; }

// environment.h equirectUv(): u = 0.5 + atan2(d.x, −d.z) / 2π, v = 0.5 − asin(d.y) / π.
vec2 equirectUv(vec3 d) {
    float lon = (d.x == 0.0 && d.z == 0.0) ? 0.0 : atan(d.x, -d.z);  // straight up / down
    float lat = asin(clamp(d.y, -1.0, 1.0));
    return vec2(0.5 + lon * (0.5 / ENV_PI), 0.5 - lat * (1.0 / ENV_PI));
}

// environment.h diffuseLight(): the SH irradiance at unit normal n, at least 0.
vec3 diffuseLight(vec3 n) {
    vec3 e = uEnvSh[0].rgb * 0.282095;
    e += (uEnvSh[1].rgb * n.y + uEnvSh[2].rgb * n.z + uEnvSh[3].rgb * n.x) * 0.488603;
    e += (uEnvSh[4].rgb * (n.x * n.y) + uEnvSh[5].rgb * (n.y * n.z) +
          uEnvSh[7].rgb * (n.x * n.z)) * 1.092548;
    e += uEnvSh[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0));
    e += uEnvSh[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// environment.h prefiltered(): the mip chain at λ = roughness · (kLevels − 1) (explicit: the
// same in the vertex and fragment stages).
vec3 prefiltered(vec3 r, float roughness) {
    return textureLod(uEnvironment, equirectUv(r),
                      clamp(roughness, 0.0, 1.0) * float(ENV_LEVELS - 1)).rgb;
}

// environment.h splitSum(): (A, B) at n.v and roughness, bilinear, clamped.
vec2 splitSum(float nv, float roughness) {
    return textureLod(uSplitSum, vec2(clamp(nv, 0.0, 1.0), clamp(roughness, 0.0, 1.0)), 0.0).rg;
}

// environment.h roughnessOfShininess(): α² = 2 / (s + 2), r = √α.
float roughnessOfShininess(float s) { return sqrt(sqrt(2.0 / (max(s, 0.0) + 2.0))); }

// lighting.h environmentTerms(): unit lit normal n, unit v toward the shading eye; metal and
// rough a metallic-roughness material's (maps applied), occlusion the occlusion map's.
void environmentTerms(InstanceData m, vec3 n, vec3 v, float metal, float rough, float occlusion,
                      out vec3 diffuse, out vec3 specular) {
    float ndotv = dot(n, v);
    vec3 r = n * (2.0 * ndotv) - v;
    bool blinnPhong = m.pbr.z != 1.0;
    float roughness = blinnPhong ? roughnessOfShininess(m.params.x) : rough;
    vec3 e = diffuseLight(n);
    vec3 p = prefiltered(r, roughness);
    vec2 ab = splitSum(abs(ndotv), roughness);
    float fd = 0.04 * ab.x + ab.y;
    if (blinnPhong) {
        diffuse = e * occlusion;
        specular = p * (occlusion * m.material.w * fd);
    } else {
        diffuse = ((1.0 - metal) * (1.0 - fd) * e + (metal * ab.x) * p) * occlusion;
        specular = p * (occlusion * ((1.0 - metal) * fd + metal * ab.y));
    }
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
vec3 flatSpecular(InstanceData m) { return m.pbr.z == 1.0 ? m.emissive.rgb : vec3(0.0); }

vec3 shadeFlat(InstanceData m, vec3 faceNormal, vec3 p) {
    if (m.pbr.z == 2.0) return finishColor(m.material.rgb);
    vec3 n0 = faceNormal;
    faceNormal = facingNormal(m, faceNormal, p);
    vec3 albedo = m.material.rgb;
    vec3 c = uAmbient.rgb * albedo;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, p, l);
        c += (max(dot(faceNormal, l), 0.0) * albedo * lc) * shadowFactor(i, p, n0);
    }
    if (hasEnvironment()) c += diffuseLight(faceNormal) * albedo;
    return finishColor(c + flatSpecular(m));
}

// lighting.h metallicRoughnessTerms(), as gl's shaders.cpp has it.
// `shadowNormal`: the normal shadowFactor offsets by (the surface's own where a normal map bent
// `normal`, pixel shading; else `normal`).
// `occlusion`: the occlusion map's, for the environment's light (1 without a map or per vertex).
void metallicRoughnessTerms(InstanceData m, vec3 normal, vec3 shadowNormal, vec3 worldPos,
                            float occlusion, out vec3 diffuse, out vec3 specular) {
    vec3 n = normalize(facingNormal(m, normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    float metal = clamp(m.pbr.x, 0.0, 1.0);
    float rough = clamp(m.pbr.y, 0.0, 1.0);
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
    if (hasEnvironment()) {
        vec3 ed, es;
        environmentTerms(m, n, v, metal, rough, occlusion, ed, es);
        diffuse += ed;
        specular += es;
    }
    specular += m.emissive.rgb;
}

vec3 shadeBlinnPhong(InstanceData m, vec3 normal, vec3 worldPos) {
    if (m.pbr.z == 1.0) {
        vec3 d, sp;
        metallicRoughnessTerms(m, normal, normal, worldPos, 1.0, d, sp);
        return finishColor(m.material.rgb * d + sp);
    }
    if (m.pbr.z == 2.0) return finishColor(m.material.rgb);
    vec3 albedo = m.material.rgb;
    vec3 n = normalize(facingNormal(m, normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    vec3 c = uAmbient.rgb * albedo;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, worldPos, l);
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + v);
            float spec = m.material.w * pow(max(dot(n, h), 0.0), m.params.x);
            c += ((nl * albedo + vec3(spec)) * lc) * shadowFactor(i, worldPos, normal);
        }
    }
    if (hasEnvironment()) {
        vec3 ed, es;
        environmentTerms(m, n, v, 0.0, 0.0, 1.0, ed, es);
        c += albedo * ed + es;
    }
    return finishColor(c);
}

// Meshes with vertex colours (lighting.h LightTerms, gl's SPLIT_LIGHTING): the colour varies
// across the triangle, so the lighting is kept as D (ambient + sum of max(n.l, 0) light, which
// multiplies albedo x vertex colour) and S (the specular sum, added): clamp(base * D + S).
vec3 flatDiffuse(InstanceData m, vec3 faceNormal, vec3 p) {
    if (m.pbr.z == 2.0) return vec3(1.0);
    vec3 n0 = faceNormal;
    faceNormal = facingNormal(m, faceNormal, p);
    vec3 d = uAmbient.rgb;
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, p, l);
        d += (max(dot(faceNormal, l), 0.0) * lc) * shadowFactor(i, p, n0);
    }
    if (hasEnvironment()) d += diffuseLight(faceNormal);
    return d;
}

// `shadowNormal` and `occlusion` as metallicRoughnessTerms'.
void blinnPhongTerms(InstanceData m, vec3 normal, vec3 shadowNormal, vec3 worldPos,
                     float occlusion, out vec3 diffuse, out vec3 specular) {
    if (m.pbr.z == 1.0) {
        metallicRoughnessTerms(m, normal, shadowNormal, worldPos, occlusion, diffuse, specular);
        return;
    }
    if (m.pbr.z == 2.0) {
        diffuse = vec3(1.0);
        specular = vec3(0.0);
        return;
    }
    vec3 n = normalize(facingNormal(m, normal, worldPos));
    vec3 v = normalize(SHADING_EYE - worldPos);
    diffuse = uAmbient.rgb;
    specular = vec3(0.0);
    for (int i = 0; i < uCounts.x; ++i) {
        vec3 l;
        vec3 lc = lightAt(i, worldPos, l);
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + v);
            float spec = m.material.w * pow(max(dot(n, h), 0.0), m.params.x);
            lc *= shadowFactor(i, worldPos, shadowNormal);
            diffuse += nl * lc;
            specular += spec * lc;
        }
    }
    if (hasEnvironment()) {
        vec3 ed, es;
        environmentTerms(m, n, v, 0.0, 0.0, occlusion, ed, es);
        diffuse += ed;
        specular += es;
    }
}

// lighting.h applySurfaceMaps(): a lit fragment's terms under its texture maps, in every
// shading (D and S computed without them): the occlusion scales the ambient term, a
// metallic-roughness material's emissive (held once in S) the emissive texel. Unlit: unchanged.
void applySurfaceMaps(InstanceData m, float occlusion, vec3 emissiveTexel, inout vec3 diffuse,
                      inout vec3 specular) {
    if (m.pbr.z == 2.0) return;
    diffuse -= uAmbient.rgb * (1.0 - occlusion);
    if (m.pbr.z == 1.0) specular += m.emissive.rgb * (emissiveTexel - vec3(1.0));
}

// lighting.h perturbedNormal(): the normal map's texel (linear RGB) as a tangent-space normal
// c = 2·rgb − 1 with c.x, c.y × scale, in the frame of the interpolated normal n, the tangent
// made orthogonal to n (Gram-Schmidt) and the bitangent sign(w) · cross(n, t); a degenerate
// tangent (none: (0, 0, 0, 1)) keeps n.
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
