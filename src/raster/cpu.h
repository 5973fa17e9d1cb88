// src/raster/cpu.h — CPU identification and the runtime-dispatched SIMD kernels.
//
// Kernels exist in three translation units compiled with their own ISA flags (simd/*.cpp,
// MaskedOcclusionCulling style): scalar (always built, the reference), AVX2 and AVX-512 (built
// unless MVR_SIMD=scalar). All three compute the same operations in the same order, so their
// results are identical bit for bit (tests/raster check this).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "lanes.h"
#include "mvr/raster/soft_backend.h"
#include "pipeline.h"

namespace mvr::raster::detail {

SimdPath bestSupportedSimd();
/// Auto → best; a path this CPU/build lacks → best available.
SimdPath resolveSimd(SimdPath requested);

/// Projection of (y, z, w) for n vertices: outcodeYZW, and where no clip bit is set, q = 1/w,
/// snapped window y and window depth (other lanes hold unspecified values).
using ProjectYZWFn = void (*)(const float* y, const float* z, const float* w, std::size_t n,
                              float height, std::uint8_t* code, float* q, std::int32_t* sy,
                              float* zw);
/// Projection of x for n vertices given q: outcodeX, and snapped window x.
using ProjectXFn = void (*)(const float* x, const float* w, const float* q, std::size_t n,
                            float width, std::uint8_t* code, std::int32_t* sx);

/// x setup of one triangle for n views (snapped window x of its vertices per view, the shared
/// y setup with a non-empty row range): fills `out` for views 0..n-1 (see ViewsSetup) and returns
/// the views whose mask is not 0 (bit k: view k), so that the caller visits only those.
using SetupViewsFn = std::uint64_t (*)(const YSetup& ys, const std::int32_t* x0,
                                       const std::int32_t* x1, const std::int32_t* x2, int n,
                                       int width, ViewsSetup& out);

/// The x setup of one triangle in n <= 64 views of a sheared row whose x is derived, not stored
/// (issue 12): view k's x of vertex j is snapX(shearClipWc(t.cx[j], shears[k], t.wc[j]), t.q[j],
/// width). Only the views with a pixel-center column in their x extent (setupViews' colMin <=
/// colMax; a sub-pixel triangle has none in most views) are set up: they are packed in view
/// order, x.view[i] = k and x.x[j][i] = its x, and setupViews' results for them are in column i
/// of `out`. Returns the packed positions whose mask is not 0 (bit i). `shears` must be
/// readable for n floats.
using SetupShearedFn = std::uint64_t (*)(const YSetup& ys, const ShearedTri& t, const float* shears,
                                         int n, int width, ViewsSetup& out, ViewsX& x);

/// Vertex lighting (Shading::Vertex) of n vertices: world position transformPoint(worldFromModel,
/// p), normal transformDir(normalFromModel, normal), color shadeBlinnPhong(ctx, material, normal,
/// world) — 3 floats per vertex into `color`. SIMD paths: the same float operations in the same
/// order as lighting.h (glm's scalar code, specularPow vectorized), so bit for bit the scalar
/// result.
using ShadeVerticesFn = void (*)(const glm::vec3* positions, const glm::vec3* normals,
                                 std::size_t n, const glm::mat4& worldFromModel,
                                 const glm::mat3& normalFromModel, const ShadingContext& ctx,
                                 const Material& material, float* color);

/// transformPoint(m, positions[i]) for n vertices, stored split: x[i], y[i], z[i], w[i] (e.g. the
/// center clip positions of the vertex stage). Bit for bit pipeline.h's transformPoint.
using TransformPointsFn = void (*)(const glm::vec3* positions, std::size_t n, const glm::mat4& m,
                                   float* x, float* y, float* z, float* w);

/// out[i] = specularPow(x[i], s) (lighting.h) for n values: the kernels' vectorized pow on its
/// own, for the tests (shadeVertices inlines the same code).
using SpecularPowFn = void (*)(const float* x, std::size_t n, float s, float* out);

/// The fragments of ONE untextured triangle (Vertex or Flat shading: `flat`) in up to 64 views
/// side by side (issue 12): for each lane k of `s` in `lanes` whose mask[k] > 0, the covered 2×2
/// centers of emitSmall(s, k, rowMin, sink) with FragmentSink's depth test and color, into the
/// lane's own view: depth[slot[k]] / color[slot[k]] (images of width × height). The triangle's
/// fragment inputs (depth, 1/w, vertex colors) are the same in every view, so the SIMD paths
/// broadcast them and run the views' fragments as lanes: per lane the same operations in the
/// same order as FragmentSink, hence the same bits. Returns the lanes of `lanes` whose mask is
/// negative (the general walk, rasterTriangle: left to the caller). `slot` must be readable for
/// 64 bytes.
using ShadeLanesFn = std::uint64_t (*)(const ViewsSetup& s, std::uint64_t lanes, int rowMin,
                                       int width, int height, const FragmentTri& tri, bool flat,
                                       const std::uint8_t* slot, float* const* depth,
                                       std::uint32_t* const* color);

/// setupSheared and shadeLanes in one pass, for a long row's untextured Vertex or Flat triangle
/// (issue 12): the x of views [0, n) (n <= kMaxViews: a whole row in one call) derived, the views
/// with a pixel-center column and not in `culled` (bit k % 64 of culled[k / 64]: view k; nullptr:
/// none) set up, and the covered centers of the small ones drawn side by side into depth[k] /
/// color[k] for view k (FragmentSink's depth test and color, as shadeLanes). The views that need
/// the general walk (rasterTriangle) are returned packed in view order in `x` (x.view[i],
/// x.x[j][i]); returns how many. Nothing per view goes through memory but the packed x: the
/// setup stays in registers. A SIMD path may first leave out, for a triangle of one row in the
/// band, the views that cannot cover a center of that row (an estimate of each view's span on
/// the row's center line, widened past what snapping and rounding can move it): it then draws
/// the same pixels and returns a subset of those views (the ones left out would draw nothing).
/// depth and color must be readable for kMaxViews entries, shears for n rounded up to 8.
/// blockStride: 0, or — when the call's images lie in one block, as a streamed band's scratch
/// does — the pixels between consecutive slots' images (depth[s] == depth[0] + s · blockStride,
/// color[s] == color[0] + s · blockStride for every s < n; n · blockStride < 2^30): a kernel may
/// then address a lane's pixel as a 32-bit offset from depth[0] / color[0] instead of gathering
/// its view's address from the tables.
using DrawShearedFn = int (*)(const YSetup& ys, const ShearedTri& t, const float* shears, int n,
                              const std::uint64_t* culled, int width, int height,
                              const FragmentTri& tri, bool flat, float* const* depth,
                              std::uint32_t* const* color, std::int32_t blockStride, ViewsX& x);

/// A sheared row's guard-band bits: any[k] |= the kClipX bits of outcodeX(x, w[k]) for
/// x = shearClipWc(cx[k], s, w[k] − convergence) at s = lo and at s = hi — the row's outermost
/// shears: x is monotone in the shear (a float multiply by a fixed w − c and an add are), so
/// these are the OR over every view of the row.
using RowClipXFn = void (*)(const float* cx, const float* w, std::size_t n, float lo, float hi,
                            float convergence, std::uint8_t* any);

/// A sheared row's snapped x, interleaved as Family::sxv keeps it (issue 12's vertex stage):
/// sxv[i · nv + k] = snapX(x, q[i], width) for x = shearClip(cx[i], shears[k], w[i],
/// convergence), or 0 where outcodeX(x, w[i]) has a kClipX bit — what shearClip + projectX
/// store for view k, one row of nv <= kLaneBlock views at once, nothing per view in memory.
using RowSnapXFn = void (*)(const float* cx, const float* w, const float* q, std::size_t n,
                            const float* shears, int nv, float convergence, float width,
                            std::int32_t* sxv);

struct Kernels {
    ProjectYZWFn projectYZW;
    ProjectXFn projectX;
    SetupViewsFn setupViews;
    ShadeVerticesFn shadeVertices;
    TransformPointsFn transformPoints;
    SpecularPowFn specularPow;
    SetupLanesFn setupLanes;      ///< lanes.h: (triangle, view) pairs side by side
    SetupShearedFn setupSheared;  ///< long sheared rows: x derived from the center per view
    ShadeLanesFn shadeLanes;      ///< one triangle's fragments in many views side by side
    /// setupSheared + shadeLanes fused (every table has one; a nullptr would make the caller
    /// run the two kernels)
    DrawShearedFn drawSheared;
    RowClipXFn rowClipX;  ///< a long row's guard-band bits from its outermost shears
    /// lanes.h: setupLanes and the lanes' fragments side by side; nullptr where the ISA has no
    /// such kernel (the queue's ordered walk then draws every lane)
    DrawLanesFn drawLanes = nullptr;
    RowSnapXFn rowSnapX = nullptr;  ///< a sheared row's interleaved snapped x (every table)
};

/// The kernel table of a path (resolved first, so always a valid table).
const Kernels& kernels(SimdPath path);

// Per-ISA tables (simd/kernels_*.cpp).
const Kernels& scalarKernels();
const Kernels* avx2Kernels();    ///< nullptr when not built
const Kernels* avx512Kernels();  ///< nullptr when not built

}  // namespace mvr::raster::detail
