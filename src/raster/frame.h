// src/raster/frame.h — what one soft render needs around the pipeline: the flattened draw list,
// per-instance matrices, the band (screen tile) layout, triangle bins, and timing.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/render.h"
#include "mvr/raster/soft_backend.h"
#include "cpu.h"
#include "pipeline.h"
#include "thread_pool.h"

namespace mvr::raster::detail {

/// One instance of the scene with its vertex and triangle offsets in the frame's global
/// numbering (triangles are drawn in instance order, then mesh order, by both methods; instances
/// with AlphaMode::Blend come after all others, in instance order, unsorted — lighting.h).
struct DrawItem {
    const Mesh* mesh;
    const Instance* instance;
    std::uint32_t vertexBase, triangleBase;
    glm::mat3 normalFromModel;  ///< transpose(inverse(mat3(worldFromModel)))
};

struct DrawList {
    std::vector<DrawItem> items;
    std::uint32_t vertexCount = 0, triangleCount = 0;
};

DrawList makeDrawList(const Scene& scene);

struct TriangleRef {
    std::uint32_t i[3];
    const DrawItem* item;
};

/// Iterates the triangles [begin, end) of the frame: onItem(item) once before each draw item's
/// triangles in the range (per-item state: its material's flags), then fn(t, v) per triangle
/// with its global vertex indices v[3].
template <class OnItem, class Fn>
void forItemTriangles(const DrawList& draw, std::uint32_t begin, std::uint32_t end, OnItem&& onItem,
                      Fn&& fn) {
    for (const DrawItem& item : draw.items) {
        const std::uint32_t tBegin = std::max(begin, item.triangleBase);
        const std::uint32_t tEnd =
            std::min(end, item.triangleBase + std::uint32_t(item.mesh->triangleCount()));
        if (tBegin >= tEnd) continue;
        onItem(item);
        const std::uint32_t* idx =
            item.mesh->indices.data() + std::size_t(3) * (tBegin - item.triangleBase);
        const std::uint32_t base = item.vertexBase;
        for (std::uint32_t t = tBegin; t < tEnd; ++t, idx += 3) {
            const std::uint32_t v[3] = {base + idx[0], base + idx[1], base + idx[2]};
            fn(t, v);
        }
    }
}

/// Iterates the triangles [begin, end) of the frame with their global vertex indices and item.
template <class Fn>
void forTriangles(const DrawList& draw, std::uint32_t begin, std::uint32_t end, Fn&& fn) {
    const DrawItem* current = nullptr;
    forItemTriangles(
        draw, begin, end, [&](const DrawItem& item) { current = &item; },
        [&](std::uint32_t t, const std::uint32_t v[3]) {
            fn(t, TriangleRef{{v[0], v[1], v[2]}, current});
        });
}

/// The rig's center clip transform, from which sheared views derive (rig.h: View::clipShear).
glm::mat4 centerClipFromWorld(const Rig& rig);

/// Screen tiles: horizontal bands of rows (GL window y, up) spanning every view.
struct BandLayout {
    int count = 1, rows = 1, height = 1;
    /// ceil(2^40 / rows): bandOf() without a division (binning calls it twice per triangle).
    std::uint64_t rowsReciprocal = std::uint64_t(1) << 40;
    int rowBegin(int band) const { return band * rows; }
    int rowEnd(int band) const { return std::min(height, (band + 1) * rows); }
    /// row / rows for 0 <= row < 2^20, exactly: row · rowsReciprocal / 2^40 = row / rows + δ with
    /// 0 <= δ < row / 2^40 < 1 / rows (row · rows < 2^40), too little to reach the next integer.
    int bandOf(int row) const { return int((std::uint64_t(row) * rowsReciprocal) >> 40); }
};
/// bytesPerRow: what one row of the targets a band draws into occupies (width × 8 bytes × views),
/// 0: no limit from it.
BandLayout makeBands(int height, int threads, std::size_t bytesPerRow = 0);

/// Triangle indices per (chunk of the triangle range, band). Reading a band's lists chunk by chunk
/// gives its triangles in submission order, so depth ties resolve the same in every method.
struct Bins {
    int chunkCount = 0;
    std::uint32_t chunkSize = 1;
    std::vector<std::vector<std::uint32_t>> lists;  ///< [chunk * bands + band]

