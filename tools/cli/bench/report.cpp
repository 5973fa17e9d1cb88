#include "bench/report.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/core.h>
#include <sys/wait.h>
#include <unistd.h>

namespace mvr::cli::bench {

namespace fs = std::filesystem;

std::string machineLine(const Machine& m) {
    return fmt::format(
        "machine: {} | {} hardware threads | soft: SIMD {}, {} worker threads | "
        "GL_RENDERER: {} | {}",
        m.cpu, m.cores, m.simd, m.threads, m.gpuRenderer, m.date);
}

namespace {

std::string fmtFps(double ms) { return ms > 0 ? fmt::format("{:.1f}", 1000.0 / ms) : "-"; }

// ---- gnuplot --------------------------------------------------------------------------------

std::string gpQuote(const std::string& s) {
    std::string out = "'";
    for (const char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

/// Writes `data` and `script` (which refers to the data file as DATA) to a temporary folder
/// and runs gnuplot on it, drawing `output` (.png or .svg).
Status runGnuplot(const std::string& output, const std::string& data, std::string script) {
    std::error_code ec;
    const fs::path dir = fs::temp_directory_path(ec) / fmt::format("mvr-plot-{}", ::getpid());
    fs::create_directories(dir, ec);
    if (ec)
        return outputError(fmt::format("--plot: cannot create {}: {}", dir.string(), ec.message()));
    const fs::path dataPath = dir / "data.dat", scriptPath = dir / "plot.gp";
    const std::string ext = fs::path(output).extension().string();
    const std::string terminal = ext == ".svg"
                                     ? "set terminal svg size 1500,520 dynamic font 'sans,11'\n"
                                     : "set terminal pngcairo size 1500,520 font 'sans,10'\n";
    for (std::size_t pos = 0; (pos = script.find("DATA", pos)) != std::string::npos;) {
        const std::string quoted = gpQuote(dataPath.string());
        script.replace(pos, 4, quoted);
        pos += quoted.size();
    }
    const std::string absOut = fs::absolute(output, ec).string();
    script = terminal + "set output " + gpQuote(absOut) + "\n" + script + "\nset output\n";
    {
        std::ofstream d(dataPath), s(scriptPath);
        d << data;
        s << script;
        if (!d || !s) return outputError(fmt::format("--plot: cannot write {}", dir.string()));
    }
    const pid_t pid = ::fork();
    if (pid < 0) return outputError("--plot: cannot start gnuplot (fork failed)");
    if (pid == 0) {
        const std::string sp = scriptPath.string();
        ::execlp("gnuplot", "gnuplot", sp.c_str(), static_cast<char*>(nullptr));
        std::_Exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    fs::remove_all(dir, ec);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
            return unsupportedError(
                "--plot: gnuplot could not be run (Debian: apt-get install gnuplot-nox)");
        }
        return outputError(fmt::format("--plot: gnuplot failed writing '{}' (exit status {})",
                                       output, WIFEXITED(status) ? WEXITSTATUS(status) : -1));
    }
    return {};
}

/// Panels of fps against x, one line with min–max bars per series.
std::string renderPlotScript(const std::string& title, const std::vector<std::string>& panels,
                             const std::vector<std::string>& series, const std::string& xlabel,
                             const std::string& ylabel = "") {
    std::string s;
    const int cols = int(std::min<std::size_t>(panels.size(), 3));
    const int rowsN = int((panels.size() + cols - 1) / cols);
    s += fmt::format("set multiplot layout {},{} title {}\n", rowsN, cols, gpQuote(title));
    s += fmt::format("set xlabel {}\nset ylabel {}\nset logscale y\nset grid\n", gpQuote(xlabel),
                     gpQuote(ylabel.empty() ? "fps (median; bars: min-max)" : ylabel));
    if (!ylabel.empty()) s += "set logscale x\nset xtics (1, 2, 4, 9, 16, 45, 72, 100)\n";
    if (xlabel == "triangles") s += "set format x '%.0s%c'\n";  // 100k, 200k, …
    if (xlabel == "views" && ylabel.empty()) s += "set xtics (1, 2, 3, 4, 6, 9)\n";
    s += "set key inside top right font ',7' samplen 2 spacing 0.9 opaque box\nset pointsize 0.7\n";
    int index = 0;
    for (std::size_t p = 0; p < panels.size(); ++p) {
        s += fmt::format("set title {}\nplot ", gpQuote(panels[p]));
        for (std::size_t k = 0; k < series.size(); ++k) {
            s += fmt::format("{}DATA index {} using 1:2:3:4 with yerrorlines lw 1.5 title {}",
                             k ? ", " : "", index++, gpQuote(series[k]));
        }
        s += "\n";
        if (p == 0) s += "set key off\n";
    }
    s += "unset multiplot\n";
    return s;
}

Status plotRenderRows(const RenderReport& report, const std::string& file) {
    const RenderPlot& plot = report.plot;
    std::vector<std::string> panels;
    for (const RenderRow& r : report.rows) {
        if (plot.filter(r) &&
            std::find(panels.begin(), panels.end(), plot.panel(r)) == panels.end()) {
            panels.push_back(plot.panel(r));
        }
    }
    std::string data;  // one gnuplot index (block) per panel × series, empty ones included
    for (const std::string& panel : panels) {
        for (const std::string& series : report.series) {
            data += fmt::format("# {} {}\n", panel, series);
            for (const RenderRow& r : report.rows) {
                if (plot.filter(r) && plot.panel(r) == panel && r.spec() == series &&
                    r.error.empty()) {
                    const std::array<double, 3> y =
                        plot.y ? plot.y(r)
                               : std::array<double, 3>{1000.0 / r.wall.median, 1000.0 / r.wall.max,
                                                       1000.0 / r.wall.min};
                    data += fmt::format("{} {:.4f} {:.4f} {:.4f}\n", plot.x(r), y[0], y[1], y[2]);
                }
            }
            data += "\n\n";
        }
    }
    const std::string title =
        fmt::format("{} — {} | {}", plot.title, report.machine->cpu, report.machine->gpuRenderer);
    return runGnuplot(
        file, data,
        renderPlotScript(title, panels, report.series, plot.xlabel, plot.y ? plot.ylabel : ""));
}

// ---- markdown -------------------------------------------------------------------------------

/// "fps [min–max] ×speedup (cpu ×)" for a table cell.
std::string renderCell(const RenderRow& r) {
    if (!r.error.empty()) return "n/a";
    std::string cell = fmt::format("{} [{}–{}] {:.2f}× (cpu {:.2f}×)", fmtFps(r.wall.median),
                                   fmtFps(r.wall.max), fmtFps(r.wall.min), r.speedup, r.cpuSpeedup);
    if (!r.artifactPercent.empty()) {
        cell += " wrong px";
        for (std::size_t v = 0; v < r.artifactPercent.size(); ++v)
            cell += fmt::format("{}{:.2f}", v ? "/" : " ", r.artifactPercent[v]);
        cell += " %";
    }
    return cell;
}

void printPivot(const PivotTable& t, const std::vector<RenderRow>& rows) {
    std::vector<std::vector<std::string>> lines;
    std::vector<std::string> columns;
    for (const RenderRow& r : rows) {
        if (!t.filter(r)) continue;
        const std::vector<std::string> labels = t.rowLabels(r);
        if (std::find(lines.begin(), lines.end(), labels) == lines.end()) lines.push_back(labels);
        const std::string column = t.column(r);
        if (std::find(columns.begin(), columns.end(), column) == columns.end())
            columns.push_back(column);
    }
    fmt::print("\n{}\n\n", t.caption);
    std::string head = "|", sep = "|";
    for (const std::string& h : t.rowHeads) head += " " + h + " |", sep += "---|";
    for (const std::string& c : columns) head += " " + c + " |", sep += "---|";
    fmt::print("{}\n{}\n", head, sep);
    for (const std::vector<std::string>& labels : lines) {
        std::string line = "|";
        for (const std::string& l : labels) line += " " + l + " |";
        for (const std::string& c : columns) {
            std::string cell = "-";
            for (const RenderRow& r : rows) {
                if (t.filter(r) && t.column(r) == c && t.rowLabels(r) == labels)
                    cell = t.cell ? t.cell(r) : renderCell(r);
            }
            line += " " + cell + " |";
        }
        fmt::print("{}\n", line);
    }
}

/// The twin of a table whose cells are its rows' draw / readback / GPU timer ms.
PivotTable deviceTable(const PivotTable& t) {
    PivotTable d = t;
    d.caption =
        "The same rows' GPU-backend timings (RenderStats, medians over the timed frames) — cell: "
        "draw / readback / gpu ms: draw = first draw to the finished frame (wall), readback = "
        "handing the views back (wall), gpu = the GPU timer of the draws (GL_TIME_ELAPSED; a "
        "frame's sample is dropped when negative or above its draw time, '-' when none is "
        "left); '-' for a CPU backend's rows";
    d.cell = [](const RenderRow& r) -> std::string {
        return r.error.empty() ? deviceCell(r.device) : "error";
    };
    return d;
}

std::string csvMs(bool measured, double v) { return measured ? fmt::format("{:.3f}", v) : ""; }

}  // namespace

// ---- `mvr bench` ----------------------------------------------------------------------------

MethodRow methodRow(const Job& job, const Measured& m) {
    MethodRow r;
    r.backend = job.spec.backend, r.method = job.spec.method, r.ran = m.ran;
    r.medianMs = statsOf(m.wallMs).median;
    r.minMs = m.wallMs.empty() ? 0.0 : *std::min_element(m.wallMs.begin(), m.wallMs.end());
    r.cpuMs = statsOf(m.cpuMs).median;
    std::vector<double> vertex, setup, raster, fill;
    for (const RenderStats& s : m.stats) {
        vertex.push_back(s.stages.vertexMs), setup.push_back(s.stages.setupMs);
        raster.push_back(s.stages.rasterMs), fill.push_back(s.stages.fillMs);
        const StageTimes& st = s.stages;
        r.hasStages = r.hasStages || st.vertexMs + st.setupMs + st.rasterMs + st.fillMs > 0.0;
    }
    r.stages = {statsOf(vertex).median, statsOf(setup).median, statsOf(raster).median,
                statsOf(fill).median};
    r.device = deviceTimes(m.stats, ranOnGpu(job, m.ran));
    return r;
}

std::string deviceCell(const DeviceTimes& d) {
    if (!d.measured) return "-";
    return fmt::format("{:.2f} / {:.2f} / {}", d.drawMs, d.readbackMs,
                       d.gpuMs ? fmt::format("{:.2f}", *d.gpuMs) : "-");
}

int printMethodReport(const MethodReport& report, bool json) {
    if (json) {
        if (Status s = detail::emitJson(report, true, ""); !s) return fail(s);
        return 0;
    }
    const Machine& m = *report.machine;
    const Prepared& p = *report.request;
    const std::vector<MethodRow>& rows = report.rows;
    const std::size_t triangles = p.scene.triangleCount();
    const int views = p.rig.viewCount();
    fmt::print("machine: {} | {} hardware threads | soft SIMD path: {} | soft worker threads: {}\n",
               m.cpu, m.cores, m.simd, m.threads);
    for (const std::string& line : m.backendInfo) fmt::print("  {}\n", line);
    fmt::print(
        "scene: {} ({} triangles) | {} rig {}x{} = {} views | {}x{} | {} shading{}{} | {} frames "
        "after {} warm-up\n",
        p.sceneName, triangles, rigKindName(p.rig.kind), p.rig.columns, p.rig.rows, views,
        p.settings.width, p.settings.height, shadingName(p.settings.shading),
        p.settings.cullBackFaces ? " | cull" : "", p.settings.wireframe ? " | wireframe" : "",
        report.frames, report.warmup);
    // draw / readback / gpu: a GPU backend's own timings (medians; '-' for a CPU backend, and
    // for gpu where the timer gave no valid sample); vertex … fill: the CPU backend's stages.
    fmt::print(
        "{:<24} {:>10} {:>10} {:>9} {:>10} {:>12} {:>9} {:>9} {:>9}   {:>8} {:>8} {:>8} {:>8}\n",
        "backend:method", "median ms", "min ms", "vs first", "cpu ms", "Mtri·view/s", "draw ms",
        "read ms", "gpu ms", "vertex", "setup", "raster", "fill");
    const auto ms = [](bool measured, double v) {
        return measured ? fmt::format("{:.2f}", v) : std::string("-");
    };
    for (const MethodRow& r : rows) {
        const std::string name =
            r.backend + ":" + r.method + (r.ran != r.method ? " (" + r.ran + ")" : "");
        const double rate = double(triangles) * views / (r.medianMs * 1e3);
        const double vsFirst = rows[0].medianMs / r.medianMs;
        const DeviceTimes& d = r.device;
        std::string line = fmt::format(
            "{:<24} {:>10.2f} {:>10.2f} {:>8.2f}x {:>10.2f} {:>12.1f} {:>9} {:>9} {:>9}", name,
            r.medianMs, r.minMs, vsFirst, r.cpuMs, rate, ms(d.measured, d.drawMs),
            ms(d.measured, d.readbackMs), ms(d.gpuMs.has_value(), d.gpuMs.value_or(0.0)));
        if (r.hasStages) {
            line += fmt::format("   {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f}", r.stages.vertexMs,
                                r.stages.setupMs, r.stages.rasterMs, r.stages.fillMs);
        }
        fmt::print("{}\n", line);
    }
    return 0;
}

// ---- render rows ----------------------------------------------------------------------------

RenderRow renderRow(const Job& job, const Measured& m, std::size_t triangles) {
    RenderRow r;
    r.backend = job.spec.backend, r.method = job.spec.method, r.ran = m.ran;
    r.triangles = triangles;
    r.error = m.failed() ? m.error.message() : "";
    r.wall = statsOf(m.wallMs), r.cpu = statsOf(m.cpuMs);
    r.device = deviceTimes(m.stats, ranOnGpu(job, m.ran));
    return r;
}

void fillSpeedups(std::vector<RenderRow>& rows, std::size_t first) {
    for (std::size_t i = first; i < rows.size(); ++i) {
        for (std::size_t k = first; k < rows.size(); ++k) {
            if (rows[k].backend == rows[i].backend && rows[k].method == kBaselineMethod &&
                rows[k].error.empty() && rows[i].error.empty() && rows[i].wall.median > 0) {
                rows[i].speedup = rows[k].wall.median / rows[i].wall.median;
                rows[i].cpuSpeedup =
                    rows[i].cpu.median > 0 ? rows[k].cpu.median / rows[i].cpu.median : 0;
            }
        }
    }
}

int printRenderReport(const RenderReport& report, const CommonOptions& o) {
    if (o.json || !o.saveJson.empty()) {
        if (Status s = detail::emitJson(report, o); !s) return fail(s);
    }
    if (o.json) {
        // printed above
    } else if (o.csv) {
        fmt::print("# {}\n", machineLine(*report.machine));
        fmt::print(
            "bench,backend,method,model,copies,triangles,shading,views,config,width,height,frames,"
            "median_ms,min_ms,max_ms,q1_ms,q3_ms,cpu_median_ms,fps,speedup_vs_multipass,"
            "cpu_speedup_vs_multipass,draw_ms,readback_ms,gpu_ms,error\n");
        for (const RenderRow& r : report.rows) {
            fmt::print(
                "{},{},{},\"{}\",{},{},{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},"
                "{:.2f},{:.3f},{:.3f},{},{},{},\"{}\"\n",
                report.bench, r.backend, r.method, r.model, r.copies, r.triangles, r.shading,
                r.views, r.config, r.width, r.height, r.wall.n, r.wall.median, r.wall.min,
                r.wall.max, r.wall.q1, r.wall.q3, r.cpu.median,
                r.wall.median > 0 ? 1000.0 / r.wall.median : 0.0, r.speedup, r.cpuSpeedup,
                csvMs(r.device.measured && r.error.empty(), r.device.drawMs),
                csvMs(r.device.measured && r.error.empty(), r.device.readbackMs),
                csvMs(r.device.gpuMs.has_value() && r.error.empty(), r.device.gpuMs.value_or(0)),
                r.error);
        }
    } else {
        fmt::print("{}\n", machineLine(*report.machine));
        for (const PivotTable& t : report.tables) {
            printPivot(t, report.rows);
            // A GPU backend's rows: the same table of its draw / readback / GPU timer.
            const bool device =
                std::any_of(report.rows.begin(), report.rows.end(),
                            [&](const RenderRow& r) { return t.filter(r) && r.device.measured; });
            if (device) printPivot(deviceTable(t), report.rows);
        }
        for (const Skipped& s : report.skipped) fmt::print("skipped {}: {}\n", s.spec, s.reason);
    }
    if (!o.plot.empty()) {
        if (Status s = plotRenderRows(report, o.plot); !s) return fail(s);
    }
    return 0;
}

// ---- adelson rows ---------------------------------------------------------------------------

int printAdelsonReport(const AdelsonReport& report, const CommonOptions& o) {
    if (o.json || !o.saveJson.empty()) {
        if (Status s = detail::emitJson(report, o); !s) return fail(s);
    }
    auto pct = [](double v) { return fmt::format("{:.1f}%", v * 100.0); };
    const Machine& machine = *report.machine;
    if (o.json) {
        // printed above
    } else if (o.csv) {
        fmt::print("# {}\n", machineLine(machine));
        fmt::print(
            "algorithm,case,ops_separate,ops_simultaneous,ops_I,ops_II,ops_III,interp_I,ms_separate,"
            "ms_simultaneous,ms_separate_min,ms_separate_max,ms_simultaneous_min,ms_simultaneous_max,"
            "time_I,time_II,time_III,paper_I,paper_II,paper_III,results_agree\n");
        for (const AdelsonRow& r : report.rows) {
            fmt::print(
                "\"{}\",\"{}\",{},{},{:.4f},{:.4f},{:.4f},{},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},"
                "{:.4f},{:.4f},{:.4f},\"{}\",\"{}\",\"{}\",{}\n",
                r.algorithm, r.caseName, r.opsSep.total(), r.opsSim.total(), r.byOps.measureI,
                r.byOps.measureII, r.byOps.measureIII,
                r.hasInterp ? fmt::format("{:.4f}", r.byInterp.measureI) : "", r.sepMs.median,
                r.simMs.median, r.sepMs.min, r.sepMs.max, r.simMs.min, r.simMs.max,
                r.byTime.measureI, r.byTime.measureII, r.byTime.measureIII, r.paperI, r.paperII,
                r.paperIII, r.check.empty() ? "yes" : "no");
        }
    } else {
        fmt::print("{}\n", machineLine(machine));
        fmt::print(
            "\nadelson1991 Table 1 — savings of the simultaneous (both eyes at once) algorithm over the "
            "single-eye algorithm run for each eye, mvr's own implementations of both; I = 1 − sim/sep, "
            "II = 1 − (sim − sep/2)/(sep/2), III = sep/sim; ops = additions + multiplications + comparisons "
            "(counted in the code); time = thread CPU time, median of {} batches ({} warm-up), ms per "
            "stereo pair [min–max]\n\n",
            o.frames, o.warmup);
        fmt::print(
            "| algorithm | workload | ops I | ops II | ops III | time sep ms | time sim ms | time I | "
            "time II | time III | paper I / II / III | same result |\n");
        fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (const AdelsonRow& r : report.rows) {
            std::string opsI = pct(r.byOps.measureI);
            if (r.hasInterp) opsI += fmt::format(" (interp. {})", pct(r.byInterp.measureI));
            fmt::print(
                "| {} | {} | {} | {} | {:.2f} | {:.3f} [{:.3f}–{:.3f}] | {:.3f} [{:.3f}–{:.3f}] | {} | {} | "
                "{:.2f} | {} / {} / {} | {} |\n",
                r.algorithm, r.caseName, opsI, pct(r.byOps.measureII), r.byOps.measureIII,
                r.sepMs.median, r.sepMs.min, r.sepMs.max, r.simMs.median, r.simMs.min, r.simMs.max,
                pct(r.byTime.measureI), pct(r.byTime.measureII), r.byTime.measureIII, r.paperI,
                r.paperII, r.paperIII,
                r.check.empty() ? "yes: " + r.checkDetail : "NO: " + r.check);
        }
    }
    if (!o.plot.empty()) {
        std::string data;
        for (const AdelsonRow& r : report.rows) {
            std::string text = r.label;
            std::replace(text.begin(), text.end(), '"', '\'');
            data += fmt::format("\"{}\" {:.3f} {:.3f}\n", text, r.byOps.measureI * 100.0,
                                r.byTime.measureI * 100.0);
        }
        const std::string script = fmt::format(
            "set title {}\nset style data histograms\nset style histogram clustered gap 1\n"
            "set style fill solid 0.8 border -1\nset boxwidth 0.9\nset ylabel 'saving, measure I (%)'\n"
            "set yrange [-60:55]\nset grid ytics\nset xtics rotate by -35 left font ',9'\nset bmargin 8\n"
            "set key top right\nset arrow from graph 0, first 50 to graph 1, first 50 nohead dt 2\n"
            "plot DATA using 2:xtic(1) title 'operation counts', '' using 3 title 'time (median)'\n",
            gpQuote(fmt::format(
                "adelson1991 Table 1 on this machine (measure I; 50% = both eyes for the "
                "price of one; bars clipped at -60%) — {}",
                machine.cpu)));
        if (Status s = runGnuplot(o.plot, data, script); !s) return fail(s);
    }
    return 0;
}

// ---- plots ----------------------------------------------------------------------------------

Status checkPlotTarget(const std::string& file) {
    const std::string ext = fs::path(file).extension().string();
    if (ext != ".png" && ext != ".svg") {
        return usageError(fmt::format("--plot '{}' must end in .png or .svg", file));
    }
    bool found = false;
    if (const char* path = std::getenv("PATH")) {
        const std::string p = path;
        for (std::size_t start = 0; start <= p.size();) {
            const std::size_t end = p.find(':', start);
            const std::string dir =
                p.substr(start, end == std::string::npos ? std::string::npos : end - start);
            if (!dir.empty() && ::access((fs::path(dir) / "gnuplot").c_str(), X_OK) == 0)
                found = true;
            if (end == std::string::npos) break;
            start = end + 1;
        }
    }
    if (!found) {
        return unsupportedError(
            "--plot: gnuplot is not installed (not on PATH; Debian: apt-get install "
            "gnuplot-nox)");
    }
    return {};
}

}  // namespace mvr::cli::bench
