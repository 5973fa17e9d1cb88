// src/raster/unified.h — the unified method's per-frame data (families of views that share
// y, z, w; per-view x where it is stored; the view-independent vertex outputs), its back-face
// classification of a family (bin and raster stages), its vertex stage (unified_vertex.cpp) and
// bin stage (unified_bin.cpp). The raster stage is in unified.cpp.
#pragma once

#include <vector>

#include "methods.h"

namespace mvr::raster::detail {

/// Views sharing (y, z, w): an off-axis row (same shear.y), or a single unsheared view.
struct Family {
    bool sheared = false;
    /// A sheared row of more than kLaneBlock views (issue 12): its views' x is not stored per
    /// vertex but derived per triangle from the center clip x and `shears` (setupSheared).
    bool many = false;
    std::vector<float> shears;  ///< many: shear.x of views[k], padded to a multiple of 16
    float shearY = 0.0f;
    float shearXMin = 0.0f, shearXMax = 0.0f;
    std::vector<int> views;
    std::uint8_t views8[kLaneBlock] = {};  ///< views as bytes, padded (LaneQueue::addLanes)
    // Per vertex: clip y (z, w: the center's for sheared families, else own), projection.
    std::vector<float> y, z, w, q, zw;
    std::vector<std::int32_t> sy;
    std::vector<std::uint8_t> code;
    /// Snapped window x of every view of the family, interleaved per vertex
    /// (sxv[vertex · views.size() + k]): the raster stage's x setup loads a triangle's x for all
    /// the family's views as three contiguous rows, without a per-view gather.
    std::vector<std::int32_t> sxv;
    /// Another family with the same views' x (the rows of a grid share their columns' x):
    /// its sxv is this family's, and this family's is not filled. −1: none.
    int sxvTwin = -1;
    const std::int32_t* sxvData = nullptr;  ///< sxv, or the twin's
};

/// One view's clip x, snapped window x and left/right outcodes per vertex: stored for a view with
/// its own matrix; a sheared view stores none (`derived`: UnifiedData::viewX, viewCode, viewSx
/// compute them from the centre; the fast paths read its family's sxv or derive x per triangle).
struct ViewData {
    int family = 0;
    float shearX = 0.0f;
    bool derived = false;  ///< a sheared view: x, sx, code are empty (derive them)
    std::vector<float> x;
    std::vector<std::int32_t> sx;
    std::vector<std::uint8_t> code;
};

struct UnifiedData : MethodScratch {
    std::vector<Family> families;
    std::vector<ViewData> views;
    bool anySheared = false;
    // Per vertex, view-independent: world position, attributes, center clip position.
    std::vector<glm::vec3> world;
    std::vector<float> attr;     ///< attrStride floats per vertex
    std::size_t attrStride = 0;  ///< attributeCount(shading): only what is interpolated
    std::vector<float> cx, cy, cz, cw;
    /// OR over all views of the left/right guard-band bits; the vertex stage also ORs it into
    /// every family's code (bits kClipX are free there), so the bin and raster stages read one
    /// byte per vertex for both questions.
    std::vector<std::uint8_t> anyClipX;
    Bins bins;
    BandBuffers
        bandBuffers;  ///< streamed bands (unified.cpp): per worker, one band's rows of every view

    const float* attrOf(std::uint32_t v) const { return attr.data() + v * attrStride; }
    const float* famZ(const Family& f) const { return f.sheared ? cz.data() : f.z.data(); }
    /// 1/w and window depth: functions of (z, w) only, so every sheared family (every row of a
    /// grid) shares one array — the fragment inputs of a triangle are the same for all its rows.
    std::vector<float> cq, czw;
    const float* famQ(const Family& f) const { return f.sheared ? cq.data() : f.q.data(); }
    const float* famZW(const Family& f) const { return f.sheared ? czw.data() : f.zw.data(); }
    float* famQ(Family& f) { return f.sheared ? cq.data() : f.q.data(); }
    float* famZW(Family& f) { return f.sheared ? czw.data() : f.zw.data(); }
    const float* famW(const Family& f) const { return f.sheared ? cw.data() : f.w.data(); }
    float convergence = 0.0f, width = 0.0f;
    /// A view's clip x, outcodeX and snapped x of vertex i: stored, or (sheared views) derived
    /// from the center with the operations the vertex stage uses for sxv and the guard-band bits.
    float viewX(const ViewData& vd, std::uint32_t i) const {
        return vd.derived ? shearClip(cx[i], vd.shearX, cw[i], convergence) : vd.x[i];
    }
    std::uint8_t viewCode(const ViewData& vd, std::uint32_t i) const {
        return vd.derived ? outcodeX(viewX(vd, i), cw[i]) : vd.code[i];
    }
    /// Only where the view's code has no kClipX bit (projectX stores 0 there).
    std::int32_t viewSx(const ViewData& vd, std::uint32_t i) const {
        return vd.derived ? snapX(viewX(vd, i), cq[i], width) : vd.sx[i];
    }
};

/// Back-face classification of a family's views for one triangle (adelson1991): all culled,
/// all kept, or mixed (then per view).
enum class FaceClass { AllBack, AllFront, Mixed };

struct TriangleFaces {
    ShearDet det;  ///< for sheared families (computed once per triangle)
    bool haveDet = false;
};

inline FaceClass classify(const Family& fam, const ShearDet& det) {
    const float lo = shearedDet(det, fam.shearXMin, fam.shearY);
    const float hi = shearedDet(det, fam.shearXMax, fam.shearY);
    if (lo < 0.0f && hi < 0.0f) return FaceClass::AllBack;
    if (lo >= 0.0f && hi >= 0.0f) return FaceClass::AllFront;
    return FaceClass::Mixed;
}

inline ShearDet triangleShearDet(const UnifiedData& d, const std::uint32_t v[3],
                                 float convergence) {
    const float cx[3] = {d.cx[v[0]], d.cx[v[1]], d.cx[v[2]]};
    const float cy[3] = {d.cy[v[0]], d.cy[v[1]], d.cy[v[2]]};
    const float w[3] = {d.cw[v[0]], d.cw[v[1]], d.cw[v[2]]};
    return shearDet(cx, cy, w, convergence);
}

/// det[x, y, w] of an unsheared family's (single) view.
inline bool ownViewCulled(const UnifiedData& d, const Family& fam, const std::uint32_t v[3]) {
    const ViewData& vd = d.views[std::size_t(fam.views[0])];
    const float x[3] = {vd.x[v[0]], vd.x[v[1]], vd.x[v[2]]};
    const float y[3] = {fam.y[v[0]], fam.y[v[1]], fam.y[v[2]]};
    const float w[3] = {fam.w[v[0]], fam.w[v[1]], fam.w[v[2]]};
    return det3(x, y, w) < 0.0f;
}

/// This frame's families and views from the rig, reusing the previous frame's arrays.
void buildFamilies(const Rig& rig, Shading shading, bool textured, bool colored, bool tangents,
                   std::size_t vertexCount,
                   UnifiedData& d);
/// Vertex stage: attributes, center clip position, per family y/z/w projection, per stored view
/// x, and the guard-band bits of all views folded into the families' codes.
void vertexStage(FrameContext& f, UnifiedData& d);
/// Bin stage: each triangle's bands from its families' codes and snapped y (trivial reject,
/// back faces when culling), into d.bins.
void binStage(FrameContext& f, UnifiedData& d);

}  // namespace mvr::raster::detail