    void reset(std::uint32_t triangleCount, int bands);
    /// Appends triangle t to every band overlapping pixel rows [rowMin, rowMax].
    void add(int chunk, std::uint32_t t, int rowMin, int rowMax, const BandLayout& layout) {
        const int b0 = layout.bandOf(std::max(0, rowMin));
        const int b1 = std::min(layout.count - 1, layout.bandOf(std::max(0, rowMax)));
        for (int b = b0; b <= b1; ++b) lists[std::size_t(chunk) * layout.count + b].push_back(t);
    }
};

/// The triangles of one band in submission order (its lists chunk by chunk), with their global
/// vertex indices: onItem(item) first whenever the draw item changes (material, instance), then
/// fn(v) for the triangle.
template <class OnItem, class Fn>
void forBandTriangles(const DrawList& draw, const Bins& bins, int band, int bandCount,
                      OnItem&& onItem, Fn&& fn) {
    std::size_t item = 0;
    std::uint32_t itemEnd = 0;
    const DrawItem* it = nullptr;
    for (int chunk = 0; chunk < bins.chunkCount; ++chunk) {
        for (std::uint32_t t : bins.lists[std::size_t(chunk) * bandCount + band]) {
            if (!it || t >= itemEnd) {
                while (t >= draw.items[item].triangleBase + draw.items[item].mesh->triangleCount())
                    ++item;
                it = &draw.items[item];
                itemEnd = it->triangleBase + std::uint32_t(it->mesh->triangleCount());
                onItem(*it);
            }
            const std::uint32_t* idx = &it->mesh->indices[std::size_t(t - it->triangleBase) * 3];
            const std::uint32_t v[3] = {it->vertexBase + idx[0], it->vertexBase + idx[1],
                                        it->vertexBase + idx[2]};
            fn(v);
        }
    }
}

/// Runs fn(item, begin, end) on chunks of about 4096 vertices of every draw item, all items in ONE
/// parallel pass (one fork/join per vertex stage rather than one per instance).
template <class Fn>
void forVertexChunks(const DrawList& draw, ThreadPool& pool, Fn&& fn) {
    std::vector<std::uint32_t> firstTask(draw.items.size() + 1, 0);
    for (std::size_t i = 0; i < draw.items.size(); ++i) {
        const std::uint32_t n = std::uint32_t(draw.items[i].mesh->positions.size());
        firstTask[i + 1] = firstTask[i] + std::max(1u, n / 4096u);
    }
    pool.run(int(firstTask.back()), [&](int task, int) {
        const std::size_t i =
            std::size_t(std::upper_bound(firstTask.begin(), firstTask.end(), std::uint32_t(task)) -
                        firstTask.begin() - 1);
        const DrawItem& item = draw.items[i];
        const std::uint32_t n = std::uint32_t(item.mesh->positions.size());
        const std::uint32_t chunks = firstTask[i + 1] - firstTask[i];
        const std::uint32_t chunk = std::uint32_t(task) - firstTask[i];
        fn(item, std::uint32_t(n * std::uint64_t(chunk) / chunks),
           std::uint32_t(n * std::uint64_t(chunk + 1) / chunks));
    });
}

/// Outputs sized for the views, plus Targets pointing into them; new buffers are allocated on
/// the pool's workers. The images are not cleared here: each method's raster task clears the
/// rows of its band (clearRows) just before drawing them — or, for a streamed band (unified,
/// FrameContext::streamBands), clears its scratch and copies the rows in (streamRows) — so that
/// a frame touches its images once: clearing them all up front wrote every line out to memory
/// and the raster read it back (at 100 views of 420x560, 188 MB a frame).
void allocateOutputs(ThreadPool& pool, RenderOutput& out, int views, const RenderSettings& settings,
                     std::vector<Target>& targets);

/// Streamed bands' scratch (FrameContext::streamBands): per worker `pixels` values of color and
/// depth, kept frame after frame (unified: one band's rows of every view; multipass: of the view).
struct BandBuffers {
    std::vector<std::vector<std::uint32_t>> color;
    std::vector<std::vector<float>> depth;

