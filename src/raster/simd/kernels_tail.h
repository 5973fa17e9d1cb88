// Scalar loops of the projection kernels: the scalar path, and the tails of the SIMD paths.
#pragma once

#include <bit>

#include "../lanes.h"
#include "../pipeline.h"

namespace mvr::raster::detail {

inline void projectYZWTail(const float* y, const float* z, const float* w, std::size_t n,
                           float height, std::uint8_t* code, float* q, std::int32_t* sy,
                           float* zw) {
    for (std::size_t i = 0; i < n; ++i) {
        code[i] = outcodeYZW(y[i], z[i], w[i]);
        q[i] = 1.0f / w[i];
        sy[i] = code[i] & kClipYZW ? 0 : snapY(y[i], q[i], height);
        zw[i] = windowDepth(z[i], q[i]);
    }
}

inline void projectXTail(const float* x, const float* w, const float* q, std::size_t n, float width,
                         std::uint8_t* code, std::int32_t* sx) {
    for (std::size_t i = 0; i < n; ++i) {
        code[i] = outcodeX(x[i], w[i]);
        sx[i] = code[i] & kClipX ? 0 : snapX(x[i], q[i], width);
    }
}

inline void rowClipXTail(const float* cx, const float* w, std::size_t n, float lo, float hi,
                         float convergence, std::uint8_t* any) {
    for (std::size_t i = 0; i < n; ++i) {
        const float wc = w[i] - convergence;
        any[i] |= (outcodeX(shearClipWc(cx[i], lo, wc), w[i]) |
                   outcodeX(shearClipWc(cx[i], hi, wc), w[i])) &
                  kClipX;
    }
}

inline void rowSnapXTail(const float* cx, const float* w, const float* q, std::size_t n,
                         const float* shears, int nv, float convergence, float width,
                         std::int32_t* sxv) {
    for (std::size_t i = 0; i < n; ++i) {
        const float wc = w[i] - convergence;
        for (int k = 0; k < nv; ++k) {
            const float x = shearClipWc(cx[i], shears[k], wc);
            sxv[i * std::size_t(nv) + std::size_t(k)] =
                outcodeX(x, w[i]) & kClipX ? 0 : snapX(x, q[i], width);
        }
    }
}

/// Vertex lighting, one vertex at a time: the reference (pipeline.h's vertexAttributes).
inline void shadeVerticesTail(const glm::vec3* positions, const glm::vec3* normals, std::size_t n,
                              const glm::mat4& worldFromModel, const glm::mat3& normalFromModel,
                              const ShadingContext& ctx, const Material& material, float* color) {
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3 world = glm::vec3(transformPoint(worldFromModel, positions[i]));
        vertexAttributes(Shading::Vertex, ctx, material, world,
                         transformDir(normalFromModel, normals[i]), color + 3 * i);
    }
}

inline void specularPowTail(const float* x, std::size_t n, float s, float* out) {
    for (std::size_t i = 0; i < n; ++i) out[i] = specularPow(x[i], s);
}

/// Clip (or any) positions of n vertices, transformPoint(m, p) split into x, y, z, w arrays.
inline void transformPointsTail(const glm::vec3* positions, std::size_t n, const glm::mat4& m,
                                float* x, float* y, float* z, float* w) {
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec4 c = transformPoint(m, positions[i]);
        x[i] = c.x, y[i] = c.y, z[i] = c.z, w[i] = c.w;
    }
}

/// Views [begin, n) of setupViews, one at a time: the reference for the SIMD versions (and the
/// same integer operations as rasterSmallTriangle).
inline std::uint64_t setupViewsTail(const YSetup& ys, const std::int32_t* x0,
                                    const std::int32_t* x1, const std::int32_t* x2, int begin,
                                    int n, int width, ViewsSetup& o) {
    std::uint64_t lanes = 0;
    const bool tall = ys.rowMax > ys.rowMin;
    const std::int32_t ylo = std::min(ys.y[0], std::min(ys.y[1], ys.y[2]));
    const std::int32_t yhi = std::max(ys.y[0], std::max(ys.y[1], ys.y[2]));
    const bool rowsSmall = ys.rowMax - ys.rowMin <= 1 && yhi - ylo < kSmallSpan;
    const std::int32_t py0 = ys.rowMin * kSubpixel + kHalfSubpixel;
    const std::int32_t yr[3] = {ys.y[0] - py0, ys.y[1] - py0, ys.y[2] - py0};
    for (int k = begin; k < n; ++k) {
        const std::int32_t x[3] = {x0[k], x1[k], x2[k]};
        const std::int32_t xlo = std::min(x[0], std::min(x[1], x[2]));
        const std::int32_t xhi = std::max(x[0], std::max(x[1], x[2]));
        const int colMin = std::max(0, ceilDivSub(std::int64_t(xlo) - kHalfSubpixel));
        const int colMax = std::min(width - 1, floorDivSub(std::int64_t(xhi) - kHalfSubpixel));
        o.colMin[k] = colMin;
        if (colMin > colMax) {
            o.mask[k] = 0;
            continue;
        }
        if (!rowsSmall || colMax - colMin > 1 || xhi - xlo >= kSmallSpan) {
            o.mask[k] = -1;
            lanes |= std::uint64_t(1) << k;
            continue;
        }
        const std::int32_t px0 = colMin * kSubpixel + kHalfSubpixel;
        const std::int32_t xr[3] = {x[0] - px0, x[1] - px0, x[2] - px0};
        std::int32_t dx[3], dy[3], bias[3];
        const std::int32_t area = edgeSetup(xr, yr, ys.dy, dx, dy, bias);
        o.area[k] = area;
        unsigned mask = 0;
        for (int i = 0; i < 3; ++i) {
            const int a = i == 2 ? 0 : i + 1;
            o.e[i][k] = dy[i] * xr[a] - dx[i] * yr[a] + bias[i];
            o.sx[i][k] = -dy[i] * kSubpixel;
            o.sy[i][k] = dx[i] * kSubpixel;
            o.bias[i][k] = bias[i];
        }
        for (int j = 0; j < 4; ++j) {
            std::int32_t any = 0;
            for (int i = 0; i < 3; ++i) {
                any |= o.e[i][k] - 1 + (j & 1 ? o.sx[i][k] : 0) + (j & 2 ? o.sy[i][k] : 0);
            }
            mask |= unsigned(any >= 0) << j;
        }
        const unsigned wide = unsigned(colMax > colMin);
        mask &= 1u | (wide << 1) | (unsigned(tall) << 2) | ((wide & unsigned(tall)) << 3);
        o.mask[k] = area == 0 ? 0 : std::int32_t(mask);
        lanes |= std::uint64_t(o.mask[k] != 0) << k;
    }
    return lanes;
}

