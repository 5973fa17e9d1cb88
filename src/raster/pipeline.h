// src/raster/pipeline.h — the pieces both soft methods are built from: vertex transform,
// homogeneous clipping, projection and snapping, triangle setup, coverage and fragment shading.
//
// Bit-exactness between "multipass" and "unified" rests on one rule: every value that reaches a
// pixel is computed by the SAME function below from the SAME inputs, in the same operation order;
// "unified" only computes a value once where its inputs are identical for several views.
// All raster sources are compiled with -ffp-contract=off so that no a*b+c is fused in one
// translation unit and not in another (scalar vs AVX files would otherwise differ in the last bit).
//
// Fixed point: window coordinates in 1/256 pixel ("24.8" in an int32: the guard band keeps
// |x_w|, |y_w| < 2^20 px for images up to 16384 px). Edge functions are exact in int64
// (|Δ| < 2^29, products < 2^58).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include "mvr/core/lighting.h"
#include "mvr/core/render.h"
#include "mvr/core/shadows.h"
#include "mvr/core/texture_sampling.h"

namespace mvr::raster::detail {

inline constexpr int kSubpixelBits = 8;
inline constexpr int kSubpixel = 1 << kSubpixelBits;
inline constexpr int kHalfSubpixel = kSubpixel / 2;
/// The int32 coverage path (rasterSmallTriangle, setupViews / setupLanes masks) takes a
/// triangle whose CLAMPED box holds at most 2×2 pixel centres only when its UNCLAMPED box is
/// also narrower and lower than this (1/256 px units, 64 px): its coordinates relative to a
/// centre inside the box are then below 2^14, every edge product below 2^28 and every sum of
/// them inside int32. A large triangle of which only a corner is in the image, or in the band,
/// takes the int64 walk instead (its edge values overflowed int32 there: UBSan).
inline constexpr std::int32_t kSmallSpan = 1 << 14;
/// Guard band in NDC units: triangles are clipped against |x|, |y| ≤ kGuardBand·w only.
inline constexpr float kGuardBand = 64.0f;
/// Attributes interpolated per fragment: Vertex = color (3), Pixel = normal + world position (6);
/// in a textured frame (FrameContext::textured) Flat = uv (2), Vertex = LightTerms D, S + uv (8),
/// Pixel = normal + world position + uv (8); a frame with vertex colours (FrameContext::colored,
/// always textured) adds the vertex's linear RGBA (4) after the uv; a pixel-shaded frame with
/// normal maps (FrameContext::tangents) the world tangent and its handedness (4) after those.
inline constexpr int kMaxAttrs = 16;
/// A triangle clipped by 6 planes has at most 3 + 6 vertices.
inline constexpr int kMaxPolyVerts = 9;

inline int attributeCount(Shading s, bool textured = false, bool colored = false,
                          bool tangents = false) {
    if (textured)
        return (s == Shading::Flat ? 2 : 8) + (colored ? 4 : 0) +
               (tangents && s == Shading::Pixel ? 4 : 0);
    return s == Shading::Vertex ? 3 : s == Shading::Pixel ? 6 : 0;
}
/// Where the texture coordinates start in a textured frame's attributes.
inline constexpr int uvAttribute(Shading s) { return s == Shading::Flat ? 0 : 6; }
/// Where the vertex colour starts in a coloured frame's attributes.
inline constexpr int colorAttribute(Shading s) { return uvAttribute(s) + 2; }
/// Where the tangent starts in a pixel-shaded frame with tangents.
inline constexpr int tangentAttribute(bool colored) { return colored ? 12 : 8; }


// ---- outcodes --------------------------------------------------------------------------------
// Clip planes, in the order the clipper applies them. Near, far, bottom and top involve only
// (y, z, w) and are therefore shared by the views of an off-axis row (adelson1991's
// Liang–Barsky observation); left and right involve x and are per view.
enum : std::uint8_t {
    kClipNear = 1 << 0,    ///< z < −w
    kClipFar = 1 << 1,     ///< z > w
    kClipBottom = 1 << 2,  ///< y < −G·w  (guard band)
    kClipTop = 1 << 3,     ///< y > G·w
    kClipLeft = 1 << 4,    ///< x < −G·w
    kClipRight = 1 << 5,   ///< x > G·w
    kOutBottom = 1 << 6,   ///< y < −w   (outside the viewport: trivial reject only)
    kOutTop = 1 << 7,      ///< y > w
};
// x-side viewport outcodes live in a second byte for per-view codes (bits reuse the layout).
enum : std::uint8_t {
    kOutLeft = 1 << 6,   ///< x < −w
    kOutRight = 1 << 7,  ///< x > w
};
inline constexpr std::uint8_t kClipYZW = kClipNear | kClipFar | kClipBottom | kClipTop;
inline constexpr std::uint8_t kRejectYZW = kClipNear | kClipFar | kOutBottom | kOutTop;
inline constexpr std::uint8_t kClipX = kClipLeft | kClipRight;
inline constexpr std::uint8_t kRejectX = kOutLeft | kOutRight;

/// Outcode bits of (y, z, w): near, far, guard bottom/top, viewport bottom/top.
inline std::uint8_t outcodeYZW(float y, float z, float w) {
    std::uint8_t c = 0;
    if (z < -w) c |= kClipNear;
    if (z > w) c |= kClipFar;
    if (y < -kGuardBand * w) c |= kClipBottom;
    if (y > kGuardBand * w) c |= kClipTop;
    if (y < -w) c |= kOutBottom;
    if (y > w) c |= kOutTop;
    // w ≤ 0 (or NaN) cannot be projected: send the triangle to the clipper, which drops
    // polygons that still have such a vertex after clipping.
    if (!(w > 0.0f)) c |= kClipNear;
    return c;
}
/// Outcode bits of (x, w): guard left/right, viewport left/right.
inline std::uint8_t outcodeX(float x, float w) {
    std::uint8_t c = 0;
    if (x < -kGuardBand * w) c |= kClipLeft;
    if (x > kGuardBand * w) c |= kClipRight;
    if (x < -w) c |= kOutLeft;
    if (x > w) c |= kOutRight;
    return c;
}

// ---- vertex stage --------------------------------------------------------------------------------
/// m · (p, 1) with a fixed operation order ((m0·x + m1·y) + m2·z) + m3, so that the scalar and
/// SIMD vertex kernels agree bit for bit.
inline glm::vec4 transformPoint(const glm::mat4& m, const glm::vec3& p) {
    glm::vec4 r;
    for (int i = 0; i < 4; ++i) r[i] = ((m[0][i] * p.x + m[1][i] * p.y) + m[2][i] * p.z) + m[3][i];
    return r;
}
inline glm::vec3 transformDir(const glm::mat3& m, const glm::vec3& n) {
    glm::vec3 r;
    for (int i = 0; i < 3; ++i) r[i] = (m[0][i] * n.x + m[1][i] * n.y) + m[2][i] * n.z;
    return r;
}
/// A model-space tangent (Mesh::tangents) in world space: its direction through the model's
/// linear part, its handedness flipped by a mirroring one (the bitangent is a cross product).
inline glm::vec4 worldTangent(const glm::mat4& worldFromModel, const glm::vec4& t) {
    const glm::mat3 m(worldFromModel);
    const float w = glm::determinant(m) < 0.0f ? -t.w : t.w;
    return glm::vec4(transformDir(m, glm::vec3(t)), w);
}
/// The off-axis shear of kalaiah2007/nvidia-gtc2010: clip.x += shear · (clip.w − convergence).
/// shearClip with w − convergence already formed (one subtraction per vertex for all views):
/// the same operations, so the same bits.
inline float shearClipWc(float centerClip, float shear, float wMinusConvergence) {
    return centerClip + shear * wMinusConvergence;
}
inline float shearClip(float centerClip, float shear, float w, float convergence) {
    return shearClipWc(centerClip, shear, w - convergence);
}

/// Per-vertex shading attributes (the view-independent vertex outputs of kalaiah2007).
/// Vertex: Blinn-Phong color; Pixel: world normal (not normalized) and world position.
inline void vertexAttributes(Shading shading, const ShadingContext& ctx, const Material& material,
                             const glm::vec3& worldPos, const glm::vec3& worldNormal, float* out) {
    if (shading == Shading::Vertex) {
        float sh[kMaxLights];
        const glm::vec3 c =
            shadeBlinnPhong(ctx, material, worldNormal, worldPos,
                            shadowFactors(ctx.shadows, ctx.lights, worldPos, worldNormal, sh));
        out[0] = c.x, out[1] = c.y, out[2] = c.z;
    } else if (shading == Shading::Pixel) {
        out[0] = worldNormal.x, out[1] = worldNormal.y, out[2] = worldNormal.z;
        out[3] = worldPos.x, out[4] = worldPos.y, out[5] = worldPos.z;
    }
}

/// A textured frame's vertex attributes (see kMaxAttrs): Vertex: blinnPhongTerms' D and S;
/// Pixel: the normal and world position; then the texture coordinates (all modes); then, in a
/// coloured frame (`colored`), the vertex colour (`color`, or opaque white when null); then, in
/// a pixel-shaded frame with tangents (`tangent` not null), the world tangent (worldTangent).
inline void texturedVertexAttributes(Shading shading, const ShadingContext& ctx,
                                     const Material& material, const glm::vec3& worldPos,
                                     const glm::vec3& worldNormal, glm::vec2 uv, bool colored,
                                     const glm::vec4* color, float* out,
                                     const glm::vec4* tangent = nullptr) {
    if (shading == Shading::Vertex) {
        float sh[kMaxLights];
        const LightTerms t =
            blinnPhongTerms(ctx, material, worldNormal, worldPos,
                            shadowFactors(ctx.shadows, ctx.lights, worldPos, worldNormal, sh));
        out[0] = t.diffuse.x, out[1] = t.diffuse.y, out[2] = t.diffuse.z;
        out[3] = t.specular.x, out[4] = t.specular.y, out[5] = t.specular.z;
    } else if (shading == Shading::Pixel) {
        out[0] = worldNormal.x, out[1] = worldNormal.y, out[2] = worldNormal.z;
        out[3] = worldPos.x, out[4] = worldPos.y, out[5] = worldPos.z;
    }
    const int k = uvAttribute(shading);
    out[k] = uv.x, out[k + 1] = uv.y;
    if (colored) {
        const glm::vec4 c = color ? *color : glm::vec4(1.0f);
        out[k + 2] = c.x, out[k + 3] = c.y, out[k + 4] = c.z, out[k + 5] = c.w;
    }
    if (tangent && shading == Shading::Pixel) {
        const int j = tangentAttribute(colored);
        out[j] = tangent->x, out[j + 1] = tangent->y, out[j + 2] = tangent->z;
        out[j + 3] = tangent->w;
    }
}

inline std::uint32_t packColor(const glm::vec3& c) {
    return std::uint32_t(quantizeUnorm8(c.x)) | (std::uint32_t(quantizeUnorm8(c.y)) << 8) |
           (std::uint32_t(quantizeUnorm8(c.z)) << 16) | 0xff000000u;
}

/// The triangle's world-space unit face normal (0 for a degenerate one).
inline glm::vec3 faceNormal(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
    const float len = glm::length(n);
    return (len > 0.0f && std::isfinite(len)) ? n / len : glm::vec3(0.0f);
}
/// The triangle's centroid: where Flat evaluates point and spot lights (lighting.h).
inline glm::vec3 centroid(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    return ((p0 + p1) + p2) * (1.0f / 3.0f);
}
/// Flat shading: one color per triangle from its world-space face normal (lighting.h).
inline std::uint32_t flatColor(const ShadingContext& ctx, const Material& material,
                               const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2) {
    const glm::vec3 unit = faceNormal(p0, p1, p2);
    const glm::vec3 c = centroid(p0, p1, p2);
    // Shadows (issue 15): one factor per triangle, at its centroid (flat = one color).
    float sh[kMaxLights];
    const float* shadow = shadowFactors(ctx.shadows, ctx.lights, c, unit, sh);
    return packColor(shadeFlat(ctx, material, unit, c, shadow));
}

/// Vertex lighting with shadows (issue 15): the Kernels::shadeVertices of a frame with shadow
/// maps (scalar: the lookup is not vectorized), the same for every method.
inline void shadeVerticesShadowed(const glm::vec3* positions, const glm::vec3* normals,
                                  std::size_t n, const glm::mat4& worldFromModel,
                                  const glm::mat3& normalFromModel, const ShadingContext& ctx,
                                  const Material& material, float* color) {
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 world = glm::vec3(transformPoint(worldFromModel, positions[i]));
        const glm::vec3 normal = transformDir(normalFromModel, normals[i]);
        float sh[kMaxLights];
        const glm::vec3 c =
            shadeBlinnPhong(ctx, material, normal, world,
                            shadowFactors(ctx.shadows, ctx.lights, world, normal, sh));
        color[3 * i] = c.x, color[3 * i + 1] = c.y, color[3 * i + 2] = c.z;
    }
}

