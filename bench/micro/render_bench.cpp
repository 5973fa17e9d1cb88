// bench/micro/render_bench.cpp — one whole frame of the soft backend per method: the default
// procedural scene (no data files), framed as `mvr render` frames it, a stereo pair of 320x240,
// vertex shading, on one worker thread (so that the figure is the pipeline's, not the machine's
// core count) with the best SIMD path. Names: render/soft:METHOD; counters: the stages' ms per
// frame (RenderStats::stages) and frames/s.
#include <benchmark/benchmark.h>

#include <string>

#include "mvr/core/framing.h"
#include "mvr/core/scene.h"
#include "mvr/raster/soft_backend.h"

namespace mvr::bench {
namespace {

void renderFrame(benchmark::State& state, const std::string& method) {
    auto backend = raster::makeSoftBackend({.threads = 1});
    const Scene scene = makeDefaultScene();
    RenderSettings settings;
    settings.width = 320, settings.height = 240;
    auto request = frameScene(scene, FramingParams{}, settings);
    if (!request) {
        state.SkipWithError(request.status().message().c_str());
        return;
    }
    StageTimes sum;
    for (auto _ : state) {
        auto out = backend->render(scene, request->rig, request->settings, method);
        if (!out) {
            state.SkipWithError(out.status().message().c_str());
            return;
        }
        benchmark::DoNotOptimize(out->color.data());
        sum.vertexMs += out->stages.vertexMs, sum.setupMs += out->stages.setupMs;
        sum.rasterMs += out->stages.rasterMs, sum.fillMs += out->stages.fillMs;
    }
    using benchmark::Counter;
    state.counters["vertex_ms"] = Counter(sum.vertexMs, Counter::kAvgIterations);
    state.counters["setup_ms"] = Counter(sum.setupMs, Counter::kAvgIterations);
    state.counters["raster_ms"] = Counter(sum.rasterMs, Counter::kAvgIterations);
    state.counters["fill_ms"] = Counter(sum.fillMs, Counter::kAvgIterations);
    state.counters["fps"] = Counter(double(state.iterations()), Counter::kIsRate);
}

bool registerRenders() {
    for (const std::string& method : raster::makeSoftBackend({.threads = 1})->methods()) {
        benchmark::RegisterBenchmark(("render/soft:" + method).c_str(), renderFrame, method)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    return true;
}

[[maybe_unused]] const bool kRegistered = registerRenders();

}  // namespace
}  // namespace mvr::bench
