// setupLanes (lanes.h): every SIMD path equals the scalar reference, and a lane gives the very
// integers setupViews gives the same triangle and view (so queuing lanes cannot change a pixel).
#include <gtest/gtest.h>

#include <random>

#include "cpu.h"
#include "lanes.h"

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

}  // namespace
}  // namespace mvr::raster
