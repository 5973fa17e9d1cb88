// src/raster/unified_bin.cpp — the unified method's bin stage (unified.h): each triangle's bands
// from its families' codes and snapped y, with trivial reject and adelson1991's back-face test.
#include "unified.h"

#include <algorithm>
#include <type_traits>
#include <vector>

#include "wireframe.h"

namespace mvr::raster::detail {

void binStage(FrameContext& f, UnifiedData& d) {
    Bins& bins = d.bins;
    bins.reset(f.draw.triangleCount, f.bands.count);
    const bool cull = f.settings.cullBackFaces;
    const int height = f.settings.height;
    const bool wireframe = f.settings.wireframe;
    // The families' arrays, read straight: through the vectors, every triangle reloaded them
    // (the bins' push_back could alias them as far as the compiler knew).
    struct FamilyBin {
        const Family* fam;
        const std::uint8_t* code;
        const std::int32_t* sy;
    };
    std::vector<FamilyBin> families;
    for (const Family& fam : d.families) families.push_back({&fam, fam.code.data(), fam.sy.data()});
    // Sheared families without culling (a row or stereo pair: one; a grid: one per row of
    // views) are binned from their two outermost rows alone. A vertex's y, hence its snapped y,
    // is monotone in shear.y (a float multiply by a fixed w − c and an add are, and so is
    // snapping for w > 0); every family's kClipX bits are the same (the OR over all rows: one
    // anyClipX) and so are the z/w bits. So a row between the outermost shears covers rows
    // between theirs, lies outside the guard band only where an outer row does, and is rejected
    // by a plane where both outer rows are: their union is conservative for every row. One
    // family is its own outer pair. (Also the faster loop: pointers in registers, no per-family
    // bookkeeping — 1024x768, binning of a stereo pair 3.4 -> 2.3 ms, of a 3x3 grid 5.9 -> 2.9;
    // for one family a loop reading its arrays once measured slower, 3.2 ms.)
    const FamilyBin* outer[2] = {nullptr, nullptr};
    if (!cull && std::all_of(d.families.begin(), d.families.end(),
                             [](const Family& fam) { return fam.sheared; })) {
        outer[0] = outer[1] = &families[0];
        for (const FamilyBin& fb : families) {
            if (fb.fam->shearY < outer[0]->fam->shearY) outer[0] = &fb;
            if (fb.fam->shearY > outer[1]->fam->shearY) outer[1] = &fb;
        }
    }
    auto binOuter = [&](int chunk) {
        const BandLayout bands = f.bands;
        const std::uint32_t begin = bins.chunkSize * std::uint32_t(chunk);
        const std::uint32_t end = std::min(f.draw.triangleCount, begin + bins.chunkSize);
        const std::uint8_t* ca = outer[0]->code;
        const std::uint8_t* cb = outer[1]->code;
        const std::int32_t* ya = outer[0]->sy;
        const std::int32_t* yb = outer[1]->sy;
        forItemTriangles(
            f.draw, begin, end, [](const DrawItem&) {},
            [&](std::uint32_t t, const std::uint32_t v[3]) {
                const std::uint8_t a0 = ca[v[0]], a1 = ca[v[1]], a2 = ca[v[2]];
                const std::uint8_t b0 = cb[v[0]], b1 = cb[v[1]], b2 = cb[v[2]];
                if (a0 & a1 & a2 & b0 & b1 & b2 & kRejectYZW) return;
                int rowMin = 0, rowMax = height - 1;
                if (!((a0 | a1 | a2 | b0 | b1 | b2) & (kClipYZW | kClipX))) {
                    const std::int32_t ya0 = ya[v[0]], ya1 = ya[v[1]], ya2 = ya[v[2]];
                    const std::int32_t yb0 = yb[v[0]], yb1 = yb[v[1]], yb2 = yb[v[2]];
                    const std::int32_t lo = std::min(std::min(std::min(ya0, ya1), ya2),
                                                     std::min(std::min(yb0, yb1), yb2));
                    const std::int32_t hi = std::max(std::max(std::max(ya0, ya1), ya2),
                                                     std::max(std::max(yb0, yb1), yb2));
                    if (wireframe) {
                        wireframeRows(lo, hi, hi, height, rowMin, rowMax);
                    } else {
                        triangleRows(lo, hi, hi, height, rowMin, rowMax);
                    }
                }
                if (rowMin <= rowMax) bins.add(chunk, t, rowMin, rowMax, bands);
            });
    };
    // One family (a row, the stereo pair): its loop unrolled, nothing kept across families; each
    // draw item's culling flag once (forItemTriangles' onItem).
    auto binChunk = [&](int chunk, auto single) {
        const FamilyBin* famBegin = families.data();
        const FamilyBin* famEnd = single ? famBegin + 1 : famBegin + families.size();
        const BandLayout bands = f.bands;
        const std::uint32_t begin = bins.chunkSize * std::uint32_t(chunk);
        const std::uint32_t end = std::min(f.draw.triangleCount, begin + bins.chunkSize);
        bool cullTri = false;  // the item's: culling on and its material not double-sided
        auto onItem = [&](const DrawItem& item) {
            cullTri = cull && !item.instance->material.doubleSided;
        };
        forItemTriangles(
            f.draw, begin, end, onItem, [&](std::uint32_t t, const std::uint32_t v[3]) {
                ShearDet det;
                if (cullTri && d.anySheared) det = triangleShearDet(d, v, f.rig.convergence);
                int rowMin = height, rowMax = -1;
                for (const FamilyBin* fb = famBegin; fb != famEnd; ++fb) {
                    const std::uint8_t* code = fb->code;
                    const std::uint8_t c0 = code[v[0]], c1 = code[v[1]], c2 = code[v[2]];
                    if (c0 & c1 & c2 & kRejectYZW) continue;
                    if (cullTri) {
                        const Family& fam = *fb->fam;
                        if (fam.sheared ? classify(fam, det) == FaceClass::AllBack
                                        : ownViewCulled(d, fam, v)) {
                            continue;
                        }
                    }
                    if ((c0 | c1 | c2) & (kClipYZW | kClipX)) {  // kClipX: any view's: anyClipX
                        rowMin = 0, rowMax = height - 1;
                        break;
                    }
                    const std::int32_t* sy = fb->sy;
                    int lo, hi;
                    if (wireframe) {
                        wireframeRows(sy[v[0]], sy[v[1]], sy[v[2]], height, lo, hi);
                    } else {
                        triangleRows(sy[v[0]], sy[v[1]], sy[v[2]], height, lo, hi);  // inlined
                    }
                    if (lo > hi) continue;
                    rowMin = std::min(rowMin, lo), rowMax = std::max(rowMax, hi);
                }
                if (rowMin <= rowMax) bins.add(chunk, t, rowMin, rowMax, bands);
            });
    };
    const bool single = families.size() == 1;
    f.pool.run(bins.chunkCount, [&](int chunk, int) {
        if (outer[0]) {
            binOuter(chunk);
        } else if (single) {
            binChunk(chunk, std::true_type{});
        } else {
            binChunk(chunk, std::false_type{});
        }
    });
}

}  // namespace mvr::raster::detail
