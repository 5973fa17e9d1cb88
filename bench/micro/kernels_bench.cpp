// bench/micro/kernels_bench.cpp — the soft backend's SIMD kernels (src/raster/cpu.h's table), one
// benchmark per kernel and SIMD path: transformPoints, shadeVertices, specularPow, projectYZW,
// projectX (per vertex), setupViews (one triangle seen by a family of views) and setupLanes (a
// band's queue of (triangle, view) lanes). items_per_second counts vertices, values, (triangle,
// view) pairs or lanes. Names: kernel/path/size, e.g. transformPoints/avx2/4096.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "cpu.h"
#include "lanes.h"
#include "micro.h"

namespace mvr::bench {
namespace {

using raster::detail::Kernels;

constexpr std::size_t kVertices = 4096;

struct Vertices {
    std::vector<glm::vec3> positions, normals;
    glm::mat4 clipFromModel, worldFromModel;
    glm::mat3 normalFromModel;
};

Vertices makeVertices(std::size_t n) {
    std::mt19937 rng = benchRng();
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    Vertices v;
    v.positions.resize(n);
    v.normals.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        v.positions[i] = {u(rng), u(rng), u(rng)};
        v.normals[i] =
            glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.0f, 1e-3f));
    }
    v.worldFromModel = glm::rotate(glm::translate(glm::mat4(1.0f), {0.5f, -0.2f, 0.1f}), 0.7f,
                                   glm::vec3(0.2f, 1.0f, 0.3f));
    v.normalFromModel = glm::transpose(glm::inverse(glm::mat3(v.worldFromModel)));
    v.clipFromModel =
        glm::perspective(0.8f, 4.0f / 3.0f, 0.5f, 50.0f) *
        glm::lookAt(glm::vec3(0.0f, 1.0f, 8.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0)) *
        v.worldFromModel;
    return v;
}