// ---- back faces ----------------------------------------------------------------------------
/// det[x, y, w] of a triangle's clip positions: > 0 ⇔ counter-clockwise (front) on screen.
inline float det3(const float x[3], const float y[3], const float w[3]) {
    return (x[0] * (y[1] * w[2] - y[2] * w[1]) + x[1] * (y[2] * w[0] - y[0] * w[2])) +
           x[2] * (y[0] * w[1] - y[1] * w[0]);
}
/// adelson1991's stereo back-face test in clip space. For views that are shears of the center
/// clip position (x_v = x_c + s_x(w − c), y_v = y_c + s_y(w − c)), det[x_v, y_v, w] is linear in
/// the shear: det_c + s_x·K_x + s_y·K_y with K_x = −c·det[1, y_c, w], K_y = −c·det[x_c, 1, w].
/// Both methods classify sheared views with this form (multipass per view, unified once per
/// triangle plus one multiply-add per view), so their decisions agree exactly.
struct ShearDet {
    float center = 0, kx = 0, ky = 0;
};
inline ShearDet shearDet(const float cx[3], const float cy[3], const float w[3],
                         float convergence) {
    ShearDet d;
    d.center = det3(cx, cy, w);
    const float dx = ((cy[1] * w[2] - cy[2] * w[1]) + (cy[2] * w[0] - cy[0] * w[2])) +
                     (cy[0] * w[1] - cy[1] * w[0]);
    const float dy = (cx[0] * (w[2] - w[1]) + cx[1] * (w[0] - w[2])) + cx[2] * (w[1] - w[0]);
    d.kx = -convergence * dx;
    d.ky = -convergence * dy;
    return d;
}
inline float shearedDet(const ShearDet& d, float sx, float sy) {
    return (d.center + sx * d.kx) + sy * d.ky;
}

