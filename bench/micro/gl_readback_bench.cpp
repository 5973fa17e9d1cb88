// bench/micro/gl_readback_bench.cpp — the gl backend's frame split into draw and read-back
// (Backend::lastStats()), per method and view count, with and without depth: what the
// read-back costs as the views grow (issue: it grew ~N² with one target holding every view).
// Suzanne (MVR_SHARED_DIR/models/suzanne.obj; read-back does not depend on the triangles),
// 420×560 a view (a Looking Glass Portrait's), vertex lighting. Counters: draw_ms,
// readback_ms, gpu_ms (−1: no timer) and passes, means over the iterations; frames rendered
// into one RenderOutput (Backend::renderInto). Needs an EGL
// context: without one every benchmark says so and stops. MVR_GL_VIEWS_PER_TARGET=N tries
// other target bounds without a build.
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "mvr/core/framing.h"
#include "mvr/core/mesh.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/gl/gl_backend.h"
#include "mvr/io/mesh_io.h"

namespace {

const mvr::Scene* suzanne() {
    static const std::unique_ptr<mvr::Scene> s = []() -> std::unique_ptr<mvr::Scene> {
        const char* dir = std::getenv("MVR_SHARED_DIR");
        const std::filesystem::path p =
            std::filesystem::path(dir ? dir : MVR_BENCH_SHARED_DIR) / "models" / "suzanne.obj";
        auto mesh = mvr::loadMesh(p);
        if (!mesh) return nullptr;
        std::vector<mvr::Mesh> meshes;
        meshes.push_back(std::move(mesh).value());
        return std::make_unique<mvr::Scene>(mvr::makeGridScene(std::move(meshes), 1));
    }();
    return s.get();
}

mvr::Backend& gl() {
    static std::unique_ptr<mvr::Backend> b = mvr::gl::makeGlBackend();
    return *b;
}

// Args: views, depth (0/1). The method is the benchmark's name.
void readback(benchmark::State& state, const char* method) {
    const mvr::Scene* scene = suzanne();
    if (!scene) return state.SkipWithError("suzanne.obj not found (MVR_SHARED_DIR)");
    if (const mvr::Status s = gl().supports(method); !s)
        return state.SkipWithError(s.message().c_str());
    const int views = static_cast<int>(state.range(0));
    mvr::RenderSettings s;
    s.width = 420;
    s.height = 560;
    s.depth = state.range(1) != 0;
    mvr::FramingParams fp;
    fp.columns = views;
    auto req = mvr::frameScene(*scene, fp, s);
    if (!req) return state.SkipWithError(req.status().message().c_str());
    s = req->settings;
    // Frame after frame into one output (as a sequence or a viewer renders), after a first
    // frame that compiles, allocates and faults the pages in.
    mvr::RenderOutput out;
    if (const mvr::Status st = gl().renderInto(*scene, req->rig, s, method, out); !st)
        return state.SkipWithError(st.message().c_str());
    double draw = 0, read = 0, gpu = 0;
    int passes = 0, n = 0;
    for (auto _ : state) {
        if (const mvr::Status st = gl().renderInto(*scene, req->rig, s, method, out); !st)
            return state.SkipWithError(st.message().c_str());
        benchmark::DoNotOptimize(out.color.data());
        const auto st = gl().lastStats();
        draw += st->drawWallMs;
        read += st->readbackWallMs;
        gpu += st->gpuMs;
        passes = st->passes;
        ++n;
    }
    state.counters["draw_ms"] = draw / n;
    state.counters["readback_ms"] = read / n;
    state.counters["gpu_ms"] = gpu / n;
    state.counters["passes"] = passes;
}

void args(benchmark::internal::Benchmark* b) {
    for (int views : {1, 9, 45, 100})
        for (int depth : {1, 0}) b->Args({views, depth});
    b->ArgNames({"views", "depth"})->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(readback, multipass, "multipass")->Apply(args);
BENCHMARK_CAPTURE(readback, instanced_layer, "instanced-layer")->Apply(args);
BENCHMARK_CAPTURE(readback, gs_layered, "gs-layered")->Apply(args);
BENCHMARK_CAPTURE(readback, multiview, "multiview")->Apply(args);
BENCHMARK_CAPTURE(readback, kalaiah_emulation, "kalaiah-emulation")->Apply(args);

}  // namespace