void transformPoints(benchmark::State& state, const Kernels* k) {
    const std::size_t n = std::size_t(state.range(0));
    const Vertices v = makeVertices(n);
    std::vector<float> out(4 * n);
    for (auto _ : state) {
        k->transformPoints(v.positions.data(), n, v.clipFromModel, &out[0], &out[n], &out[2 * n],
                           &out[3 * n]);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

void shadeVertices(benchmark::State& state, const Kernels* k) {
    const std::size_t n = std::size_t(state.range(0));
    const Vertices v = makeVertices(n);
    const std::vector<DirectionalLight> lights = defaultLights();
    const ShadingContext ctx{lights, glm::vec3(0.12f), glm::vec3(0.0f, 1.0f, 8.0f)};
    const Material material;
    std::vector<float> color(3 * n);
    for (auto _ : state) {
        k->shadeVertices(v.positions.data(), v.normals.data(), n, v.worldFromModel,
                         v.normalFromModel, ctx, material, color.data());
        benchmark::DoNotOptimize(color.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

void specularPow(benchmark::State& state, const Kernels* k) {
    const std::size_t n = std::size_t(state.range(0));
    std::mt19937 rng = benchRng();
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> x(n), out(n);
    for (float& value : x) value = u(rng);
    for (auto _ : state) {
        k->specularPow(x.data(), n, 32.0f, out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

/// Clip positions of the benchmark's vertices (x, y, z, w split), as the vertex stage has them.
std::vector<float> clipPositions(std::size_t n) {
    const Vertices v = makeVertices(n);
    std::vector<float> clip(4 * n);
    raster::detail::scalarKernels().transformPoints(v.positions.data(), n, v.clipFromModel,
                                                    &clip[0], &clip[n], &clip[2 * n], &clip[3 * n]);
    return clip;
}

void projectYZW(benchmark::State& state, const Kernels* k) {
    const std::size_t n = std::size_t(state.range(0));
    const std::vector<float> clip = clipPositions(n);
    std::vector<std::uint8_t> code(n);
    std::vector<float> q(n), zw(n);
    std::vector<std::int32_t> sy(n);
    for (auto _ : state) {
        k->projectYZW(&clip[n], &clip[2 * n], &clip[3 * n], n, 768.0f, code.data(), q.data(),
                      sy.data(), zw.data());
        benchmark::DoNotOptimize(sy.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

void projectX(benchmark::State& state, const Kernels* k) {
    const std::size_t n = std::size_t(state.range(0));
    const std::vector<float> clip = clipPositions(n);
    std::vector<std::uint8_t> code(n);
    std::vector<float> q(n), zw(n);
    std::vector<std::int32_t> sx(n), sy(n);
    k->projectYZW(&clip[n], &clip[2 * n], &clip[3 * n], n, 768.0f, code.data(), q.data(), sy.data(),
                  zw.data());
    for (auto _ : state) {
        k->projectX(&clip[0], &clip[3 * n], q.data(), n, 1024.0f, code.data(), sx.data());
        benchmark::DoNotOptimize(sx.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

// Small triangles (a few pixels, as in the papers' dense meshes) with one in four large, in a
// 1024x768 target: the mix tests/raster uses.
constexpr int kTriangles = 256;
constexpr int kWidth = 1024;

void setupViews(benchmark::State& state, const Kernels* k) {
    const int views = int(state.range(0));
    std::mt19937 rng = benchRng();
    std::uniform_int_distribution<std::int32_t> jitter(-900, 900);
    std::uniform_int_distribution<std::int32_t> pos(0, 190000);
    struct Tri {
        raster::detail::YSetup ys;
        std::int32_t x[3][kMaxViews];
    };
    std::vector<Tri> tris;
    while (int(tris.size()) < kTriangles) {
        const bool big = tris.size() % 4 == 0;
        const std::int32_t cy = pos(rng), cx = pos(rng);
        Tri t;
        std::int32_t y[3];
        for (auto& v : y) v = cy + (big ? jitter(rng) * 20 : jitter(rng) / 2);
        raster::detail::setupY(t.ys, y[0], y[1], y[2], 0, 767);
        if (t.ys.rowMin > t.ys.rowMax) continue;
        for (int view = 0; view < views; ++view) {
            for (int i = 0; i < 3; ++i)
                t.x[i][view] = cx + view * 37 + (big ? jitter(rng) * 20 : jitter(rng) / 2);
        }
        tris.push_back(t);
    }
    raster::detail::ViewsSetup out;
    for (auto _ : state) {
        std::uint64_t any = 0;
        for (const Tri& t : tris)
            any |= k->setupViews(t.ys, t.x[0], t.x[1], t.x[2], views, kWidth, out);
        benchmark::DoNotOptimize(any);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(kTriangles) * views);
}

void setupLanes(benchmark::State& state, const Kernels* k) {
    // Full queues of stereo pairs (8 triangles x 2 views), as a band's raster loop fills them.
    std::mt19937 rng = benchRng();
    std::uniform_int_distribution<std::int32_t> jitter(-900, 900);
    std::uniform_int_distribution<std::int32_t> pos(-2000, 200000);
    constexpr int kQueues = kTriangles / 8;
    std::vector<raster::detail::TriangleLanes> queues(kQueues);
    for (auto& lanes : queues) {
        int n = 0;
        while (n < raster::detail::kLaneCount) {
            const bool big = rng() % 4 == 0;
            const std::int32_t cy = pos(rng), cx = pos(rng);
            std::int32_t y[3];
            for (auto& v : y) v = cy + (big ? jitter(rng) * 20 : jitter(rng) / 2);
            raster::detail::YSetup ys;
            raster::detail::setupY(ys, y[0], y[1], y[2], 100, 147);  // a band of 48 rows
            if (ys.rowMin > ys.rowMax) continue;
            for (int view = 0; view < 2; ++view, ++n) {
                for (int i = 0; i < 3; ++i) {
                    lanes.x[i][n] = cx + view * 37 + (big ? jitter(rng) * 20 : jitter(rng) / 2);
                    lanes.y[i][n] = ys.y[i];
                }
                lanes.rowMin[n] = ys.rowMin, lanes.rowMax[n] = ys.rowMax;
            }
        }
    }
    for (auto _ : state) {
        std::uint32_t any = 0;
        for (auto& lanes : queues) any |= k->setupLanes(lanes, raster::detail::kLaneCount, kWidth);
        benchmark::DoNotOptimize(any);
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(kQueues) *
                            raster::detail::kLaneCount);
}

bool registerKernels() {
    for (const KernelPath& p : kernelPaths()) {
        const std::string path = "/" + p.name;
        const auto perVertex = [&](const char* name,
                                   void (*fn)(benchmark::State&, const Kernels*)) {
            benchmark::RegisterBenchmark((name + path).c_str(), fn, p.kernels)
                ->Arg(std::int64_t(kVertices));
        };
        perVertex("transformPoints", transformPoints);
        perVertex("shadeVertices", shadeVertices);
        perVertex("specularPow", specularPow);
        perVertex("projectYZW", projectYZW);
        perVertex("projectX", projectX);
        // setupViews serves families of more than 8 views (smaller ones go through setupLanes).
        benchmark::RegisterBenchmark(("setupViews" + path).c_str(), setupViews, p.kernels)
            ->ArgName("views")
            ->Arg(9)
            ->Arg(16)
            ->Arg(kMaxViews);
        benchmark::RegisterBenchmark(("setupLanes" + path).c_str(), setupLanes, p.kernels);
    }
    return true;
}

[[maybe_unused]] const bool kRegistered = registerKernels();

}  // namespace
}  // namespace mvr::bench