    void resize(int workers, std::size_t pixels) {
        color.resize(std::size_t(workers)), depth.resize(std::size_t(workers));
        for (auto& c : color) c.resize(pixels);
        for (auto& z : depth) z.resize(pixels);
    }
    /// `image` drawn into worker w's buffers from pixel `at` on: the same size, its pointers
    /// there (a band's Target::offset is set per band: image.index(0, rowHi)).
    Target target(int worker, std::size_t at, const Target& image) {
        Target t = image;
        t.color = color[std::size_t(worker)].data() + at;
        t.depth = depth[std::size_t(worker)].data() + at;
        return t;
    }
};

/// Rows [rowLo, rowHi] of every from[v] (a band's scratch) copied into to[v] (the images) with
/// non-temporal stores: the images' lines are written without being read first, and do not
/// evict the scratch from the cache. Ends with one store fence.
void streamRows(std::span<const Target> from, std::span<const Target> to, int rowLo, int rowHi);

/// Rows [rowLo, rowHi] of a target cleared: color to `clear` (packColor of the clear color,
/// alpha 255), depth to 1.
inline void clearRows(const Target& t, int rowLo, int rowHi, std::uint32_t clear) {
    const std::size_t first = t.index(0, rowHi), count = std::size_t(rowHi - rowLo + 1) * t.width;
    std::fill_n(t.color + first, count, clear);
    std::fill_n(t.depth + first, count, 1.0f);
}

/// Pixel rows [rowMin, rowMax] a triangle with snapped window y may cover (whole screen rows).
inline void triangleRows(std::int32_t y0, std::int32_t y1, std::int32_t y2, int height, int& rowMin,
                         int& rowMax) {
    const std::int32_t lo = std::min(y0, std::min(y1, y2)), hi = std::max(y0, std::max(y1, y2));
    rowMin = std::max(0, ceilDivSub(std::int64_t(lo) - kHalfSubpixel));
    rowMax = std::min(height - 1, floorDivSub(std::int64_t(hi) - kHalfSubpixel));
}

class StageClock {
public:
    StageClock() : mLast(std::chrono::steady_clock::now()) {}
    /// Milliseconds since the previous lap (or construction).
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - mLast).count();
        mLast = now;
        return ms;
    }

private:
    std::chrono::steady_clock::time_point mLast;
};

/// Everything a method needs for one render.
struct FrameContext {
    const Scene& scene;
    const Rig& rig;
    const RenderSettings& settings;
    ThreadPool& pool;
    ShadingContext shading;
    DrawList draw;
    BandLayout bands;
    glm::mat4 centerClip;
    const Kernels& kernels;
    /// Textured attribute layout (pipeline.h kMaxAttrs): some material has a texture (any
    /// slot: hasTexture) or an alpha mode other than Opaque. Untextured scenes keep the old layout and images.
    bool textured = false;
    bool punctualLights = false;  ///< some light is a point or spot light
    std::vector<MipChain> mips;   ///< per Scene::textures, built once per render (not per view)
    /// unified: draw each band into a per-worker scratch and stream it into the images (the
    /// frame's images are larger than SoftOptions::streamAboveBytes).
    bool streamBands = false;
    /// Some drawn mesh has vertex colours (Mesh::colors): the textured layout with the colour
    /// after the uv (pipeline.h colorAttribute); such a frame is always textured.
    bool colored = false;
    /// Pixel shading and some drawn material has a normal map on a mesh with tangents: the
    /// textured layout with the world tangent (pipeline.h tangentAttribute).
    bool tangents = false;

    /// --specular per-view (RenderSettings::specular, pixel shading): view v's copy of `shading`
    /// with its own eye (View::eyeWorld) as centerEye; empty otherwise (setViewShading).
    std::vector<ShadingContext> viewShading;
    /// RowStreamingBackend::renderRows (soft_backend.h): unified streams every band (streamBands)
    /// and hands the band's rows of every view here instead of into the images (the targets
    /// then carry only the views' size).
    ViewRowSink* rowSink = nullptr;

    /// The shading context view v's fragments are shaded with.
    const ShadingContext& shadingOf(std::size_t view) const {
        return view < viewShading.size() ? viewShading[view] : shading;
    }
    /// Fills viewShading from `shading` when the settings ask for per-view specular in pixel
    /// shading (the only shading evaluated per view); call after `shading` is final.
    void setViewShading() {
        viewShading.clear();
        if (!shadesFromEachEye(settings)) return;
        viewShading.assign(rig.views.size(), shading);
        for (std::size_t v = 0; v < rig.views.size(); ++v)
            viewShading[v].centerEye = rig.views[v].eyeWorld;
    }

