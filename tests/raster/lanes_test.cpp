// setupLanes (lanes.h): every SIMD path equals the scalar reference, and a lane gives the very
// integers setupViews gives the same triangle and view (so queuing lanes cannot change a pixel).
// drawLanes: where it draws, the very pixels of the queue's ordered walk through FragmentSink;
// where it declines, nothing written.
#include <gtest/gtest.h>

#include <bit>
#include <memory>
#include <random>
#include <vector>

#include "cpu.h"
#include "lanes.h"
#include "mvr_test_support.h"

namespace mvr::raster {
namespace {

struct LaneCase {
    detail::TriangleLanes lanes{};
    detail::YSetup ys[detail::kLaneCount];
    int n = 0;
};

// Random small and large triangles, several views each (as the raster queue fills lanes).
LaneCase randomLanes(std::mt19937& rng, bool big) {
    std::uniform_int_distribution<std::int32_t> jitter(-900, 900);
    std::uniform_int_distribution<std::int32_t> pos(-2000, 200000);
    LaneCase c;
    const int target = 1 + int(rng() % detail::kLaneCount);
    while (c.n < target) {
        const std::int32_t cy = pos(rng), cx = pos(rng);
        std::int32_t y[3];
        for (auto& v : y) v = cy + (big ? jitter(rng) * 20 : jitter(rng) / 2);
        detail::YSetup ys;
        detail::setupY(ys, y[0], y[1], y[2], 100, 147);  // a band of 48 rows
        if (ys.rowMin > ys.rowMax) continue;
        const int views = std::min(target - c.n, 1 + int(rng() % 3));
        for (int k = 0; k < views; ++k, ++c.n) {
            for (int i = 0; i < 3; ++i) {
                c.lanes.x[i][c.n] = cx + k * 37 + (big ? jitter(rng) * 20 : jitter(rng) / 2);
                c.lanes.y[i][c.n] = ys.y[i];
            }
            c.lanes.rowMin[c.n] = ys.rowMin, c.lanes.rowMax[c.n] = ys.rowMax;
            c.ys[c.n] = ys;
        }
    }
    return c;
}

void expectSameSetup(const detail::ViewsSetup& got, int gk, const detail::ViewsSetup& ref, int rk,
                     const std::string& where) {
    ASSERT_EQ(got.mask[gk], ref.mask[rk]) << where;
    if (ref.mask[rk] == 0) return;
    ASSERT_EQ(got.colMin[gk], ref.colMin[rk]) << where;
    if (ref.mask[rk] < 0) return;
    ASSERT_EQ(got.area[gk], ref.area[rk]) << where;
    for (int i = 0; i < 3; ++i) {
        ASSERT_EQ(got.e[i][gk], ref.e[i][rk]) << where;
        ASSERT_EQ(got.sx[i][gk], ref.sx[i][rk]) << where;
        ASSERT_EQ(got.sy[i][gk], ref.sy[i][rk]) << where;
        ASSERT_EQ(got.bias[i][gk], ref.bias[i][rk]) << where;
    }
}

TEST(Lanes, EachLaneEqualsSetupViewsOfItsTriangle) {
    std::mt19937 rng(2026);
    int small = 0, general = 0, empty = 0;
    for (int iter = 0; iter < 2000; ++iter) {
        LaneCase c = randomLanes(rng, iter % 4 == 0);
        const std::uint32_t lanes = detail::scalarKernels().setupLanes(c.lanes, c.n, 1024);
        for (int k = 0; k < c.n; ++k) {
            detail::ViewsSetup ref;
            const std::int32_t x0 = c.lanes.x[0][k], x1 = c.lanes.x[1][k], x2 = c.lanes.x[2][k];
            const std::uint64_t refLane =
                detail::scalarKernels().setupViews(c.ys[k], &x0, &x1, &x2, 1, 1024, ref);
            ASSERT_EQ((lanes >> k) & 1u, refLane) << iter << " lane " << k;
            expectSameSetup(c.lanes.out, k, ref, 0,
                            std::to_string(iter) + " lane " + std::to_string(k));
            small += ref.mask[0] > 0, general += ref.mask[0] < 0, empty += ref.mask[0] == 0;
        }
        if (c.n < 32) {
            ASSERT_EQ(lanes >> c.n, 0u) << "no lanes past n";
        }
    }
    EXPECT_GT(small, 1000);
    EXPECT_GT(general, 1000);
    EXPECT_GT(empty, 1000);
}

TEST(Lanes, SimdPathsEqualScalar) {
    std::mt19937 rng(77);
    const SimdPath best = detail::bestSupportedSimd();
    int compared = 0;
    for (int iter = 0; iter < 3000; ++iter) {
        const LaneCase c = randomLanes(rng, iter % 4 == 0);
        detail::TriangleLanes ref = c.lanes;
        const std::uint32_t refLanes = detail::scalarKernels().setupLanes(ref, c.n, 1024);
        for (auto [table, path] : {std::pair{detail::avx2Kernels(), SimdPath::Avx2},
                                   std::pair{detail::avx512Kernels(), SimdPath::Avx512}}) {
            if (!table) continue;
            const detail::SetupLanesFn fn = table->setupLanes;
            if (path == SimdPath::Avx512 && best != SimdPath::Avx512) continue;
            if (path == SimdPath::Avx2 && best == SimdPath::Scalar) continue;
            detail::TriangleLanes got = c.lanes;
            ASSERT_EQ(fn(got, c.n, 1024), refLanes) << iter << " " << simdPathName(path);
            for (int k = 0; k < c.n; ++k) {
                expectSameSetup(
                    got.out, k, ref.out, k,
                    std::to_string(iter) + " lane " + std::to_string(k) + " " + simdPathName(path));
            }
            ++compared;
        }
    }
    if (best != SimdPath::Scalar) {
        EXPECT_GT(compared, 0);  // a SIMD path was really compared
    }
}

/// A band's scratch of `views` images in one block (a streamed band: rows rowHi down to rowLo of
/// a kW × kH image per view, view v at v · stride), as unified's streamed bands lay them out.
struct LaneBlock {
    static constexpr int kW = 40, kH = 64, kRowLo = 20, kRowHi = 35;
    static constexpr int kStride = (kRowHi - kRowLo + 1) * kW;
    int views = 1;
    std::vector<float> depth;
    std::vector<std::uint32_t> color;
    explicit LaneBlock(int n) : views(n), depth(std::size_t(n) * kStride), color(depth.size()) {}
    detail::Target target(int v) {
        return detail::Target{color.data() + std::size_t(v) * kStride,
                              depth.data() + std::size_t(v) * kStride, kW, kH,
                              std::size_t(kH - 1 - kRowHi) * kW};
    }
};

/// Triangles for a queue: mostly a pixel or two across (some larger: the general walk; some
/// covering three centres) in a small part of the band, so that lanes of one view often cover the
/// same pixel; some repeat an earlier triangle with its depths and other colors (a tie at every
/// pixel it covers); in some queues all lie at one depth (ties between different triangles).
struct QueuedTriangle {
    detail::YSetup ys;
    std::int32_t x[3];
    detail::FragmentTri frag;
    float attr[3][3];
};

template <Shading S>
void drawLanesCase(std::mt19937& rng, const detail::Kernels& k, bool colors, int& drawn,
                   int& declined, int& many) {
    std::uniform_real_distribution<float> unit(0.0f, 1.0f), color(-0.2f, 1.2f);
    const int views = 1 + int(rng() % 3);
    LaneBlock ref(views), got(views);
    for (std::size_t i = 0; i < ref.depth.size(); ++i) {
        ref.depth[i] = got.depth[i] = 0.3f + 0.7f * unit(rng);
        ref.color[i] = got.color[i] = std::uint32_t(rng());
    }
    std::vector<detail::Target> targets;
    for (int v = 0; v < views; ++v) targets.push_back(got.target(v));
    detail::LaneQueue<S> queue;
    ASSERT_TRUE(detail::laneImages(targets.data(), targets.size(), queue.images));
    queue.draw = k.drawLanes;
    queue.slotColors.colors = colors;
    std::vector<std::unique_ptr<QueuedTriangle>> pool;
    const int spread = 2 + int(rng() % 24);  // pixels: small → many shared pixels
    const bool quads = rng() % 3 == 0;       // more than 16 fragments in a queue
    const bool wall = rng() % 4 == 0;        // one depth: ties between different triangles
    for (int flushes = 0; flushes < 6; ++flushes) {
        while (!queue.needsFlush(views)) {
            auto t = std::make_unique<QueuedTriangle>();
            if (!pool.empty() && rng() % (quads ? 3 : 16) == 0) {
                *t = *pool[rng() % pool.size()];  // the same triangle again: ties
            } else {
                const bool big = rng() % 40 == 0;
                const int r = big ? 6 * detail::kSubpixel : detail::kSubpixel * 3 / 4;
                std::uniform_int_distribution<std::int32_t> jitter(-r, r);
                const std::int32_t cx = std::int32_t(rng() % unsigned(spread * detail::kSubpixel)) +
                                        8 * detail::kSubpixel;
                const std::int32_t cy = std::int32_t(rng() % unsigned(spread * detail::kSubpixel)) +
                                        (LaneBlock::kRowLo + 2) * detail::kSubpixel;
                std::int32_t y[3];
                for (int j = 0; j < 3; ++j) t->x[j] = cx + jitter(rng), y[j] = cy + jitter(rng);
                if (quads && rng() % 2 == 0) {  // 3 centres of a 2 × 2 block: 3 fragments
                    const std::int32_t px = cx & ~(detail::kSubpixel - 1),
                                       py = cy & ~(detail::kSubpixel - 1);
                    const std::int32_t e = detail::kSubpixel / 8;
                    t->x[0] = px + e, y[0] = py + e;
                    t->x[1] = px + 2 * detail::kSubpixel + 2 * e, y[1] = py + e;
                    t->x[2] = px + e, y[2] = py + 2 * detail::kSubpixel + 2 * e;
                    if (rng() % 2) std::swap(t->x[1], t->x[2]), std::swap(y[1], y[2]);
                }
                detail::setupY(t->ys, y[0], y[1], y[2], LaneBlock::kRowLo, LaneBlock::kRowHi);
                if (t->ys.rowMin > t->ys.rowMax) continue;
                for (int j = 0; j < 3; ++j) {
                    t->frag.z[j] = wall ? 0.25f : unit(rng);
                    t->frag.q[j] = 0.5f + unit(rng);
                }
            }
            for (int j = 0; j < 3; ++j) {
                for (float& a : t->attr[j]) a = color(rng);
                t->frag.attr[j] = t->attr[j];
            }
            t->frag.flat = std::uint32_t(rng());
            const int slot = queue.addTriangle(t->frag);
            for (int v = 0; v < views; ++v) {
                const std::int32_t d = v * std::int32_t(rng() % 200);  // each view's shift
                queue.addLane(slot, t->ys, v, t->x[0] + d, t->x[1] + d, t->x[2] + d);
            }
            pool.push_back(std::move(t));
        }
        // The reference: the ordered walk; then the kernel on the same queue.
        detail::LaneQueue<S> walk = queue;
        walk.draw = nullptr;
        std::vector<detail::FragmentSink<S>> sinks;
        for (int v = 0; v < views; ++v)
            sinks.push_back(detail::FragmentSink<S>{ref.target(v), nullptr, {}});
        walk.flush(detail::scalarKernels().setupLanes, LaneBlock::kW,
                   [&](int v) -> detail::FragmentSink<S>& { return sinks[std::size_t(v)]; });
        int fragments = 0;
        for (int l = 0; l < queue.laneCount; ++l)
            fragments +=
                walk.lanes.out.mask[l] > 0 ? std::popcount(unsigned(walk.lanes.out.mask[l])) : 0;
        many += fragments > 16;
        const LaneBlock before = got;
        detail::TriangleLanes setup = queue.lanes;  // the scalar setupLanes of the lanes
        const std::uint32_t setupBits =
            detail::scalarKernels().setupLanes(setup, queue.laneCount, LaneBlock::kW);
        const std::uint32_t bits =
            k.drawLanes(queue.lanes, queue.laneCount, LaneBlock::kW, queue.laneSlot, queue.laneView,
                        queue.slotColors, queue.slotFrag, S == Shading::Flat, queue.images);
        if (bits == detail::kLanesDrawn) {
            ++drawn;
            ASSERT_EQ(got.depth, ref.depth) << "flush " << flushes;
            ASSERT_EQ(got.color, ref.color) << "flush " << flushes;
        } else {
            ++declined;
            ASSERT_EQ(got.depth, before.depth) << "declined, but wrote";
            ASSERT_EQ(got.color, before.color) << "declined, but wrote";
            // The ordered walk continues from what the kernel left: setupLanes' lanes and setup.
            ASSERT_EQ(bits, setupBits);
            for (int l = 0; l < queue.laneCount; ++l)
                expectSameSetup(queue.lanes.out, l, setup.out, l, "lane " + std::to_string(l));
            got = ref;
        }
        queue.laneCount = queue.slotCount = 0;
    }
}

TEST(Lanes, DrawLanesEqualsTheOrderedWalk) {
    std::vector<const detail::Kernels*> paths;
    for (const detail::Kernels* table : {detail::avx2Kernels(), detail::avx512Kernels()}) {
        if (table && table->drawLanes && detail::bestSupportedSimd() == SimdPath::Avx512)
            paths.push_back(table);
    }
    if (paths.empty()) MVR_SKIP(NotApplicable) << "no drawLanes kernel on this CPU";
    std::mt19937 rng(4242);
    for (const detail::Kernels* k : paths) {
        int drawn = 0, declined = 0, many = 0;
        for (int iter = 0; iter < 1500; ++iter) {
            if (iter % 2 == 0) {
                drawLanesCase<Shading::Vertex>(rng, *k, iter % 4 == 0, drawn, declined, many);
            } else {
                drawLanesCase<Shading::Flat>(rng, *k, false, drawn, declined, many);
            }
            if (HasFatalFailure()) return;
        }
        EXPECT_GT(drawn, 1000);     // the kernel's own path was compared
        EXPECT_GT(declined, 1000);  // and its refusals (ties, general lanes) checked
    }
}

}  // namespace
}  // namespace mvr::raster