// ---- projection and snapping ---------------------------------------------------------------
/// Window x in 1/256 px of a clip x with q = 1/w. Rounding: nearest, ties to even (lrintf and
/// cvtps2dq agree).
inline std::int32_t snapX(float x, float q, float width) {
    return static_cast<std::int32_t>(
        std::lrintf(((x * q) * 0.5f + 0.5f) * width * float(kSubpixel)));
}
inline std::int32_t snapY(float y, float q, float height) { return snapX(y, q, height); }
inline float windowDepth(float z, float q) { return std::clamp((z * q) * 0.5f + 0.5f, 0.0f, 1.0f); }

// ---- homogeneous clipping --------------------------------------------------------------------
/// A polygon vertex during clipping: clip position and attributes.
struct ClipVertex {
    float x, y, z, w;
    float a[kMaxAttrs];
};

inline float planeDistance(int plane, float x, float y, float z, float w) {
    switch (plane) {
        case 0: return z + w;                // near
        case 1: return w - z;                // far
        case 2: return y + kGuardBand * w;   // bottom
        case 3: return kGuardBand * w - y;   // top
        case 4: return x + kGuardBand * w;   // left
        default: return kGuardBand * w - x;  // right
    }
}

/// t of the intersection on the edge from an inside vertex (distance dIn ≥ 0) to an outside one
/// (dOut < 0). Always computed from the inside end, so a shared edge clips identically for both
/// triangles (and for every view that shares the plane).
inline float clipT(float dIn, float dOut) { return dIn / (dIn - dOut); }
inline float lerpF(float a, float b, float t) { return a + t * (b - a); }