    /// The mip chain of Scene::textures[index], or null (-1, out of range, untextured frame).
    const MipChain* mipsOf(int index) const {
        return index >= 0 && std::size_t(index) < mips.size() ? &mips[std::size_t(index)]
                                                               : nullptr;
    }
    /// Points a fragment sink's inputs at material `m` and its textures (every slot).
    void setMaterial(ShadeInputs& in, const Material& m) const {
        in.material = &m;
        in.texture = mipsOf(m.baseColorTexture);
        in.metallicRoughness = mipsOf(m.metallicRoughnessTexture);
        in.occlusion = mipsOf(m.occlusionTexture);
        in.emissive = mipsOf(m.emissiveTexture);
        in.normal = tangents ? mipsOf(m.normalTexture) : nullptr;
        in.tangents = tangents;
    }
    /// A textured frame's attributes of `item`'s vertex i at world position `world`
    /// (pipeline.h texturedVertexAttributes), the same for every method.
    void texturedAttributes(const DrawItem& item, std::uint32_t i, const glm::vec3& world,
                            float* out) const {
        const Mesh& mesh = *item.mesh;
        glm::vec4 tangent(0.0f, 0.0f, 0.0f, 1.0f);  // none: the normal map is not applied
        if (tangents && !mesh.tangents.empty())
            tangent = worldTangent(item.instance->worldFromModel, mesh.tangents[i]);
        texturedVertexAttributes(settings.shading, shading, item.instance->material, world,
                                 transformDir(item.normalFromModel, mesh.normals[i]),
                                 mesh.texcoords.empty() ? glm::vec2(0.0f) : mesh.texcoords[i],
                                 colored, mesh.colors.empty() ? nullptr : &mesh.colors[i], out,
                                 tangents ? &tangent : nullptr);
    }
    /// Vertex lighting through the scalar lighting.h functions instead of the SIMD kernel
    /// (which implements directional, single-sided Blinn-Phong only, without image lighting).
    bool scalarVertexPath(const DrawItem& item) const {
        const Material& m = item.instance->material;
        return textured || punctualLights || m.doubleSided ||
               m.model != MaterialModel::BlinnPhong || shading.tonemap != Tonemap::None ||
               shading.environment;
    }
};

/// Sets FrameContext::textured, punctualLights and builds the mip chains (in parallel).
void prepareTextures(FrameContext& f);

/// The rasterization stage of a polygon (a triangle, or what the shared planes left of one) whose
/// clip positions need clipping: clip against `planes`, project, and draw the fan for one view.
/// Used by multipass for every clipped triangle and by unified for views whose x needs
/// guard-band clipping after the family's shared planes.
template <class SinkT>
void drawClippedPolygon(ClipVertex* poly, int count, std::uint8_t planes, int attrCount,
                        const Target& target, int rowLo, int rowHi, SinkT& sink,
                        FragmentTri& frag) {
    ClipVertex scratch[kMaxPolyVerts];
    const int n = clipPolygon(poly, count, planes, attrCount, scratch);
    if (n < 3) return;
    std::int32_t px[kMaxPolyVerts], py[kMaxPolyVerts];
    float pz[kMaxPolyVerts], pq[kMaxPolyVerts];
    for (int i = 0; i < n; ++i) {
        if (!(poly[i].w > 0.0f)) return;
        pq[i] = 1.0f / poly[i].w;
        px[i] = snapX(poly[i].x, pq[i], float(target.width));
        py[i] = snapY(poly[i].y, pq[i], float(target.height));
        pz[i] = windowDepth(poly[i].z, pq[i]);
    }
    for (int k = 1; k + 1 < n; ++k) {
        const int idx[3] = {0, k, k + 1};
        YSetup ys;
        setupY(ys, py[0], py[k], py[k + 1], rowLo, rowHi);
        const std::int32_t x[3] = {px[0], px[k], px[k + 1]};
        for (int j = 0; j < 3; ++j) {
            frag.z[j] = pz[idx[j]];
            frag.q[j] = pq[idx[j]];
            frag.attr[j] = poly[idx[j]].a;
        }
        rasterTriangle(ys, x, target.width, sink);
    }
}

}  // namespace mvr::raster::detail
