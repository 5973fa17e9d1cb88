// src/raster/multipass.cpp — the reference: N independent single-view renders.
//
// Per view: vertex stage (lighting, transform, outcodes, projection), primitive stage (trivial
// reject, back-face cull, binning into bands), raster stage (clip if needed, setup, coverage,
// depth, shading). Nothing is shared between views except the cleared framebuffers' layout.
//
// Choice for bit-exactness with "unified" (documented in soft_backend.h): a view that has
// View::clipShear gets its clip position as the rig's center clip position sheared,
// x = x_c + s_x(w − c), y = y_c + s_y(w − c) — the form the unified pipeline computes once per
// vertex — and its back-face test uses the same linear form of det[x, y, w]. Views without a
// shear use their own clipFromWorld matrix.
#include "methods.h"
#include "wireframe.h"

namespace mvr::raster::detail {

namespace {

struct ViewVertexData : MethodScratch {
    std::vector<float> x, y, z, w, cx, cy;     // clip (and center clip x, y for sheared views)
    std::vector<std::int32_t> sx, sy;          // snapped window position
    std::vector<float> zw, q;                  // window depth, 1/w
    std::vector<std::uint8_t> codeYZW, codeX;  // outcodes
    std::vector<float> attr;                   // attrStride floats per vertex
    std::size_t attrStride = 0;                // attributeCount(shading): only what is interpolated
    std::vector<glm::vec3> world;              // world positions (Flat's face normal)
    Bins bins;
    BandBuffers bandBuffers;  ///< streamed bands: per worker, one band's rows of the view