/// Sutherland–Hodgman against the planes in `planes` (outcode bits 0..5), in plane order.
/// `poly` holds n vertices; returns the new count (0 when nothing is left). `scratch` must hold
/// kMaxPolyVerts vertices.
inline int clipPolygon(ClipVertex* poly, int n, std::uint8_t planes, int attrCount,
                       ClipVertex* scratch) {
    ClipVertex* in = poly;
    ClipVertex* out = scratch;
    for (int plane = 0; plane < 6 && n > 0; ++plane) {
        if (!(planes & (1u << plane))) continue;
        float d[kMaxPolyVerts];
        for (int i = 0; i < n; ++i) d[i] = planeDistance(plane, in[i].x, in[i].y, in[i].z, in[i].w);
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const int j = i + 1 == n ? 0 : i + 1;
            const bool inI = d[i] >= 0.0f, inJ = d[j] >= 0.0f;
            if (inI) out[m++] = in[i];
            if (inI != inJ) {
                const ClipVertex& a = inI ? in[i] : in[j];
                const ClipVertex& b = inI ? in[j] : in[i];
                const float t = inI ? clipT(d[i], d[j]) : clipT(d[j], d[i]);
                ClipVertex& v = out[m++];
                v.x = lerpF(a.x, b.x, t);
                v.y = lerpF(a.y, b.y, t);
                v.z = lerpF(a.z, b.z, t);
                v.w = lerpF(a.w, b.w, t);
                for (int k = 0; k < attrCount; ++k) v.a[k] = lerpF(a.a[k], b.a[k], t);
            }
        }
        n = m;
        std::swap(in, out);
    }
    if (in != poly) {
        for (int i = 0; i < n; ++i) poly[i] = in[i];
    }
    return n;
}

// ---- triangle setup and coverage -------------------------------------------------------------
inline int floorDivSub(std::int64_t v) { return static_cast<int>(v >> kSubpixelBits); }
inline int ceilDivSub(std::int64_t v) {
    return static_cast<int>((v + (kSubpixel - 1)) >> kSubpixelBits);
}

/// The part of a triangle's setup that does not depend on x: snapped y, y extent (pixel rows,
/// clamped to the band being drawn) and Δy of the three edges. Shared by every view that shares y.
struct YSetup {
    std::int32_t y[3];
    std::int32_t dy[3];  ///< edge i runs from vertex i+1 to vertex i+2: dy[i] = y[i+2] − y[i+1]
    int rowMin, rowMax;  ///< pixel rows (GL window y, up) whose centers may be covered; inclusive
};

/// Rows whose pixel centers y + 0.5 lie within [min y, max y], clamped to [rowLo, rowHi].
inline void setupY(YSetup& s, std::int32_t y0, std::int32_t y1, std::int32_t y2, int rowLo,
                   int rowHi) {
    s.y[0] = y0, s.y[1] = y1, s.y[2] = y2;
    s.dy[0] = y2 - y1, s.dy[1] = y0 - y2, s.dy[2] = y1 - y0;
    const std::int32_t lo = std::min(y0, std::min(y1, y2)), hi = std::max(y0, std::max(y1, y2));
    s.rowMin = std::max(rowLo, ceilDivSub(std::int64_t(lo) - kHalfSubpixel));
    s.rowMax = std::min(rowHi, floorDivSub(std::int64_t(hi) - kHalfSubpixel));
}

