// src/raster/unified_vertex.cpp — the unified method's families and vertex stage (unified.h;
// the stage-by-stage description is at the top of unified.cpp).
#include <array>
#include <bit>

#include "unified.h"

namespace mvr::raster::detail {

void buildFamilies(const Rig& rig, Shading shading, bool textured, bool colored, bool tangents,
                   std::size_t vertexCount,
                   UnifiedData& d) {
    // The previous frame's families give their per-vertex arrays to this frame's: at many views
    // sxv alone is tens of MB (past glibc's mmap threshold), and allocating it anew every frame
    // cost its page faults and zero fill again (100 views of 208k triangles: ~200 ms a frame).
    std::vector<Family> previous = std::move(d.families);
    d.families.clear();
    d.views.resize(std::size_t(rig.viewCount()));
    d.anySheared = false;
    for (int v = 0; v < rig.viewCount(); ++v) {
        const View& view = rig.views[std::size_t(v)];
        int fam = -1;
        if (view.clipShear) {
            d.anySheared = true;
            for (std::size_t i = 0; i < d.families.size(); ++i) {
                const Family& f = d.families[i];
                // Bitwise equality: the family's y must be the very bits each view would compute.
                if (f.sheared && std::bit_cast<std::uint32_t>(f.shearY) ==
                                     std::bit_cast<std::uint32_t>(view.clipShear->y)) {
                    fam = int(i);
                }
            }
        }
        if (fam < 0) {
            fam = int(d.families.size());
            Family f;
            if (std::size_t(fam) < previous.size()) {
                Family& old = previous[std::size_t(fam)];
                f.y = std::move(old.y), f.z = std::move(old.z), f.w = std::move(old.w);
                f.q = std::move(old.q), f.zw = std::move(old.zw), f.sy = std::move(old.sy);
                f.code = std::move(old.code), f.sxv = std::move(old.sxv);
                f.shears = std::move(old.shears);
                f.shears.clear();
            }
            f.sheared = view.clipShear.has_value();
            f.shearY = f.sheared ? view.clipShear->y : 0.0f;
            f.shearXMin = f.shearXMax = f.sheared ? view.clipShear->x : 0.0f;
            d.families.push_back(std::move(f));
        }
        Family& f = d.families[std::size_t(fam)];
        f.views.push_back(v);
        ViewData& vd = d.views[std::size_t(v)];
        vd.family = fam;
        vd.shearX = view.clipShear ? view.clipShear->x : 0.0f;
        f.shearXMin = std::min(f.shearXMin, vd.shearX);
        f.shearXMax = std::max(f.shearXMax, vd.shearX);
    }
    for (Family& f : d.families) {
        f.many = f.sheared && f.views.size() > std::size_t(kLaneBlock);
        if (!f.many) continue;
        for (int v : f.views) f.shears.push_back(d.views[std::size_t(v)].shearX);
        f.shears.resize((f.shears.size() + 15) / 16 * 16, 0.0f);
    }
    // Sheared views store no x per vertex: the vertex stage writes a row's snapped x straight
    // into its family's interleaved sxv (rows of at most kLaneBlock views) or nothing (`many`),
    // and the slow paths derive a view's x, outcode and snapped x from the centre (viewX, ...).
    for (ViewData& vd : d.views) vd.derived = d.families[std::size_t(vd.family)].sheared;
    // Family twins: sheared rows with the same number of views and, position by position, the
    // same shear.x bits (a grid's rows) have the same snapped x: the later ones read the first
    // one's sxv.
    for (std::size_t fi = 0; fi < d.families.size(); ++fi) {
        Family& f = d.families[fi];
        f.sxvTwin = -1;
        for (std::size_t fj = 0; fj < fi && f.sxvTwin < 0 && f.sheared && !f.many; ++fj) {
            const Family& g = d.families[fj];
            bool same = g.sheared && g.sxvTwin < 0 && g.views.size() == f.views.size();
            for (std::size_t k = 0; same && k < f.views.size(); ++k) {
                same = std::bit_cast<std::uint32_t>(d.views[std::size_t(f.views[k])].shearX) ==
                       std::bit_cast<std::uint32_t>(d.views[std::size_t(g.views[k])].shearX);
            }
            if (same) f.sxvTwin = int(fj);
        }
    }
    const std::size_t n = vertexCount;
    for (Family& f : d.families) {
        for (std::size_t k = 0; k < f.views.size() && k < std::size_t(kLaneBlock); ++k) {
            f.views8[k] = std::uint8_t(f.views[k]);
        }
        f.y.resize(n), f.sy.resize(n), f.code.resize(n);
        if (!f.sheared) f.q.resize(n), f.zw.resize(n);
        // + padding: addLanes reads 8 at a time
        f.sxv.resize(f.sxvTwin < 0 && !f.many ? n * f.views.size() + kLaneBlock : 0);
        if (!f.sheared) f.z.resize(n), f.w.resize(n);
    }
    for (Family& f : d.families) {
        f.sxvData = f.sxvTwin < 0 ? f.sxv.data() : d.families[std::size_t(f.sxvTwin)].sxv.data();
    }
    for (ViewData& vd : d.views) {
        const std::size_t own = vd.derived ? 0 : n;
        vd.x.resize(own), vd.sx.resize(own), vd.code.resize(own);
    }
    d.attrStride = std::size_t(attributeCount(shading, textured, colored, tangents));
    d.world.resize(shading == Shading::Flat ? n : 0), d.attr.resize(n * d.attrStride),
        d.anyClipX.resize(n);
    if (d.anySheared)
        d.cx.resize(n), d.cy.resize(n), d.cz.resize(n), d.cw.resize(n), d.cq.resize(n),
            d.czw.resize(n);
}

void vertexStage(FrameContext& f, UnifiedData& d) {
    const Shading shading = f.settings.shading;
    const float width = float(f.settings.width), height = float(f.settings.height);
    const float conv = f.rig.convergence;
    forVertexChunks(
        f.draw, f.pool, [&](const DrawItem& item, std::uint32_t begin, std::uint32_t end) {
            const glm::mat4 centerFromModel = f.centerClip * item.instance->worldFromModel;
            std::array<glm::mat4, kMaxViews> ownFromModel;
            for (std::size_t fi = 0; fi < d.families.size(); ++fi) {
                if (!d.families[fi].sheared) {
                    const View& view = f.rig.views[std::size_t(d.families[fi].views[0])];
                    ownFromModel[fi] = view.clipFromWorld() * item.instance->worldFromModel;
                }
            }
            const std::uint32_t g = item.vertexBase + begin, count = end - begin;
            // View-independent outputs, once (Vertex: lit below, a chunk at a time, unless
            // the frame or item needs the scalar path: textures, point lights, double-sided).
            const bool scalarLit = f.scalarVertexPath(item);
            for (std::uint32_t i = begin; i < end && (shading != Shading::Vertex || scalarLit);
                 ++i) {
                const std::uint32_t gi = item.vertexBase + i;
                const glm::vec3& p = item.mesh->positions[i];
                if (f.textured) {
                    const glm::vec3 world =
                        glm::vec3(transformPoint(item.instance->worldFromModel, p));
                    if (shading == Shading::Flat) d.world[gi] = world;
                    f.texturedAttributes(item, i, world, d.attr.data() + gi * d.attrStride);
                } else if (shading == Shading::Flat) {
                    d.world[gi] = glm::vec3(transformPoint(item.instance->worldFromModel, p));
                } else {
                    vertexAttributes(shading, f.shading, item.instance->material,
                                     glm::vec3(transformPoint(item.instance->worldFromModel, p)),
                                     transformDir(item.normalFromModel, item.mesh->normals[i]),
                                     d.attr.data() + gi * d.attrStride);
                }
            }
            // View-specific positions: one shared center transform (the shears follow below, per
            // family and view); views without a shear transform with their own matrix.
            const glm::vec3* positions = &item.mesh->positions[begin];
            if (d.anySheared) {
                f.kernels.transformPoints(positions, count, centerFromModel, &d.cx[g], &d.cy[g],
                                          &d.cz[g], &d.cw[g]);
            }
            for (std::size_t fi = 0; fi < d.families.size(); ++fi) {
                Family& fam = d.families[fi];
                if (fam.sheared) continue;
                f.kernels.transformPoints(positions, count, ownFromModel[fi],
                                          &d.views[std::size_t(fam.views[0])].x[g], &fam.y[g],
                                          &fam.z[g], &fam.w[g]);
            }
            if (shading == Shading::Vertex && !scalarLit) {
                f.kernels.shadeVertices(&item.mesh->positions[begin], &item.mesh->normals[begin],
                                        count, item.instance->worldFromModel, item.normalFromModel,
                                        f.shading, item.instance->material,
                                        d.attr.data() + g * d.attrStride);
            }
            for (Family& fam : d.families) {
                if (!fam.sheared) continue;
                const float* cy = &d.cy[g];
                const float* cw = &d.cw[g];
                float* y = &fam.y[g];
                for (std::uint32_t k = 0; k < count; ++k)
                    y[k] = shearClip(cy[k], fam.shearY, cw[k], conv);
            }
            std::fill_n(&d.anyClipX[g], count, std::uint8_t(0));
            for (Family& fam : d.families) {
                f.kernels.projectYZW(&fam.y[g], &d.famZ(fam)[g], &d.famW(fam)[g], count, height,
                                     &fam.code[g], d.famQ(fam) + g, &fam.sy[g], d.famZW(fam) + g);
            }
            for (const Family& fam : d.families) {
                // A sheared row: its outermost views' guard-band bits are every view's (rowClipX;
                // a twin row has the same shears).
                if (fam.sheared && fam.sxvTwin < 0) {
                    f.kernels.rowClipX(&d.cx[g], &d.cw[g], count, fam.shearXMin, fam.shearXMax,
                                       conv, &d.anyClipX[g]);
                }
            }
            // Views with their own matrix: x, outcode and snapped x stored (a one-view family).
            for (ViewData& vd : d.views) {
                if (vd.derived) continue;
                const Family& fam = d.families[std::size_t(vd.family)];
                f.kernels.projectX(&vd.x[g], &d.famW(fam)[g], d.famQ(fam) + g, count, width,
                                   &vd.code[g], &vd.sx[g]);
                // Raw pointers: through the vectors every byte reloaded them (scalar loops).
                const std::uint8_t* code = &vd.code[g];
                std::uint8_t* any = &d.anyClipX[g];
                for (std::uint32_t k = 0; k < count; ++k) any[k] |= code[k] & kClipX;
            }
            for (Family& fam : d.families) {
                if (fam.sxvTwin >= 0 || fam.many) continue;  // twin: its twin's sxv is the same
                const std::size_t nv = fam.views.size();
                std::int32_t* sxv = &fam.sxv[std::size_t(g) * nv];
                if (!fam.sheared) {
                    std::copy_n(&d.views[std::size_t(fam.views[0])].sx[g], count, sxv);
                    continue;
                }
                // A sheared row: each view's snapped x straight into sxv, computed in registers
                // (the guard-band bits: rowClipX above) — nothing per view and vertex in memory.
                float shears[kLaneBlock];
                for (std::size_t lane = 0; lane < nv; ++lane)
                    shears[lane] = d.views[std::size_t(fam.views[lane])].shearX;
                f.kernels.rowSnapX(&d.cx[g], &d.cw[g], d.cq.data() + g, count, shears, int(nv),
                                   conv, width, sxv);
            }
            for (Family& fam : d.families) {
                std::uint8_t* code = &fam.code[g];
                const std::uint8_t* any = &d.anyClipX[g];
                for (std::uint32_t k = 0; k < count; ++k) code[k] |= any[k];
            }
        });
}

}  // namespace mvr::raster::detail