    void resize(std::size_t n, Shading shading, bool textured, bool colored, bool tangents) {
        for (auto* v : {&x, &y, &z, &w, &cx, &cy, &zw, &q}) v->resize(n);
        attrStride = std::size_t(attributeCount(shading, textured, colored, tangents));
        sx.resize(n), sy.resize(n), codeYZW.resize(n), codeX.resize(n), attr.resize(n * attrStride);
        world.resize(shading == Shading::Flat ? n : 0);
    }
    const float* attrOf(std::uint32_t v) const { return attr.data() + v * attrStride; }
};

/// Outcodes of a triangle: AND (trivial reject) and OR (clip planes) over its vertices.
struct TriCodes {
    std::uint8_t andYZW, andX, orYZW, orX;
    bool rejected() const { return (andYZW & kRejectYZW) || (andX & kRejectX); }
    std::uint8_t planes() const { return std::uint8_t((orYZW & kClipYZW) | (orX & kClipX)); }
};

void vertexStage(FrameContext& f, const View& view, ViewVertexData& d) {
    const Shading shading = f.settings.shading;
    const float width = float(f.settings.width), height = float(f.settings.height);
    const bool sheared = view.clipShear.has_value();
    const glm::vec2 shear = sheared ? *view.clipShear : glm::vec2(0.0f);
    const float conv = f.rig.convergence;
    const glm::mat4 viewClip = sheared ? f.centerClip : view.clipFromWorld();
    forVertexChunks(
        f.draw, f.pool, [&](const DrawItem& item, std::uint32_t begin, std::uint32_t end) {
            const glm::mat4 clipFromModel = viewClip * item.instance->worldFromModel;
            const std::uint32_t g = item.vertexBase + begin, count = end - begin;
            // Clip positions (SIMD kernel); a sheared view keeps the center's x, y for the
            // back-face test and shears them.
            f.kernels.transformPoints(&item.mesh->positions[begin], count, clipFromModel,
                                      sheared ? &d.cx[g] : &d.x[g], sheared ? &d.cy[g] : &d.y[g],
                                      &d.z[g], &d.w[g]);
            if (sheared) {
                const float* cx = &d.cx[g];
                const float* cy = &d.cy[g];
                const float* cw = &d.w[g];
                float* x = &d.x[g];
                float* y = &d.y[g];
                for (std::uint32_t k = 0; k < count; ++k)
                    x[k] = shearClip(cx[k], shear.x, cw[k], conv);
                for (std::uint32_t k = 0; k < count; ++k)
                    y[k] = shearClip(cy[k], shear.y, cw[k], conv);
            }
            // Vertex: below, unless the frame or item needs the scalar path (textures, point
            // lights, double-sided).
            const bool scalarLit = f.scalarVertexPath(item);
            for (std::uint32_t i = begin; i < end && (shading != Shading::Vertex || scalarLit);
                 ++i) {
                const std::uint32_t gi = item.vertexBase + i;
                const glm::vec3& p = item.mesh->positions[i];
                const glm::vec3 world = glm::vec3(transformPoint(item.instance->worldFromModel, p));
                if (f.textured) {
                    if (shading == Shading::Flat) d.world[gi] = world;
                    f.texturedAttributes(item, i, world, d.attr.data() + gi * d.attrStride);
                } else if (shading == Shading::Flat) {
                    d.world[gi] = world;
                } else {
                    vertexAttributes(shading, f.shading, item.instance->material, world,
                                     transformDir(item.normalFromModel, item.mesh->normals[i]),
                                     d.attr.data() + gi * d.attrStride);
                }
            }
            if (shading == Shading::Vertex && !scalarLit) {
                f.kernels.shadeVertices(&item.mesh->positions[begin], &item.mesh->normals[begin],
                                        count, item.instance->worldFromModel, item.normalFromModel,
                                        f.shading, item.instance->material,
                                        d.attr.data() + g * d.attrStride);
            }
            f.kernels.projectYZW(&d.y[g], &d.z[g], &d.w[g], count, height, &d.codeYZW[g], &d.q[g],
                                 &d.sy[g], &d.zw[g]);
            f.kernels.projectX(&d.x[g], &d.w[g], &d.q[g], count, width, &d.codeX[g], &d.sx[g]);
        });
}

/// A triangle's outcodes from the per-vertex y/z/w and x codes (raw pointers: the hot callers
/// load them once, not after every store that might alias the vectors' internals).
TriCodes triCodes(const std::uint8_t* y, const std::uint8_t* x, const std::uint32_t v[3]) {
    return {std::uint8_t(y[v[0]] & y[v[1]] & y[v[2]]), std::uint8_t(x[v[0]] & x[v[1]] & x[v[2]]),
            std::uint8_t(y[v[0]] | y[v[1]] | y[v[2]]), std::uint8_t(x[v[0]] | x[v[1]] | x[v[2]])};
}

/// Back-face test: true when the triangle is culled in this view.
bool culled(const FrameContext& f, const View& view, const ViewVertexData& d,
            const TriangleRef& t) {
    if (!f.settings.cullBackFaces || t.item->instance->material.doubleSided) return false;
    const float w[3] = {d.w[t.i[0]], d.w[t.i[1]], d.w[t.i[2]]};
    float det;
    if (view.clipShear) {
        const float cx[3] = {d.cx[t.i[0]], d.cx[t.i[1]], d.cx[t.i[2]]};
        const float cy[3] = {d.cy[t.i[0]], d.cy[t.i[1]], d.cy[t.i[2]]};
        det = shearedDet(shearDet(cx, cy, w, f.rig.convergence), view.clipShear->x,
                         view.clipShear->y);
    } else {
        const float x[3] = {d.x[t.i[0]], d.x[t.i[1]], d.x[t.i[2]]};
        const float y[3] = {d.y[t.i[0]], d.y[t.i[1]], d.y[t.i[2]]};
        det = det3(x, y, w);
    }
    return det < 0.0f;
}

void binStage(FrameContext& f, const View& view, const ViewVertexData& d, Bins& bins) {
    bins.reset(f.draw.triangleCount, f.bands.count);
    f.pool.run(bins.chunkCount, [&](int chunk, int) {
        const std::uint32_t begin = bins.chunkSize * std::uint32_t(chunk);
        const std::uint32_t end = std::min(f.draw.triangleCount, begin + bins.chunkSize);
        // The arrays' pointers in registers (through the vectors they were reloaded after every
        // bin's push_back: 1024x768, binning 2.66 -> 2.48 ms).
        const std::uint8_t* codeYZW = d.codeYZW.data();
        const std::uint8_t* codeX = d.codeX.data();
        const std::int32_t* sy = d.sy.data();
        const BandLayout bands = f.bands;
        const int height = f.settings.height;
        const bool wireframe = f.settings.wireframe, cull = f.settings.cullBackFaces;
        const DrawItem* item = nullptr;
        forItemTriangles(
            f.draw, begin, end, [&](const DrawItem& it) { item = &it; },
            [&](std::uint32_t t, const std::uint32_t v[3]) {
                const TriCodes codes = triCodes(codeYZW, codeX, v);
                if (codes.rejected()) return;
                if (cull && culled(f, view, d, TriangleRef{{v[0], v[1], v[2]}, item})) return;
                int rowMin = 0, rowMax = height - 1;
                if (!codes.planes()) {
                    if (wireframe) {
                        wireframeRows(sy[v[0]], sy[v[1]], sy[v[2]], height, rowMin, rowMax);
                    } else {  // a direct call, so that it is inlined (not through a function pointer)
                        triangleRows(sy[v[0]], sy[v[1]], sy[v[2]], height, rowMin, rowMax);
                    }
                }
                if (rowMin <= rowMax) bins.add(chunk, t, rowMin, rowMax, bands);
            });
    });
}

/// The three edges of a triangle as lines, this view on its own: near/far clip, projection,
/// Liang–Barsky against left, right, bottom, top.
template <class SinkT>
void drawWireframe(const FrameContext& f, const ViewVertexData& d, const std::uint32_t v[3],
                   const Target& target, int rowLo, int rowHi, SinkT& sink, FragmentTri& frag) {
    const int attrCount = attributeCount(f.settings.shading, f.textured, f.colored, f.tangents);
    const float width = float(target.width), height = float(target.height);
    for (int edge = 0; edge < 3; ++edge) {
        const std::uint32_t i0 = v[edge], i1 = v[edge == 2 ? 0 : edge + 1];
        LineEnds e;
        e.y[0] = d.y[i0], e.z[0] = d.z[i0], e.w[0] = d.w[i0], e.x[0][0] = d.x[i0];
        e.y[1] = d.y[i1], e.z[1] = d.z[i1], e.w[1] = d.w[i1], e.x[1][0] = d.x[i1];
        e.a[0] = d.attrOf(i0), e.a[1] = d.attrOf(i1);
        float attr[2][kMaxAttrs];
        if (!clipLineNearFar(e, 1, attrCount, attr)) continue;
        float xw[2], yw[2];
        for (int j = 0; j < 2; ++j) {
            const float q = 1.0f / e.w[j];
            xw[j] = windowCoord(e.x[j][0], q, width);
            yw[j] = windowCoord(e.y[j], q, height);
            frag.z[j] = windowDepth(e.z[j], q);
            frag.q[j] = q;
            frag.attr[j] = e.a[j];
        }
        frag.z[2] = frag.z[1], frag.q[2] = frag.q[1], frag.attr[2] = frag.attr[1];
        float t0 = 0.0f, t1 = 1.0f;
        if (!liangBarskyAxis(xw[0], xw[1] - xw[0], 0.0f, width, t0, t1)) continue;
        if (!liangBarskyAxis(yw[0], yw[1] - yw[0], 0.0f, height, t0, t1)) continue;
        rasterLine(xw[0], yw[0], xw[1], yw[1], t0, t1, target.width, target.height, rowLo, rowHi,
                   sink);
    }
}

template <Shading S>
void rasterStage(FrameContext& f, ViewVertexData& d, const Bins& bins, const Target& image,
                 int view) {
    const int attrCount = attributeCount(S, f.textured, f.colored, f.tangents);
    const std::uint32_t clear = packColor(f.settings.clearColor);
    // Streamed bands (as unified's, FrameContext::streamBands): each worker draws a band into a
    // scratch that stays in its cache and streams the rows into the image (written once, never
    // read from memory); otherwise each band's rows of the image are cleared just before they
    // are drawn.
    const bool stream = f.streamBands;
    if (stream) d.bandBuffers.resize(f.pool.size(), std::size_t(f.bands.rows) * image.width);
    f.pool.run(f.bands.count, [&](int band, int worker) {
        const int rowLo = f.bands.rowBegin(band), rowHi = f.bands.rowEnd(band) - 1;
        Target target = image;
        if (stream) {
            target = d.bandBuffers.target(worker, 0, image);
            target.offset = image.index(0, rowHi);
        }
        clearRows(target, rowLo, rowHi, clear);  // into the cache just before it is drawn
        FragmentTri frag{};
        FragmentSink<S> sink{target, &frag, {&f.shadingOf(std::size_t(view)), nullptr, f.textured, nullptr, f.colored}};
        // Small triangles wait in a queue and are set up 16 at a time (lanes.h), as in unified;
        // everything drawn directly flushes the queue first (submission order).
        LaneQueue<S> queue;
        // The queue's fragments side by side (drawLanes); a slot is one lane here, so the
        // kernel reads the vertex colors of the lanes that pass a depth test only.
        queue.useDrawLanes(f.kernels.drawLanes, f.textured, &target, 1, false);
        auto flush = [&] {
            queue.flush(f.kernels.setupLanes, target.width,
                        [&](int) -> FragmentSink<S>& { return sink; });
        };
        const Material* material = nullptr;
        auto onItem = [&](const DrawItem& it) {
            flush();  // the queued triangles shade with the previous material
            material = &it.instance->material;
            f.setMaterial(sink.shade, *material);
        };
        forBandTriangles(f.draw, bins, band, f.bands.count, onItem, [&](const std::uint32_t v[3]) {
            if constexpr (S == Shading::Flat) {
                setFlat(frag, f.textured, f.shading, *material, d.world[v[0]], d.world[v[1]],
                        d.world[v[2]]);
            }
            if (f.settings.wireframe) {
                flush();
                drawWireframe(f, d, v, target, rowLo, rowHi, sink, frag);
                return;
            }
            const std::uint8_t planes = triCodes(d.codeYZW.data(), d.codeX.data(), v).planes();
            if (!planes) {
                YSetup ys;
                setupY(ys, d.sy[v[0]], d.sy[v[1]], d.sy[v[2]], rowLo, rowHi);
                if (ys.rowMin > ys.rowMax) return;  // (rasterTriangle would draw nothing)
                for (int j = 0; j < 3; ++j) {
                    frag.z[j] = d.zw[v[j]];
                    frag.q[j] = d.q[v[j]];
                    frag.attr[j] = d.attrOf(v[j]);
                }
                if (queue.needsFlush(1)) flush();
                queue.addLane(queue.addTriangle(frag), ys, 0, d.sx[v[0]], d.sx[v[1]], d.sx[v[2]]);
            } else {
                flush();
                ClipVertex poly[kMaxPolyVerts];
                for (int j = 0; j < 3; ++j) {
                    ClipVertex& cv = poly[j];
                    cv.x = d.x[v[j]], cv.y = d.y[v[j]], cv.z = d.z[v[j]], cv.w = d.w[v[j]];
                    std::copy_n(d.attrOf(v[j]), attrCount, cv.a);
                }
                drawClippedPolygon(poly, 3, planes, attrCount, target, rowLo, rowHi, sink, frag);
            }
        });
        flush();
        if (stream) streamRows({&target, 1}, {&image, 1}, rowLo, rowHi);
    });
}

}  // namespace

void renderMultipass(FrameContext& f, std::span<const Target> targets, StageTimes& times,
                     std::unique_ptr<MethodScratch>& scratch) {
    if (!dynamic_cast<ViewVertexData*>(scratch.get())) scratch = std::make_unique<ViewVertexData>();
    ViewVertexData& d = static_cast<ViewVertexData&>(*scratch);
    d.resize(f.draw.vertexCount, f.settings.shading, f.textured, f.colored, f.tangents);
    Bins& bins = d.bins;
    for (int v = 0; v < f.rig.viewCount(); ++v) {
        const View& view = f.rig.views[std::size_t(v)];
        StageClock clock;
        vertexStage(f, view, d);
        times.vertexMs += clock.lap();
        binStage(f, view, d, bins);
        times.setupMs += clock.lap();
        switch (f.settings.shading) {
            case Shading::Flat: rasterStage<Shading::Flat>(f, d, bins, targets[v], v); break;
            case Shading::Vertex: rasterStage<Shading::Vertex>(f, d, bins, targets[v], v); break;
            case Shading::Pixel: rasterStage<Shading::Pixel>(f, d, bins, targets[v], v); break;
        }
        times.rasterMs += clock.lap();
    }
}

}  // namespace mvr::raster::detail