/// setupSheared one view at a time: x derived, the views with a column packed, then
/// setupViewsTail of the packed views (the reference).
inline std::uint64_t setupShearedTail(const YSetup& ys, const ShearedTri& t, const float* shears,
                                      int n, int width, ViewsSetup& o, ViewsX& x) {
    int m = 0;
    for (int k = 0; k < n; ++k) {
        std::int32_t xk[3];
        for (int j = 0; j < 3; ++j)
            xk[j] = snapX(shearClipWc(t.cx[j], shears[k], t.wc[j]), t.q[j], float(width));
        if (noColumns(xk[0], xk[1], xk[2], width)) continue;
        for (int j = 0; j < 3; ++j) x.x[j][m] = xk[j];
        x.view[m++] = std::uint8_t(k);
    }
    return setupViewsTail(ys, x.x[0], x.x[1], x.x[2], 0, m, width, o);
}

/// setupLanes, lane by lane through setupViewsTail: the reference of the SIMD paths.
inline std::uint32_t setupLanesTail(TriangleLanes& l, int n, int width) {
    std::uint32_t lanes = 0;
    for (int k = 0; k < n; ++k) {
        YSetup ys;
        setupY(ys, l.y[0][k], l.y[1][k], l.y[2][k], l.rowMin[k], l.rowMax[k]);
        ys.rowMin = l.rowMin[k], ys.rowMax = l.rowMax[k];
        lanes |= std::uint32_t(setupViewsTail(ys, l.x[0], l.x[1], l.x[2], k, k + 1, width, l.out));
    }
    return lanes;
}

/// shadeLanes one lane at a time through FragmentSink (the reference).
inline std::uint64_t shadeLanesTail(const ViewsSetup& s, std::uint64_t lanes, int rowMin, int width,
                                    int height, const FragmentTri& tri, bool flat,
                                    const std::uint8_t* slot, float* const* depth,
                                    std::uint32_t* const* color) {
    std::uint64_t general = 0;
    for (; lanes; lanes &= lanes - 1) {
        const int k = std::countr_zero(lanes);
        if (s.mask[k] < 0) general |= std::uint64_t(1) << k;
        if (s.mask[k] <= 0) continue;
        const Target target{color[slot[k]], depth[slot[k]], width, height};
        if (flat) {
            FragmentSink<Shading::Flat> sink{target, &tri, ShadeInputs{}};
            emitSmall(s, k, rowMin, sink);
        } else {
            FragmentSink<Shading::Vertex> sink{target, &tri, ShadeInputs{}};
            emitSmall(s, k, rowMin, sink);
        }
    }
    return general;
}

/// drawSheared as setupShearedTail, the culled views taken out, shadeLanesTail, 64 views at a
/// time, and the views left to the general walk packed into `x` (the reference).
inline int drawShearedTail(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                           const std::uint64_t* culled, int width, int height,
                           const FragmentTri& tri, bool flat, float* const* depth,
                           std::uint32_t* const* color, std::int32_t /*blockStride*/, ViewsX& x) {
    int count = 0;
    for (int base = 0; base < n; base += 64) {
        ViewsSetup s;
        ViewsX chunk;
        std::uint64_t lanes =
            setupShearedTail(ys, t, shears + base, std::min(64, n - base), width, s, chunk);
        const std::uint64_t out = culled ? culled[base / 64] : 0;
        for (std::uint64_t bits = lanes; bits; bits &= bits - 1) {
            const int k = std::countr_zero(bits);
            if ((out >> chunk.view[k]) & 1u) lanes &= ~(std::uint64_t(1) << k);
        }
        for (std::uint64_t general = shadeLanesTail(s, lanes, ys.rowMin, width, height, tri, flat,
                                                    chunk.view, depth + base, color + base);
             general; general &= general - 1) {
            const int k = std::countr_zero(general);
            for (int j = 0; j < 3; ++j) x.x[j][count] = chunk.x[j][k];
            x.view[count++] = std::uint8_t(base + chunk.view[k]);
        }
    }
    return count;
}

}  // namespace mvr::raster::detail