/// Edge setup shared by both coverage paths, in integer type T (int32 when the coordinates are
/// relative to a nearby pixel center, int64 otherwise). Edge i runs from vertex i+1 to i+2;
/// returns 2 × area (> 0) after reversing clockwise triangles (E_ba = −E_ab exactly), or 0.
/// Top-left rule with y up and counter-clockwise order: a left edge runs downward (dy < 0), a
/// top edge is horizontal running left (dx < 0); inside ⇔ E > 0, or E == 0 on a top-left edge
/// ⇔ E + bias > 0 with bias 1 on top-left edges.
template <class T>
inline T edgeSetup(const T xr[3], const T yr[3], const std::int32_t sharedDy[3], T dx[3], T dy[3],
                   T bias[3]) {
    dx[0] = xr[2] - xr[1], dx[1] = xr[0] - xr[2], dx[2] = xr[1] - xr[0];
    dy[0] = sharedDy[0], dy[1] = sharedDy[1], dy[2] = sharedDy[2];  // from YSetup: once per family
    T area = dx[2] * (yr[2] - yr[0]) - dy[2] * (xr[2] - xr[0]);
    const T flip = area < 0 ? T(-1) : T(0);  // the area's sign is random: keep it branch-free
    area = (area ^ flip) - flip;
    for (int i = 0; i < 3; ++i) {
        dx[i] = (dx[i] ^ flip) - flip, dy[i] = (dy[i] ^ flip) - flip;
        bias[i] = T((dy[i] < 0) | ((dy[i] == 0) & (dx[i] < 0)));
    }
    return area;
}

/// Coverage of a triangle whose box holds at most 2×2 pixel centers — most triangles of a
/// dense mesh. Coordinates relative to the first pixel center fit int32 (the box is < 3 px), the
/// four centers are tested without branches and only covered ones are visited.
template <class Sink>
inline void rasterSmallTriangle(const YSetup& ys, const std::int32_t x[3], int colMin, int colMax,
                                Sink& sink) {
    const std::int32_t px0 = colMin * kSubpixel + kHalfSubpixel;
    const std::int32_t py0 = ys.rowMin * kSubpixel + kHalfSubpixel;
    const std::int32_t xr[3] = {x[0] - px0, x[1] - px0, x[2] - px0};
    const std::int32_t yr[3] = {ys.y[0] - py0, ys.y[1] - py0, ys.y[2] - py0};
    std::int32_t dx[3], dy[3], bias[3];
    const std::int32_t area = edgeSetup(xr, yr, ys.dy, dx, dy, bias);
    if (area == 0) return;
    std::int32_t e[4][3];
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        e[0][i] = dy[i] * xr[a] - dx[i] * yr[a] + bias[i];  // E + bias at the first center
        e[1][i] = e[0][i] - dy[i] * kSubpixel;
        e[2][i] = e[0][i] + dx[i] * kSubpixel;
        e[3][i] = e[2][i] - dy[i] * kSubpixel;
    }
    const unsigned wide = unsigned(colMax > colMin), tall = unsigned(ys.rowMax > ys.rowMin);
    unsigned mask = 1u | (wide << 1) | (tall << 2) | ((wide & tall) << 3);
    for (int k = 0; k < 4; ++k) {
        mask &= ~(unsigned(((e[k][0] - 1) | (e[k][1] - 1) | (e[k][2] - 1)) < 0) << k);
    }
    if (!mask) return;
    const float invArea = 1.0f / static_cast<float>(area);
    while (mask) {
        const int k = __builtin_ctz(mask);
        mask &= mask - 1;
        sink(colMin + (k & 1), ys.rowMin + (k >> 1),
             static_cast<float>(e[k][0] - bias[0]) * invArea,
             static_cast<float>(e[k][1] - bias[1]) * invArea,
             static_cast<float>(e[k][2] - bias[2]) * invArea);
    }
}

/// True when no pixel-center column of [0, width) lies within the triangle's snapped x extent —
/// the same column range rasterTriangle() computes, so such a triangle draws nothing in that view.
inline bool noColumns(std::int32_t x0, std::int32_t x1, std::int32_t x2, int width) {
    const std::int32_t xlo = std::min(x0, std::min(x1, x2)), xhi = std::max(x0, std::max(x1, x2));
    const int colMin = std::max(0, ceilDivSub(std::int64_t(xlo) - kHalfSubpixel));
    const int colMax = std::min(width - 1, floorDivSub(std::int64_t(xhi) - kHalfSubpixel));
    return colMin > colMax;
}

