// The JSON of the bench reports (nlohmann-json; an mvr built without it says so for --json).
// Objects print with their keys sorted (nlohmann::json's std::map).
#include "bench/report.h"

#include <fstream>
#include <optional>

#include <fmt/core.h>

#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define MVR_BENCH_HAVE_JSON 1
#endif

namespace mvr::cli::bench::detail {

#ifdef MVR_BENCH_HAVE_JSON

namespace {

using nlohmann::json;

Status emit(const json& j, bool print, const std::string& saveTo) {
    if (print) fmt::print("{}\n", j.dump(2));
    if (!saveTo.empty()) {
        std::ofstream out(saveTo);
        out << j.dump(2) << "\n";
        if (!out) return outputError(fmt::format("--save-json: cannot write '{}'", saveTo));
    }
    return {};
}

/// The paper benches' machine object.
json machineJson(const Machine& m) {
    return {{"cpu", m.cpu},
            {"cores", m.cores},
            {"simd", m.simd},
            {"threads", m.threads},
            {"gl_renderer", m.gpuRenderer},
            {"date", m.date}};
}

json statsJson(const Stats& s) {
    return {{"median", s.median}, {"min", s.min}, {"max", s.max},
            {"q1", s.q1},         {"q3", s.q3},   {"n", s.n}};
}

/// A GPU backend's timings into a result: draw_ms, readback_ms, gpu_ms (null: no valid GPU
/// timer sample), gpu_frames and per_frame {draw_ms, readback_ms, gpu_ms: [.., null, ..]}. A CPU
/// backend's result has none of these fields.
void addDeviceTimes(json& e, const DeviceTimes& d) {
    if (!d.measured) return;
    e["draw_ms"] = d.drawMs;
    e["readback_ms"] = d.readbackMs;
    e["gpu_ms"] = d.gpuMs ? json(*d.gpuMs) : json(nullptr);
    e["gpu_frames"] = d.gpuFrames;
    json gpu = json::array();
    for (const std::optional<double>& g : d.frameGpuMs) gpu.push_back(g ? json(*g) : json(nullptr));
    e["per_frame"] = {
        {"draw_ms", d.frameDrawMs}, {"readback_ms", d.frameReadbackMs}, {"gpu_ms", gpu}};
}

}  // namespace

Status emitJson(const MethodReport& report, bool print, const std::string& saveTo) {
    const Machine& m = *report.machine;
    const Prepared& p = *report.request;
    json j;
    j["machine"] = {{"cpu", m.cpu},
                    {"cores", m.cores},
                    {"simd", m.simd},
                    {"threads", m.threads},
                    {"backends", m.backendInfo}};
    j["scene"] = {{"name", p.sceneName},
                  {"rig", rigKindName(p.rig.kind)},
                  {"columns", p.rig.columns},
                  {"rows", p.rig.rows},
                  {"cull", p.settings.cullBackFaces},
                  {"wireframe", p.settings.wireframe}};
    j["results"] = json::array();
    for (const MethodRow& r : report.rows) {
        json e = {{"backend", r.backend},
                  {"method", r.method},
                  {"views", p.rig.viewCount()},
                  {"triangles", p.scene.triangleCount()},
                  {"shading", shadingName(p.settings.shading)},
                  {"width", p.settings.width},
                  {"height", p.settings.height},
                  {"median_ms", r.medianMs},
                  {"min_ms", r.minMs},
                  {"frames", report.frames},
                  {"cpu_ms", r.cpuMs},
                  {"speedup_vs_first", report.rows[0].medianMs / r.medianMs}};
        if (r.ran != r.method) e["ran"] = r.ran;
        addDeviceTimes(e, r.device);
        if (r.hasStages) {
            e["stages_ms"] = {{"vertex", r.stages.vertexMs},
                              {"setup", r.stages.setupMs},
                              {"raster", r.stages.rasterMs},
                              {"fill", r.stages.fillMs}};
        }
        j["results"].push_back(e);
    }
    return emit(j, print, saveTo);
}

Status emitJson(const RenderReport& report, const CommonOptions& o) {
    json j;
    j["bench"] = report.bench;
    j["machine"] = machineJson(*report.machine);
    j["frames"] = o.frames, j["warmup"] = o.warmup;
    j["results"] = json::array();
    for (const RenderRow& r : report.rows) {
        json e = {{"backend", r.backend}, {"method", r.method},       {"model", r.model},
                  {"copies", r.copies},   {"triangles", r.triangles}, {"shading", r.shading},
                  {"views", r.views},     {"config", r.config},       {"width", r.width},
                  {"height", r.height}};
        e["textured"] = r.textured;
        if (!r.error.empty()) {
            e["error"] = r.error;
        } else {
            e["wall_ms"] = statsJson(r.wall);
            e["cpu_ms"] = statsJson(r.cpu);
            e["fps"] = 1000.0 / r.wall.median;
            e["fps_min"] = 1000.0 / r.wall.max;
            e["fps_max"] = 1000.0 / r.wall.min;
            e["speedup_vs_multipass"] = r.speedup;
            e["cpu_speedup_vs_multipass"] = r.cpuSpeedup;
            if (r.ran != r.method) e["ran"] = r.ran;
            if (r.timesOne > 0) e["times_one_view"] = r.timesOne;
            if (r.passes > 0) e["passes"] = r.passes;
            if (r.samples > 1) {
                e["samples"] = r.samples;  // --aa N
                if (r.timesOneSample > 0) e["times_one_sample"] = r.timesOneSample;
                // RenderStats::samples: N multisampled, 1 for sub-pixel passes
                if (r.drawnSamples > 0) e["drawn_samples"] = r.drawnSamples;
            }
            if (r.synthesize > 1) e["synthesize"] = r.synthesize;
            if (r.timesExact > 0) e["times_exact"] = r.timesExact;
            if (r.psnr > 0) e["psnr_db"] = r.psnr;
            addDeviceTimes(e, r.device);
            if (!r.artifactPercent.empty()) {
                e["artifact_percent"] = r.artifactPercent;  // per view, vs multipass
                e["artifact_max_delta"] = r.artifactMaxDelta;
            }
        }
        j["results"].push_back(e);
    }
    j["skipped"] = json::array();
    for (const Skipped& s : report.skipped)
        j["skipped"].push_back({{"method", s.spec}, {"reason", s.reason}});
    return emit(j, o.json, o.saveJson);
}

Status emitJson(const AdelsonReport& report, const CommonOptions& o) {
    json j;
    j["bench"] = "adelson1991";
    j["machine"] = machineJson(*report.machine);
    j["batches"] = o.frames, j["warmup"] = o.warmup, j["tiny"] = report.tiny;
    j["results"] = json::array();
    auto sav = [](const adelson::Savings& s) {
        return json{{"I", s.measureI}, {"II", s.measureII}, {"III", s.measureIII}};
    };
    auto ops = [](const adelson::OpCounts& c) {
        return json{{"adds", c.adds},
                    {"muls", c.muls},
                    {"cmps", c.cmps},
                    {"interps", c.interps},
                    {"total", c.total()}};
    };
    for (const AdelsonRow& r : report.rows) {
        json e = {{"algorithm", r.algorithm},
                  {"case", r.caseName},
                  {"ops_separate", ops(r.opsSep)},
                  {"ops_simultaneous", ops(r.opsSim)},
                  {"ms_separate", statsJson(r.sepMs)},
                  {"ms_simultaneous", statsJson(r.simMs)},
                  {"wall_ms_separate", statsJson(r.sepWall)},
                  {"wall_ms_simultaneous", statsJson(r.simWall)},
                  {"reps_per_batch", r.reps},
                  {"savings_ops", sav(r.byOps)},
                  {"savings_time", sav(r.byTime)},
                  {"paper", {{"I", r.paperI}, {"II", r.paperII}, {"III", r.paperIII}}},
                  {"results_agree", r.check.empty()},
                  {"check", r.check.empty() ? r.checkDetail : r.check}};
        if (r.hasInterp) e["savings_interpolations"] = sav(r.byInterp);
        j["results"].push_back(e);
    }
    return emit(j, o.json, o.saveJson);
}

#else

namespace {
Status noJson() {
    return unsupportedError("--json needs nlohmann-json, which this mvr was built without");
}
}  // namespace

Status emitJson(const MethodReport&, bool, const std::string&) { return noJson(); }
Status emitJson(const RenderReport&, const CommonOptions&) { return noJson(); }
Status emitJson(const AdelsonReport&, const CommonOptions&) { return noJson(); }

#endif

}  // namespace mvr::cli::bench::detail
