// tools/cli/bench/report.h — what the benches print: the rows they measured as text tables
// (markdown for the paper benches), CSV, JSON (stdout and --save-json) and gnuplot plots.
// The benches fill rows (harness.h measures them); everything about layout is here.
//
// Three kinds of rows: MethodRow (`mvr bench`: methods side by side on one scene), RenderRow
// (`mvr bench sorbier | kalaiah`: one configuration × method) and AdelsonRow (`mvr bench
// adelson`: a simultaneous algorithm against its single-eye version).
#pragma once

#include <array>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "bench/harness.h"
#include "mvr/adelson/adelson.h"

namespace mvr::cli::bench {

/// "machine: CPU | N hardware threads | soft: ... | GL_RENDERER: ... | date".
std::string machineLine(const Machine& m);

// ---- `mvr bench`: methods side by side -------------------------------------------------------

struct MethodRow {
    std::string backend, method, ran;
    double medianMs = 0, minMs = 0;
    double cpuMs = 0;   ///< median process CPU time (all threads) per frame
    StageTimes stages;  ///< medians per stage (RenderStats::stages)
    bool hasStages = false;
    DeviceTimes device;  ///< a GPU backend's draw / readback / GPU timer (harness.h)
};
MethodRow methodRow(const Job& job, const Measured& measured);

struct MethodReport {
    const Machine* machine = nullptr;
    const Prepared* request = nullptr;
    std::vector<MethodRow> rows;  ///< the first is the baseline of "vs first"
    int frames = 0, warmup = 0;
};
/// The machine, scene and one line per method; JSON {machine, scene, results} with `json`.
/// Returns the exit code.
int printMethodReport(const MethodReport& report, bool json);

// ---- `mvr bench sorbier | kalaiah`: render rows --------------------------------------------

struct RenderRow {
    std::string backend, method, ran, shading, model, config, error;
    int copies = 1, views = 2, width = 0, height = 0;
    int bufferW = 0, bufferH = 0;  ///< kalaiah: the buffer the views share
    std::size_t triangles = 0;
    Stats wall, cpu;
    double speedup = 0, cpuSpeedup = 0;  ///< multipass of the same backend / this
    /// Artifacts for the bench's own camera (sorbier): per view, the percentage of pixels with
    /// a channel more than 2/255 off the same backend's multipass, and the largest difference;
    /// empty where not measured (the baseline itself, a failed job).
    std::vector<double> artifactPercent;
    int artifactMaxDelta = 0;
    /// views: time(N) / time(1) of the same job (0: not measured), and the passes it drew the
    /// views in (RenderStats::passes; 0: not recorded).
    double timesOne = 0;
    int passes = 0;
    /// views --aa: the samples a pixel (RenderSettings::samples) and time / time of one sample
    /// of the same job and views (0: not measured).
    int samples = 1;
    double timesOneSample = 0;
    /// views --aa: the samples a pixel the backend drew into its targets (RenderStats::samples:
    /// N multisampled, 1 for sub-pixel passes; 0: not recorded).
    int drawnSamples = 0;
    /// views --synthesize: K (1: every view exact), time / time of the same job and views
    /// rendered exactly (0: not measured) and the lowest PSNR of a warped view against its
    /// exact render (dB; 0: not measured).
    int synthesize = 1;
    double timesExact = 0;
    double psnr = 0;
    /// sorbier: the textured row (a base color texture sampled with mipmaps, issue 14).
    bool textured = false;
    DeviceTimes device;  ///< a GPU backend's draw / readback / GPU timer (harness.h)
    std::string spec() const { return backend + ":" + method; }
};
/// "draw / readback / gpu" ms of a row for the tables: "-" for each value not measured (a CPU
/// backend's row: all three; no valid GPU timer sample: gpu).
std::string deviceCell(const DeviceTimes& device);

/// The row of one measured job: what every render bench records; the bench adds its columns.
RenderRow renderRow(const Job& job, const Measured& measured, std::size_t triangles);
/// Speed-ups of rows[first..] over the baseline of their backend among them.
void fillSpeedups(std::vector<RenderRow>& rows, std::size_t first);

/// A markdown table of rows: one line per distinct rowLabels(), one column per distinct
/// column(), both in the order they first occur; the cell: fps [min–max] speed-up (cpu ×).
struct PivotTable {
    std::string caption;                ///< the paragraph above the table
    std::vector<std::string> rowHeads;  ///< headings of the label columns
    std::function<bool(const RenderRow&)> filter;
    std::function<std::vector<std::string>(const RenderRow&)> rowLabels;
    std::function<std::string(const RenderRow&)> column;
    /// The cell's text (empty: fps [min–max] speed-up (cpu ×)).
    std::function<std::string(const RenderRow&)> cell;
};

/// fps against `x`, one panel per distinct panel(), one line per series (job), bars min–max.
struct RenderPlot {
    std::string title;   ///< " — CPU | GL_RENDERER" is appended
    std::string xlabel;  ///< "triangles" (axis in k) or "views" (ticks at 1, 2, 3, 4, 6, 9)
    std::function<bool(const RenderRow&)> filter;
    std::function<std::string(const RenderRow&)> panel;
    std::function<double(const RenderRow&)> x;
    /// Empty: fps with min–max bars. Else the value and its bar's ends, against `ylabel`, and
    /// both axes logarithmic (views: "× one view" against N).
    std::function<std::array<double, 3>(const RenderRow&)> y;
    std::string ylabel;
};

struct RenderReport {
    std::string bench;  ///< "sorbier2008", "kalaiah2007"
    const Machine* machine = nullptr;
    std::vector<RenderRow> rows;
    std::vector<Skipped> skipped;
    std::vector<std::string> series;  ///< the jobs, in order
    std::vector<PivotTable> tables;
    RenderPlot plot;
};
/// JSON (--json, --save-json), CSV (--csv) or the machine line, tables and skipped methods;
/// then --plot. Returns the exit code.
int printRenderReport(const RenderReport& report, const CommonOptions& options);

// ---- `mvr bench adelson` ---------------------------------------------------------------------

struct AdelsonRow {
    std::string algorithm, caseName, label, paperI, paperII, paperIII, opsNote, check, checkDetail;
    adelson::OpCounts opsSep, opsSim;
    Stats sepMs, simMs;      ///< thread CPU time per call of both eyes
    Stats sepWall, simWall;  ///< wall time per call
    int reps = 1;
    adelson::Savings byOps, byTime, byInterp;
    bool hasInterp = false;
};

struct AdelsonReport {
    const Machine* machine = nullptr;
    std::vector<AdelsonRow> rows;
    bool tiny = false;
};
/// JSON, CSV or the machine line and Table 1; then --plot. Returns the exit code.
int printAdelsonReport(const AdelsonReport& report, const CommonOptions& options);

// ---- `mvr bench outputs` (outputs.cpp; report_outputs.cpp) -------------------------------

/// One configuration's run: seconds; render, compose, encode, write and video summed over its
/// frames (encode and write also over the threads that ran them).
struct OutputsRow {
    std::string config, command;
    int views = 0, width = 0, height = 0, frames = 0;
    int files = 0;  ///< a still's files
    double setup = 0;  ///< prepare (load, frame, rig) and the backend
    double render = 0, compose = 0, encode = 0, write = 0, video = 0;
    double endToEnd = 0;  ///< the render(s) to the last file, set-up excluded
    double cpu = 0;       ///< process CPU time of the run, set-up included
};
/// Each field's median over the runs of one configuration.
OutputsRow medianRow(const std::vector<OutputsRow>& runs);

struct OutputsReport {
    const Machine* machine = nullptr;
    std::string scene;
    int runs = 1;
    int queue = 1;  ///< the sequences' write queue depth
    std::vector<OutputsRow> rows;
    std::vector<std::string> skipped;  ///< "CONFIG: why" (a video without FFmpeg)
};
/// The machine line and a markdown table (ms per frame; end to end, frames per second), or
/// JSON {bench, machine, scene, runs, queue, skipped, results: [...]}. Returns the exit code.
int printOutputsReport(const OutputsReport& report, bool json);

// ---- report_json.cpp -------------------------------------------------------------------------

namespace detail {
/// The JSON of each report; printed on stdout with `print`, written to `saveTo` if non-empty.
/// Errors: Unsupported without nlohmann-json in this build; Output when saveTo fails.
Status emitJson(const MethodReport& report, bool print, const std::string& saveTo);
Status emitJson(const RenderReport& report, const CommonOptions& options);
Status emitJson(const AdelsonReport& report, const CommonOptions& options);
}  // namespace detail

// ---- plots -----------------------------------------------------------------------------------

/// --plot FILE: .png or .svg, and gnuplot on PATH. Errors: Usage, Unsupported.
Status checkPlotTarget(const std::string& file);

}  // namespace mvr::cli::bench