/// Walks the pixels of one triangle (snapped x per view, shared YSetup) whose centers are inside
/// by the top-left rule, within columns [0, width) and the rows of `ys`. Calls
/// sink(x, y, l0, l1, l2) with the screen-space barycentrics of the ORIGINAL vertex order, so
/// that the orientation fix-up for clockwise triangles does not change any float result.
template <class Sink>
inline void rasterTriangle(const YSetup& ys, const std::int32_t x[3], int width, Sink& sink) {
    if constexpr (requires { sink.setTriangle(x, ys.y); }) sink.setTriangle(x, ys.y);
    if (ys.rowMin > ys.rowMax) return;
    // Column range first: most triangles of a dense mesh are smaller than a pixel, and many have
    // no pixel center in their box at all.
    const std::int32_t xlo = std::min(x[0], std::min(x[1], x[2]));
    const std::int32_t xhi = std::max(x[0], std::max(x[1], x[2]));
    const int colMin = std::max(0, ceilDivSub(std::int64_t(xlo) - kHalfSubpixel));
    const int colMax = std::min(width - 1, floorDivSub(std::int64_t(xhi) - kHalfSubpixel));
    if (colMin > colMax) return;
    const std::int32_t ylo = std::min(ys.y[0], std::min(ys.y[1], ys.y[2]));
    const std::int32_t yhi = std::max(ys.y[0], std::max(ys.y[1], ys.y[2]));
    if (colMax - colMin <= 1 && ys.rowMax - ys.rowMin <= 1 && xhi - xlo < kSmallSpan &&
        yhi - ylo < kSmallSpan) {
        rasterSmallTriangle(ys, x, colMin, colMax, sink);
        return;
    }
    const std::int64_t xr[3] = {x[0], x[1], x[2]}, yr[3] = {ys.y[0], ys.y[1], ys.y[2]};
    std::int64_t dx[3], dy[3], bias[3], rowE[3], stepX[3];
    const std::int64_t area = edgeSetup(xr, yr, ys.dy, dx, dy, bias);
    if (area == 0) return;
    const std::int64_t px0 = std::int64_t(colMin) * kSubpixel + kHalfSubpixel;
    const std::int64_t py0 = std::int64_t(ys.rowMin) * kSubpixel + kHalfSubpixel;
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1;
        rowE[i] = dx[i] * (py0 - yr[a]) - dy[i] * (px0 - xr[a]) + bias[i];
        stepX[i] = -dy[i] * kSubpixel;
    }
    const float invArea = 1.0f / static_cast<float>(area);
    auto emit = [&](int col, int row, std::int64_t e0, std::int64_t e1, std::int64_t e2) {
        sink(col, row, static_cast<float>(e0 - bias[0]) * invArea,
             static_cast<float>(e1 - bias[1]) * invArea,
             static_cast<float>(e2 - bias[2]) * invArea);
    };
    // rowE holds E + bias; the barycentrics use E itself.
    for (int row = ys.rowMin; row <= ys.rowMax; ++row) {
        std::int64_t e0 = rowE[0], e1 = rowE[1], e2 = rowE[2];
        for (int col = colMin; col <= colMax; ++col) {
            if (((e0 - 1) | (e1 - 1) | (e2 - 1)) >= 0) emit(col, row, e0, e1, e2);  // all > 0
            e0 += stepX[0], e1 += stepX[1], e2 += stepX[2];
        }
        for (int i = 0; i < 3; ++i) rowE[i] += dx[i] * kSubpixel;
    }
}

// ---- one triangle, many views -----------------------------------------------------------------
/// The x-dependent setup of one triangle for up to kMaxViews views of a family, computed side by
/// side (SIMD across views: the views run the same instructions on different x), consumed at
/// once from L1 by the caller. Per view k: mask[k] < 0: the view needs the general walk
/// (rasterTriangle); 0: no pixel center covered; else bit j = column j&1, row j>>1 of the 2×2
/// centers from (colMin, ys.rowMin) covered, with E + bias of edge i there = e[i] + (j&1 ? sx[i]
/// : 0) + (j&2 ? sy[i] : 0), and 2 × area in area[k]. The same integers rasterSmallTriangle uses.
struct ViewsSetup {
    std::int32_t mask[kMaxViews], colMin[kMaxViews], area[kMaxViews];
    std::int32_t e[3][kMaxViews], sx[3][kMaxViews], sy[3][kMaxViews], bias[3][kMaxViews];
};

/// What a long sheared row derives its views' x from, per vertex of one triangle (issue 12: x is
/// not stored per view): view k's snapped x of vertex j is
/// snapX(shearClipWc(cx[j], shear[k], wc[j]), q[j], width) — the bits the vertex stage's
/// shearClip + projectX would have stored.
struct ShearedTri {
    float cx[3];  ///< center clip x
    float wc[3];  ///< clip w − convergence
    float q[3];   ///< 1/w
};
/// setupSheared's output besides its ViewsSetup: the views that have a pixel-center column in
/// the triangle's x extent, packed (view[i]: position in the call's views), and their snapped x.
struct ViewsX {
    alignas(64) std::int32_t x[3][kMaxViews];
    std::uint8_t view[kMaxViews + 16];  ///< + room for a whole register's store
};

/// Emits view k's covered 2×2 centers from a ViewsSetup (mask[k] > 0).
template <class Sink>
inline void emitSmall(const ViewsSetup& s, int k, int rowMin, Sink& sink) {
    unsigned mask = unsigned(s.mask[k]);
    const float invArea = 1.0f / static_cast<float>(s.area[k]);
    while (mask) {
        const int j = __builtin_ctz(mask);
        mask &= mask - 1;
        float l[3];
        for (int i = 0; i < 3; ++i) {
            const std::int32_t e =
                s.e[i][k] + (j & 1 ? s.sx[i][k] : 0) + (j & 2 ? s.sy[i][k] : 0) - s.bias[i][k];
            l[i] = static_cast<float>(e) * invArea;
        }
        sink(s.colMin[k] + (j & 1), rowMin + (j >> 1), l[0], l[1], l[2]);
    }
}

// ---- fragments --------------------------------------------------------------------------------
/// One view's framebuffer: rows stored top first (image.h), addressed with GL window y (up).
struct Target {
    std::uint32_t* color = nullptr;
    float* depth = nullptr;
    int width = 0, height = 0;
    /// The index of the pixel the pointers point at: 0 for a whole image; a streamed band's
    /// scratch (unified.cpp) holds only the band's rows, the top one first.
    std::size_t offset = 0;
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(height - 1 - y) * width + x - offset;
    }
};

