// The report of `mvr bench outputs` (report.h): a markdown table or JSON.
#include <algorithm>
#include <vector>

#include <fmt/core.h>

#include "bench/report.h"

namespace mvr::cli::bench {

namespace {

double medianOf(const std::vector<OutputsRow>& runs, double OutputsRow::*field) {
    std::vector<double> v;
    for (const OutputsRow& r : runs) v.push_back(r.*field);
    std::sort(v.begin(), v.end());
    return quantile(v, 0.5);
}

std::string jsonString(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

}  // namespace

OutputsRow medianRow(const std::vector<OutputsRow>& runs) {
    OutputsRow row = runs.at(0);
    for (double OutputsRow::*field :
         {&OutputsRow::setup, &OutputsRow::render, &OutputsRow::compose, &OutputsRow::encode,
          &OutputsRow::write, &OutputsRow::video, &OutputsRow::endToEnd, &OutputsRow::cpu})
        row.*field = medianOf(runs, field);
    return row;
}

int printOutputsReport(const OutputsReport& report, bool json) {
    if (json) {
        const Machine& m = *report.machine;
        fmt::print("{{\"bench\": \"outputs\", \"machine\": {{\"cpu\": {}, \"cores\": {}, "
                   "\"simd\": {}, \"threads\": {}, \"gl_renderer\": {}, \"date\": {}}}, "
                   "\"scene\": {}, \"runs\": {}, \"queue\": {}, \"skipped\": [",
                   jsonString(m.cpu), m.cores, jsonString(m.simd), m.threads,
                   jsonString(m.gpuRenderer), jsonString(m.date), jsonString(report.scene),
                   report.runs, report.queue);
        for (std::size_t i = 0; i < report.skipped.size(); ++i)
            fmt::print("{}{}", i ? ", " : "", jsonString(report.skipped[i]));
        fmt::print("], \"results\": [");
        for (std::size_t i = 0; i < report.rows.size(); ++i) {
            const OutputsRow& r = report.rows[i];
            const double n = std::max(1, r.frames);
            fmt::print(
                "{}\n  {{\"config\": {}, \"command\": {}, \"views\": {}, \"width\": {}, "
                "\"height\": {}, \"frames\": {}, \"files\": {}, \"setup_s\": {:.4f}, "
                "\"render_ms\": {:.3f}, \"compose_ms\": {:.3f}, \"encode_ms\": {:.3f}, "
                "\"write_ms\": {:.3f}, \"video_ms\": {:.3f}, \"end_to_end_s\": {:.4f}, "
                "\"fps\": {:.3f}, \"cpu_s\": {:.4f}}}",
                i ? "," : "", jsonString(r.config), jsonString(r.command), r.views, r.width,
                r.height, r.frames, r.files, r.setup, 1e3 * r.render / n, 1e3 * r.compose / n,
                1e3 * r.encode / n, 1e3 * r.write / n, 1e3 * r.video / n, r.endToEnd,
                r.endToEnd > 0 ? r.frames / r.endToEnd : 0.0, r.cpu);
        }
        fmt::print("\n]}}\n");
        return 0;
    }
    fmt::print("{}\n", machineLine(*report.machine));
    fmt::print("scene: {}; {} run{} per configuration (medians); sequences' write queue: {}\n\n",
               report.scene, report.runs, report.runs == 1 ? "" : "s", report.queue);
    fmt::print("| config | views | frames | set-up s | render ms | compose ms | encode ms | "
               "write ms | video ms | end to end s | frames/s | cpu s |\n");
    fmt::print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const OutputsRow& r : report.rows) {
        const double n = std::max(1, r.frames);
        fmt::print("| {} | {} of {}x{} | {} | {:.3f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} "
                   "| {:.3f} | {:.2f} | {:.2f} |\n",
                   r.config, r.views, r.width, r.height, r.frames, r.setup, 1e3 * r.render / n,
                   1e3 * r.compose / n, 1e3 * r.encode / n, 1e3 * r.write / n,
                   1e3 * r.video / n, r.endToEnd, r.endToEnd > 0 ? r.frames / r.endToEnd : 0.0,
                   r.cpu);
    }
    fmt::print("\nms: per frame; encode and write summed over the threads that ran them; a "
               "sequence's stages overlap (end to end is less than their sum).\n");
    for (const OutputsRow& r : report.rows) fmt::print("{}: mvr render {}\n", r.config, r.command);
    for (const std::string& s : report.skipped) fmt::print("skipped: {}\n", s);
    return 0;
}

}  // namespace mvr::cli::bench