/// The per-triangle fragment inputs (all view-independent for views that share z and w).
struct FragmentTri {
    float z[3];              ///< window depth
    float q[3];              ///< 1/w
    const float* attr[3];    ///< kMaxAttrs-strided attributes
    std::uint32_t flat = 0;  ///< Flat: the triangle's packed color
    glm::vec3 flatD{0.0f};   ///< Flat in a textured frame: the triangle's flatTerms D
};

/// Flat's per-triangle fragment input (view-independent): the packed color, or in a textured
/// frame the diffuse term the texel multiplies.
inline void setFlat(FragmentTri& frag, bool textured, const ShadingContext& ctx,
                    const Material& material, const glm::vec3& p0, const glm::vec3& p1,
                    const glm::vec3& p2) {
    if (textured) {
        const glm::vec3 n = faceNormal(p0, p1, p2), c = centroid(p0, p1, p2);
        float sh[kMaxLights];  // shadows (issue 15): one factor per triangle, at its centroid
        frag.flatD =
            flatTerms(ctx, material, n, c, shadowFactors(ctx.shadows, ctx.lights, c, n, sh))
                .diffuse;
    } else {
        frag.flat = flatColor(ctx, material, p0, p1, p2);
    }
}

/// Gradients of the screen barycentrics l_i per window pixel, from the triangle's snapped
/// window coordinates in one view (1/256 px): with A = 2·signed area, ∂l_0/∂x = (y1 − y2)·256/A,
/// ∂l_0/∂y = (x2 − x1)·256/A, cyclically for l_1, l_2. The per-VIEW input of the texture level
/// of detail: both methods call it with the same integers, so λ agrees bit for bit.
inline void screenGradients(const std::int32_t x[3], const std::int32_t y[3], float gx[3],
                            float gy[3]) {
    const std::int64_t area =
        std::int64_t(x[1] - x[0]) * (y[2] - y[0]) - std::int64_t(x[2] - x[0]) * (y[1] - y[0]);
    const float inv = area != 0 ? float(kSubpixel) / float(area) : 0.0f;
    for (int i = 0; i < 3; ++i) {
        const int a = i == 2 ? 0 : i + 1, b = a == 2 ? 0 : a + 1;
        gx[i] = float(y[a] - y[b]) * inv;
        gy[i] = float(x[b] - x[a]) * inv;
    }
}

struct ShadeInputs {
    const ShadingContext* ctx = nullptr;
    const Material* material = nullptr;
    bool textured = false;              ///< the frame's textured attribute layout (kMaxAttrs)
    const MipChain* texture = nullptr;  ///< the material's base color texture, or none
    bool colored = false;               ///< the frame's layout has vertex colours
    // The material's other texture slots (issue 39, lighting.h SurfaceMaps), or none.
    const MipChain* metallicRoughness = nullptr;
    const MipChain* occlusion = nullptr;
    const MipChain* emissive = nullptr;
    const MipChain* normal = nullptr;  ///< drawn in a frame with tangents only (pixel shading)
    bool tangents = false;             ///< the frame's layout has the tangent (tangentAttribute)

    /// Whether the material samples any texture: its fragments need the triangle's screen
    /// gradients (the level of detail).
    bool samples() const { return texture || metallicRoughness || occlusion || emissive || normal; }
};

/// Depth test (LESS) and shading of one fragment; the screen barycentrics l0..l2 come from
/// rasterTriangle. Depth is linear in screen space (as GL); attributes perspective-correct.
template <Shading S>
struct FragmentSink {
    Target target;
    const FragmentTri* tri;
    ShadeInputs shade;
    float gx[3] = {0, 0, 0}, gy[3] = {0, 0, 0};  ///< screenGradients of the current triangle

    /// Called by the rasterizers before a triangle's fragments in this view (snapped window
    /// coordinates); lines never call it, so wireframe samples with zero derivatives (level 0).
    void setTriangle(const std::int32_t x[3], const std::int32_t y[3]) {
        if (shade.samples()) screenGradients(x, y, gx, gy);
    }

    void operator()(int x, int y, float l0, float l1, float l2) const {
        const float z = (l0 * tri->z[0] + l1 * tri->z[1]) + l2 * tri->z[2];
        const std::size_t i = target.index(x, y);
        if (!(z < target.depth[i])) return;
        if (shade.textured) {
            texturedFragment(i, z, l0, l1, l2);
            return;
        }
        target.depth[i] = z;
        if constexpr (S == Shading::Flat) {
            target.color[i] = tri->flat;
        } else {
            const float p0 = l0 * tri->q[0], p1 = l1 * tri->q[1], p2 = l2 * tri->q[2];
            const float inv = 1.0f / ((p0 + p1) + p2);
            const float* a0 = tri->attr[0];
            const float* a1 = tri->attr[1];
            const float* a2 = tri->attr[2];
            auto at = [&](int k) { return ((p0 * a0[k] + p1 * a1[k]) + p2 * a2[k]) * inv; };
            if constexpr (S == Shading::Vertex) {
                target.color[i] = packColor(glm::vec3(at(0), at(1), at(2)));
            } else {
                const glm::vec3 n(at(0), at(1), at(2));
                const glm::vec3 p(at(3), at(4), at(5));
                float sh[kMaxLights];
                target.color[i] = packColor(shadeBlinnPhong(
                    *shade.ctx, *shade.material, n, p,
                    shadowFactors(shade.ctx->shadows, shade.ctx->lights, p, n, sh)));
            }
        }
    }

    /// A textured frame's fragment (lighting.h's textured shading, texture_sampling.h's
    /// sample): base = (albedo, alpha) × texel; Mask discards below the cutoff (no depth
    /// write); Blend mixes with the framebuffer and writes no depth.
    void texturedFragment(std::size_t i, float z, float l0, float l1, float l2) const {
        const float p0 = l0 * tri->q[0], p1 = l1 * tri->q[1], p2 = l2 * tri->q[2];
        const float inv = 1.0f / ((p0 + p1) + p2);
        const float* a0 = tri->attr[0];
        const float* a1 = tri->attr[1];
        const float* a2 = tri->attr[2];
        auto at = [&](int k) { return ((p0 * a0[k] + p1 * a1[k]) + p2 * a2[k]) * inv; };
        const Material& m = *shade.material;
        constexpr int ku = uvAttribute(S);
        const glm::vec2 uv(at(ku), at(ku + 1));
        // Every slot reads the same coordinates through the material's sampler, each at its
        // own level of detail (its own size).
        auto sample = [&](const MipChain* chain, glm::vec4 absent) {
            if (!chain || chain->levels.empty()) return absent;
            const glm::vec2 uvi[3] = {
                {a0[ku], a0[ku + 1]}, {a1[ku], a1[ku + 1]}, {a2[ku], a2[ku + 1]}};
            const UvDerivatives d = uvDerivatives(gx, gy, tri->q, uvi, uv, inv);
            const MipLevel& level0 = chain->levels[0];
            return sampleTexture(*chain, m.sampler, uv,
                                 textureLod(d, level0.width, level0.height));
        };
        glm::vec4 texel = sample(shade.texture, glm::vec4(1.0f));
        if (shade.colored) {  // the vertex colour multiplies the texel (glTF COLOR_0)
            constexpr int k = colorAttribute(S);
            texel *= glm::vec4(at(k), at(k + 1), at(k + 2), at(k + 3));
        }
        const glm::vec4 base = baseColor(m, texel);
        if (m.alphaMode == AlphaMode::Mask && base.w < m.alphaCutoff) return;
        // The other slots (lighting.h SurfaceMaps): the metallic-roughness map per pixel only.
        SurfaceMaps maps;
        if (S == Shading::Pixel && shade.metallicRoughness) {
            const glm::vec4 t = sample(shade.metallicRoughness, glm::vec4(1.0f));
            maps.roughness = t.y, maps.metallic = t.z;
        }
        if (shade.occlusion)
            maps.occlusion = occlusionOf(sample(shade.occlusion, glm::vec4(1.0f)).x,
                                         m.occlusionStrength);
        if (shade.emissive) maps.emissive = glm::vec3(sample(shade.emissive, glm::vec4(1.0f)));
        LightTerms terms;
        if constexpr (S == Shading::Flat) {
            terms.diffuse = tri->flatD;
            terms.specular = flatSpecular(m);
        } else if constexpr (S == Shading::Vertex) {
            terms.diffuse = glm::vec3(at(0), at(1), at(2));
            terms.specular = glm::vec3(at(3), at(4), at(5));
        } else {
            const glm::vec3 n(at(0), at(1), at(2));
            const glm::vec3 p(at(3), at(4), at(5));
            float sh[kMaxLights];
            // Shadows look up with the surface's own normal (their offset), lighting with the
            // normal map's.
            const float* shadow = shadowFactors(shade.ctx->shadows, shade.ctx->lights, p, n, sh);
            glm::vec3 lit = n;
            if (shade.normal && shade.tangents) {
                const int j = tangentAttribute(shade.colored);
                const glm::vec4 t(at(j), at(j + 1), at(j + 2), at(j + 3));
                lit = perturbedNormal(n, t, glm::vec3(sample(shade.normal, glm::vec4(1.0f))),
                                      m.normalScale);
            }
            terms = blinnPhongTerms(*shade.ctx, m, lit, p, shadow,
                                    shade.metallicRoughness || shade.occlusion ? &maps : nullptr);
        }
        if (shade.occlusion || shade.emissive)
            terms = applySurfaceMaps(*shade.ctx, m, terms, maps);
        glm::vec3 c = shadeTextured(*shade.ctx, glm::vec3(base), terms);
        if (m.alphaMode == AlphaMode::Blend) {
            const float a = std::clamp(base.w, 0.0f, 1.0f);
            const std::uint32_t dst = target.color[i];
            const glm::vec3 d(float(dst & 0xffu) / 255.0f, float((dst >> 8) & 0xffu) / 255.0f,
                              float((dst >> 16) & 0xffu) / 255.0f);
            c = c * a + d * (1.0f - a);
        } else {
            target.depth[i] = z;
        }
        target.color[i] = packColor(c);
    }
};

}  // namespace mvr::raster::detail
