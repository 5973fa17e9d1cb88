// `mvr bench sorbier | kalaiah | adelson` — the papers' experiments on this machine.
//
// Every bench: warm-up, then repeated timed samples interleaved over the methods (so that a
// change in machine load hits every method alike), median and spread (min, max, quartiles);
// the first line names the machine; a progress bar on stderr when it is a terminal (or lines
// with --progress); markdown tables, --json or --csv on stdout; --plot FILE.png|.svg through
// gnuplot.
#include "bench_papers.h"

#include "mvr/core/platform.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <thread>

#include <fmt/core.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mvr/adelson/adelson.h"
#include "options.h"

#include "mvr/raster/soft_backend.h"
#if __has_include(<nlohmann/json.hpp>)
#include <nlohmann/json.hpp>
#define MVR_PAPERS_HAVE_JSON 1
#endif

#ifndef MVR_DEFAULT_SHARED_DIR
#define MVR_DEFAULT_SHARED_DIR ""
#endif

namespace mvr::cli {
namespace {

namespace fs = std::filesystem;

// ---- options common to the three benches --------------------------------------------------------

struct CommonOptions {
    int frames = 5;
    int warmup = 1;
    int threads = 0;
    bool json = false;
    bool csv = false;
    bool progress = false;
    std::string plot;
    std::string saveJson;  ///< also write the JSON here (tables still on stdout)
};

void addCommon(CLI::App* app, CommonOptions& o, const char* framesHelp) {
    app->add_option("--frames", o.frames, framesHelp)->default_val(o.frames);
    app->add_option("--warmup", o.warmup, "Untimed runs of each method before timing")->default_val(o.warmup);
    app->add_option("--threads", o.threads, "soft: worker threads (0 = one per core)")->default_val(o.threads);
    auto* json = app->add_flag("--json", o.json, "Print JSON instead of tables");
    app->add_flag("--csv", o.csv, "Print CSV (one row per measurement) instead of tables")->excludes(json);
    app->add_flag("--progress", o.progress, "Progress lines on stderr even when it is not a terminal");
    app->add_option("--plot", o.plot, "Also draw FILE.png or FILE.svg with gnuplot");
    app->add_option("--save-json", o.saveJson, "Also write the JSON to FILE");
}

Status checkCommon(const CommonOptions& o) {
    if (o.frames < 1 || o.frames > 100000) {
        return usageError(fmt::format("--frames {} is out of range (expected 1..100000)", o.frames));
    }
    if (o.warmup < 0 || o.warmup > 1000) {
        return usageError(fmt::format("--warmup {} is out of range (expected 0..1000)", o.warmup));
    }
    if (o.threads < 0 || o.threads > 1024) {
        return usageError(fmt::format("--threads {} is out of range (expected 0..1024, 0 = all cores)", o.threads));
    }
    if (!o.plot.empty()) {
        const std::string ext = fs::path(o.plot).extension().string();
        if (ext != ".png" && ext != ".svg") {
            return usageError(fmt::format("--plot '{}' must end in .png or .svg", o.plot));
        }
        // gnuplot must be there before we spend minutes measuring.
        bool found = false;
        if (const char* path = std::getenv("PATH")) {
            std::string p = path;
            std::size_t start = 0;
            while (start <= p.size()) {
                const std::size_t end = p.find(':', start);
                const std::string dir = p.substr(start, end == std::string::npos ? std::string::npos : end - start);
                if (!dir.empty() && ::access((fs::path(dir) / "gnuplot").c_str(), X_OK) == 0) found = true;
                if (end == std::string::npos) break;
                start = end + 1;
            }
        }
        if (!found) {
            return unsupportedError("--plot: gnuplot is not installed (not on PATH; Debian: apt-get install gnuplot-nox)");
        }
    }
    return {};
}

// ---- statistics ---------------------------------------------------------------------------------

struct Stats {
    double median = 0, min = 0, max = 0, q1 = 0, q3 = 0;
    int n = 0;
};

double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double pos = q * double(sorted.size() - 1);
    const std::size_t i = std::size_t(pos);
    const double f = pos - double(i);
    return i + 1 < sorted.size() ? sorted[i] * (1 - f) + sorted[i + 1] * f : sorted[i];
}

Stats statsOf(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    s.n = int(v.size());
    s.median = quantile(v, 0.5), s.q1 = quantile(v, 0.25), s.q3 = quantile(v, 0.75);
    s.min = v.front(), s.max = v.back();
    return s;
}

double threadCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double processCpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

// ---- the machine --------------------------------------------------------------------------------

struct Machine {
    std::string cpu = "unknown CPU", simd = "-", glRenderer = "no GL backend in this build";
    int cores = 1, threads = 1;
    std::string date;
    std::string line() const {
        return fmt::format("machine: {} | {} hardware threads | soft: SIMD {}, {} worker threads | GL_RENDERER: {} | {}",
                           cpu, cores, simd, threads, glRenderer, date);
    }
};

Machine describeMachine(int threads, bool wantGl) {
    Machine m;
    m.cpu = cpuModelName();
    m.cores = int(std::max(1u, std::thread::hardware_concurrency()));
    m.threads = threads > 0 ? threads : m.cores;
    m.simd = raster::simdPathName(raster::bestSimdPath());
    if (wantGl) {
        auto gl = makeBackend("gl");
        if (gl) {
            m.glRenderer = "none";
            if (Status s = (*gl)->supports("multipass"); !s) m.glRenderer = "none (" + s.message() + ")";
            for (const std::string& l : (*gl)->info()) {
                if (l.rfind("GL_RENDERER: ", 0) == 0) m.glRenderer = l.substr(13);
            }
        }
    } else {
        m.glRenderer = "not used";
    }
    const std::time_t now = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    m.date = buf;
    return m;
}

#ifdef MVR_PAPERS_HAVE_JSON
/// Prints the JSON (--json) and/or writes it to --save-json FILE.
Status emitJson(const nlohmann::json& j, const CommonOptions& o) {
    if (o.json) fmt::print("{}\n", j.dump(2));
    if (!o.saveJson.empty()) {
        std::ofstream out(o.saveJson);
        out << j.dump(2) << "\n";
        if (!out) return outputError(fmt::format("--save-json: cannot write '{}'", o.saveJson));
    }
    return {};
}
nlohmann::json machineJson(const Machine& m) {
    return {{"cpu", m.cpu}, {"cores", m.cores}, {"simd", m.simd}, {"threads", m.threads},
            {"gl_renderer", m.glRenderer}, {"date", m.date}};
}
nlohmann::json statsJson(const Stats& s) {
    return {{"median", s.median}, {"min", s.min}, {"max", s.max}, {"q1", s.q1}, {"q3", s.q3}, {"n", s.n}};
}
#endif

// ---- progress -----------------------------------------------------------------------------------

class Progress {
public:
    Progress(int total, bool machineReadable, bool force)
        : mTotal(std::max(total, 1)), mBar(!machineReadable && isatty(STDERR_FILENO)), mLines(force && !mBar) {}
    void step(const std::string& label) {
        ++mDone;
        if (mBar) {
            const int width = 30, filled = mDone * width / mTotal;
            fmt::print(stderr, "\r[{}{}] {}/{} {:<50.50}", std::string(filled, '#'), std::string(width - filled, '.'),
                       mDone, mTotal, label);
            std::fflush(stderr);
        } else if (mLines) {
            fmt::print(stderr, "[{}/{}] {}\n", mDone, mTotal, label);
            std::fflush(stderr);
        }
    }
    void done() {
        if (mBar) fmt::print(stderr, "\r{:100}\r", "");
    }

private:
    int mTotal, mDone = 0;
    bool mBar, mLines;
};

// ---- gnuplot --------------------------------------------------------------------------------------

std::string gpQuote(const std::string& s) {
    std::string out = "'";
    for (const char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

/// Writes `data` and `script` (which refers to the data file as DATA and the output as OUT) to a
/// temporary folder and runs gnuplot on it.
Status runGnuplot(const std::string& output, const std::string& data, std::string script) {
    std::error_code ec;
    const fs::path dir = fs::temp_directory_path(ec) / fmt::format("mvr-plot-{}", ::getpid());
    fs::create_directories(dir, ec);
    if (ec) return outputError(fmt::format("--plot: cannot create {}: {}", dir.string(), ec.message()));
    const fs::path dataPath = dir / "data.dat", scriptPath = dir / "plot.gp";
    const std::string ext = fs::path(output).extension().string();
    const std::string terminal = ext == ".svg" ? "set terminal svg size 1500,520 dynamic font 'sans,11'\n"
                                               : "set terminal pngcairo size 1500,520 font 'sans,10'\n";
    auto replaceAll = [](std::string& s, const std::string& from, const std::string& to) {
        for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size()) {
            s.replace(pos, from.size(), to);
        }
    };
    replaceAll(script, "DATA", gpQuote(dataPath.string()));
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
            return unsupportedError("--plot: gnuplot could not be run (Debian: apt-get install gnuplot-nox)");
        }
        return outputError(fmt::format("--plot: gnuplot failed writing '{}' (exit status {})", output,
                                       WIFEXITED(status) ? WEXITSTATUS(status) : -1));
    }
    return {};
}

// ---- rendering methods ------------------------------------------------------------------------------

struct Job {
    std::string backend, method;
    Backend* impl = nullptr;
    std::string spec() const { return backend + ":" + method; }
};

struct Backends {
    std::map<std::string, std::unique_ptr<Backend>> byName;
    int threads = 0;
    Result<Backend*> get(const std::string& name) {
        auto it = byName.find(name);
        if (it != byName.end()) return it->second.get();
        auto made = makeBackend(name, BackendOptions{.threads = threads});
        if (!made) return made.status();
        Backend* raw = made->get();
        byName[name] = std::move(made).value();
        return raw;
    }
};

/// Parses BACKEND:METHOD entries, adds BACKEND:multipass as the baseline of every backend used
/// (first), and sorts out what cannot run here. Unknown backend or method: Usage error.
Result<std::vector<Job>> resolveJobs(const std::vector<std::string>& specs, Backends& backends,
                                     std::vector<std::pair<std::string, std::string>>& skipped) {
    std::vector<Job> wanted;
    for (const std::string& spec : specs) {
        const auto colon = spec.find(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size()) {
            return usageError(fmt::format("--methods entry '{}' is not of the form BACKEND:METHOD (e.g. soft:unified)", spec));
        }
        const std::string b = spec.substr(0, colon), m = spec.substr(colon + 1);
        if (b != "soft" && b != "gl") return usageError(fmt::format("--methods entry '{}': unknown backend '{}' (expected soft or gl)", spec, b));
        if (m == "auto") return usageError(fmt::format("--methods entry '{}': 'auto' is not a method to measure (it picks one of the others)", spec));
        wanted.push_back({b, m});
    }
    if (wanted.empty()) return usageError("--methods is empty (expected e.g. soft:multipass,soft:unified)");
    std::vector<Job> withBase;
    std::set<std::string> seen;
    for (const Job& j : wanted) {
        if (!seen.count(j.backend)) {
            seen.insert(j.backend);
            withBase.push_back({j.backend, "multipass"});
        }
        if (j.method != "multipass") withBase.push_back(j);
    }
    std::vector<Job> jobs;
    std::set<std::string> unique;
    for (Job& j : withBase) {
        if (!unique.insert(j.spec()).second) continue;
        auto b = backends.get(j.backend);
        if (!b) {
            if (b.status().code() == ErrorCode::Usage) return b.status();
            skipped.push_back({j.spec(), b.status().message()});
            continue;
        }
        const std::vector<std::string> known = (*b)->methods();
        if (std::find(known.begin(), known.end(), j.method) == known.end()) {
            std::string list;
            for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
            return usageError(fmt::format("--methods entry '{}': unknown method '{}' of backend {} (expected one of: {})",
                                          j.spec(), j.method, j.backend, list));
        }
        if (Status s = (*b)->supports(j.method); !s) {
            if (s.code() == ErrorCode::Usage) return s;
            skipped.push_back({j.spec(), s.message()});
            continue;
        }
        j.impl = *b;
        jobs.push_back(j);
    }
    return jobs;
}

struct Measured {
    std::vector<double> wallMs, cpuMs;
    std::string error;  ///< why this method could not render this configuration
    std::string ran;
};

/// Warm-up then `frames` rounds over the jobs, each render timed (wall and process CPU).
std::vector<Measured> measure(std::vector<Job>& jobs, const Prepared& p, const CommonOptions& o,
                              Progress& progress, const std::string& label) {
    std::vector<Measured> out(jobs.size());
    for (int round = 0; round < o.warmup + o.frames; ++round) {
        for (std::size_t j = 0; j < jobs.size(); ++j) {
            Measured& m = out[j];
            if (!m.error.empty()) continue;
            const double cpu0 = processCpuMs();
            const auto t0 = std::chrono::steady_clock::now();
            auto r = jobs[j].impl->render(p.scene, p.rig, p.settings, jobs[j].method);
            const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            const double cpu = processCpuMs() - cpu0;
            if (!r) {
                m.error = r.status().message();
                continue;
            }
            m.ran = r->method;
            if (round >= o.warmup) m.wallMs.push_back(wall), m.cpuMs.push_back(cpu);
        }
    }
    for (const Job& j : jobs) progress.step(label + " " + j.spec());
    return out;
}

/// A model path from the command line, or the shared folder's.
Result<std::string> findModel(const std::string& given, const std::string& defaultName) {
    if (!given.empty()) return given;
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("MVR_SHARED_DIR"); env && *env) candidates.push_back(fs::path(env) / "models" / defaultName);
    if (*MVR_DEFAULT_SHARED_DIR) candidates.push_back(fs::path(MVR_DEFAULT_SHARED_DIR) / "models" / defaultName);
    candidates.push_back(fs::path("../shared/models") / defaultName);
    candidates.push_back(fs::path("shared/models") / defaultName);
    for (const fs::path& c : candidates) {
        std::error_code ec;
        if (fs::is_regular_file(c, ec)) return c.string();
    }
    return inputError(fmt::format("no model given and {} not found (expected a MODEL argument, or "
                                  "$MVR_SHARED_DIR/models/{} or ../shared/models/{})",
                                  defaultName, defaultName, defaultName));
}

std::string fmtFps(double ms) { return ms > 0 ? fmt::format("{:.1f}", 1000.0 / ms) : "-"; }

struct RenderRow {
    std::string backend, method, ran, shading, model, config, error;
    int copies = 1, views = 2, width = 0, height = 0;
    int bufferW = 0, bufferH = 0;  ///< kalaiah: the buffer the views share
    std::size_t triangles = 0;
    Stats wall, cpu;
    double speedup = 0, cpuSpeedup = 0;  ///< multipass of the same backend / this
};

/// The row of one measured job: what every render bench records; the caller adds its own columns.
RenderRow measuredRow(const Job& job, const Measured& m, std::size_t triangles) {
    RenderRow r;
    r.backend = job.backend, r.method = job.method, r.ran = m.ran;
    r.triangles = triangles;
    r.error = m.error;
    r.wall = statsOf(m.wallMs), r.cpu = statsOf(m.cpuMs);
    return r;
}

void fillSpeedups(std::vector<RenderRow>& rows, std::size_t first) {
    for (std::size_t i = first; i < rows.size(); ++i) {
        for (std::size_t k = first; k < rows.size(); ++k) {
            if (rows[k].backend == rows[i].backend && rows[k].method == "multipass" && rows[k].error.empty() &&
                rows[i].error.empty() && rows[i].wall.median > 0) {
                rows[i].speedup = rows[k].wall.median / rows[i].wall.median;
                rows[i].cpuSpeedup = rows[i].cpu.median > 0 ? rows[k].cpu.median / rows[i].cpu.median : 0;
            }
        }
    }
}

int printRenderRows(const char* bench, const Machine& machine, const std::vector<RenderRow>& rows,
                    const std::vector<std::pair<std::string, std::string>>& skipped, const CommonOptions& o,
                    const std::function<void()>& printTables) {
    const CommonOptions& ocommon = o;
    if (o.json || !o.saveJson.empty()) {
#ifdef MVR_PAPERS_HAVE_JSON
        nlohmann::json j;
        j["bench"] = bench;
        j["machine"] = machineJson(machine);
        j["frames"] = o.frames, j["warmup"] = o.warmup;
        j["results"] = nlohmann::json::array();
        for (const RenderRow& r : rows) {
            nlohmann::json e = {{"backend", r.backend}, {"method", r.method}, {"model", r.model},
                                {"copies", r.copies}, {"triangles", r.triangles}, {"shading", r.shading},
                                {"views", r.views}, {"config", r.config}, {"width", r.width}, {"height", r.height}};
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
            }
            j["results"].push_back(e);
        }
        j["skipped"] = nlohmann::json::array();
        for (const auto& [m, why] : skipped) j["skipped"].push_back({{"method", m}, {"reason", why}});
        if (Status st = emitJson(j, ocommon); !st) return fail(st);
#else
        return fail(unsupportedError("--json needs nlohmann-json, which this mvr was built without"));
#endif
    }
    if (o.json) {
        // printed above
    } else if (o.csv) {
        fmt::print("# {}\n", machine.line());
        fmt::print("bench,backend,method,model,copies,triangles,shading,views,config,width,height,frames,"
                   "median_ms,min_ms,max_ms,q1_ms,q3_ms,cpu_median_ms,fps,speedup_vs_multipass,"
                   "cpu_speedup_vs_multipass,error\n");
        for (const RenderRow& r : rows) {
            fmt::print("{},{},{},\"{}\",{},{},{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.2f},{:.3f},{:.3f},\"{}\"\n",
                       bench, r.backend, r.method, r.model, r.copies, r.triangles, r.shading, r.views, r.config,
                       r.width, r.height, r.wall.n, r.wall.median, r.wall.min, r.wall.max, r.wall.q1, r.wall.q3,
                       r.cpu.median, r.wall.median > 0 ? 1000.0 / r.wall.median : 0.0, r.speedup, r.cpuSpeedup,
                       r.error);
        }
    } else {
        fmt::print("{}\n", machine.line());
        printTables();
        for (const auto& [m, why] : skipped) fmt::print("skipped {}: {}\n", m, why);
    }
    return 0;
}

/// "fps [min–max] ×speedup (cpu ×)" for a table cell.
std::string cell(const RenderRow& r) {
    if (!r.error.empty()) return "n/a";
    return fmt::format("{} [{}–{}] {:.2f}× (cpu {:.2f}×)", fmtFps(r.wall.median), fmtFps(r.wall.max),
                       fmtFps(r.wall.min), r.speedup, r.cpuSpeedup);
}

// ---- sorbier2008 Tables 1 and 2 --------------------------------------------------------------------

struct SorbierOptions {
    CommonOptions common;
    std::string model;
    std::vector<int> copies{1, 3, 5, 9};
    std::vector<std::string> shadings{"flat", "vertex", "pixel"};
    std::vector<std::string> sizes{"1024x768"};
    std::vector<std::string> methods{"soft:multipass",     "soft:unified",     "gl:multipass",
                                     "gl:gs-mrt",          "gl:gs-depthmap",   "gl:gs-layered",
                                     "gl:gs-invocations",  "gl:instanced-layer", "gl:viewport-array",
                                     "gl:kalaiah-emulation"};
};

std::string plotRenderScript(const std::string& title, const std::vector<std::string>& panels,
                             const std::vector<std::string>& series, const std::string& xlabel, bool logx) {
    std::string s;
    const int cols = int(std::min<std::size_t>(panels.size(), 3));
    const int rowsN = int((panels.size() + cols - 1) / cols);
    s += fmt::format("set multiplot layout {},{} title {}\n", rowsN, cols, gpQuote(title));
    s += fmt::format("set xlabel {}\nset ylabel 'fps (median; bars: min-max)'\nset logscale y\nset grid\n", gpQuote(xlabel));
    if (logx) s += "set logscale x\n";
    if (xlabel == "triangles") s += "set format x '%.0s%c'\n";  // 100k, 200k, …
    if (xlabel == "views") s += "set xtics (1, 2, 3, 4, 6, 9)\n";
    s += "set key inside top right font ',7' samplen 2 spacing 0.9 opaque box\nset pointsize 0.7\n";
    int index = 0;
    for (std::size_t p = 0; p < panels.size(); ++p) {
        s += fmt::format("set title {}\nplot ", gpQuote(panels[p]));
        for (std::size_t k = 0; k < series.size(); ++k) {
            s += fmt::format("{}DATA index {} using 1:2:3:4 with yerrorlines lw 1.5 title {}", k ? ", " : "", index++,
                             gpQuote(series[k]));
        }
        s += "\n";
        if (p == 0) s += "set key off\n";
    }
    s += "unset multiplot\n";
    return s;
}

int runSorbier(const SorbierOptions& o) {
    if (Status s = checkCommon(o.common); !s) return fail(s);
    if (o.copies.empty()) return fail(usageError("--copies is empty (expected e.g. 1,3,5,9)"));
    for (const int c : o.copies) {
        if (c < 1 || c > 1024) return fail(usageError(fmt::format("--copies {} is out of range (expected 1..1024)", c)));
    }
    std::vector<std::pair<int, int>> sizes;
    for (const std::string& sz : o.sizes) {
        auto p = parseSize(sz, "--sizes");
        if (!p) return fail(p.status());
        sizes.push_back(*p);
    }
    if (sizes.empty()) return fail(usageError("--sizes is empty (expected e.g. 1024x768)"));
    std::vector<Shading> shadings;
    for (const std::string& s : o.shadings) {
        auto sh = parseShading(s);
        if (!sh) return fail(usageError("--shadings: " + sh.status().message()));
        shadings.push_back(*sh);
    }
    if (shadings.empty()) return fail(usageError("--shadings is empty (expected flat,vertex,pixel)"));
    Backends backends;
    backends.threads = o.common.threads;
    std::vector<std::pair<std::string, std::string>> skipped;
    auto jobsR = resolveJobs(o.methods, backends, skipped);
    if (!jobsR) return fail(jobsR.status());
    std::vector<Job> jobs = std::move(jobsR).value();
    if (jobs.empty()) return fail(unsupportedError("none of the --methods can run here"));
    auto model = findModel(o.model, "stanford-bunny.obj");
    if (!model) return fail(model.status());
    const bool machineReadable = o.common.json || o.common.csv;
    const Machine machine = describeMachine(o.common.threads, backends.byName.count("gl") > 0);

    Progress progress(int(sizes.size() * o.copies.size() * shadings.size() * jobs.size()), machineReadable,
                      o.common.progress);
    std::vector<RenderRow> rows;
    for (const auto& [w, h] : sizes) {
        for (const int copies : o.copies) {
            SceneOptions so;
            so.models = {*model};
            so.grid = copies;
            so.size = fmt::format("{}x{}", w, h);
            so.views = 2;
            auto prepared = so.prepare();
            if (!prepared) return fail(prepared.status());
            Prepared& p = *prepared;
            for (std::size_t si = 0; si < shadings.size(); ++si) {
                p.settings.shading = shadings[si];
                const std::string label = fmt::format("{}x{} {} {} tris", w, h, o.shadings[si], p.scene.triangleCount());
                std::vector<Measured> m = measure(jobs, p, o.common, progress, label);
                const std::size_t first = rows.size();
                for (std::size_t j = 0; j < jobs.size(); ++j) {
                    RenderRow r = measuredRow(jobs[j], m[j], p.scene.triangleCount());
                    r.shading = shadingName(shadings[si]);
                    r.model = fs::path(*model).filename().string();
                    r.copies = copies, r.views = 2, r.width = w, r.height = h;
                    r.config = "2x1";
                    rows.push_back(r);
                }
                fillSpeedups(rows, first);
            }
        }
    }
    progress.done();

    auto tables = [&] {
        for (const auto& [w, h] : sizes) {
            fmt::print("\nsorbier2008 Tables 1 and 2 — {} × 1..{} copies, {}x{}, 2 views (off-axis), {} frames after {} "
                       "warm-up; cell: fps = 1000 / median wall ms [slowest–fastest frame] and speed-up over multipass "
                       "of the same backend (wall, and process CPU time)\n\n",
                       fs::path(*model).filename().string(), o.copies.back(), w, h, o.common.frames, o.common.warmup);
            std::string head = "| shading | method |", sep = "|---|---|";
            std::vector<std::size_t> tris;
            for (const RenderRow& r : rows) {
                if (r.width == w && r.height == h && std::find(tris.begin(), tris.end(), r.triangles) == tris.end()) {
                    tris.push_back(r.triangles);
                }
            }
            for (const std::size_t t : tris) head += fmt::format(" {} tris |", t), sep += "---|";
            fmt::print("{}\n{}\n", head, sep);
            for (const std::string& sh : o.shadings) {
                for (const Job& j : jobs) {
                    std::string line = fmt::format("| {} | {} |", sh, j.spec());
                    for (const std::size_t t : tris) {
                        std::string c = "-";
                        for (const RenderRow& r : rows) {
                            if (r.width == w && r.height == h && r.triangles == t && r.shading == sh &&
                                r.backend == j.backend && r.method == j.method) {
                                c = cell(r);
                            }
                        }
                        line += " " + c + " |";
                    }
                    fmt::print("{}\n", line);
                }
            }
        }
    };
    if (int rc = printRenderRows("sorbier2008", machine, rows, skipped, o.common, tables); rc != 0) return rc;

    if (!o.common.plot.empty()) {
        // One panel per shading, fps against triangles, one line per method (first size).
        std::string data;
        std::vector<std::string> panels, series;
        for (const Job& j : jobs) series.push_back(j.spec());
        for (const std::string& sh : o.shadings) {
            panels.push_back(sh + " shading");
            for (const Job& j : jobs) {
                data += fmt::format("# {} {}\n", sh, j.spec());
                for (const RenderRow& r : rows) {
                    if (r.width == sizes[0].first && r.height == sizes[0].second && r.shading == sh &&
                        r.backend == j.backend && r.method == j.method && r.error.empty()) {
                        data += fmt::format("{} {:.4f} {:.4f} {:.4f}\n", r.triangles, 1000.0 / r.wall.median,
                                            1000.0 / r.wall.max, 1000.0 / r.wall.min);
                    }
                }
                data += "\n\n";
            }
        }
        const std::string title = fmt::format("sorbier2008 Tables 1-2 on this machine: {}x{}, 2 views — {} | {}",
                                              sizes[0].first, sizes[0].second, machine.cpu, machine.glRenderer);
        if (Status s = runGnuplot(o.common.plot, data, plotRenderScript(title, panels, series, "triangles", false)); !s) {
            return fail(s);
        }
    }
    return 0;
}

// ---- kalaiah2007 Table 1 ------------------------------------------------------------------------------

struct KalaiahOptions {
    CommonOptions common;
    std::vector<std::string> models;
    std::vector<std::string> configs{"1x1", "2x1", "3x1", "2x2", "3x2", "3x3"};
    std::vector<std::string> sizes{"800x600"};
    std::string shading = "vertex";
    std::vector<std::string> methods{"soft:multipass",      "soft:unified",      "gl:multipass",
                                     "gl:kalaiah-emulation", "gl:gs-layered",    "gl:gs-invocations",
                                     "gl:instanced-layer",  "gl:viewport-array"};
};

int runKalaiah(const KalaiahOptions& o) {
    if (Status s = checkCommon(o.common); !s) return fail(s);
    std::vector<std::pair<int, int>> configs;
    static const std::regex kGrid(R"((\d{1,2})[xX](\d{1,2}))");
    for (const std::string& c : o.configs) {
        std::smatch m;
        if (!std::regex_match(c, m, kGrid)) return fail(usageError(fmt::format("--configs entry '{}' is not of the form CxR (e.g. 3x2)", c)));
        const int cols = std::stoi(m[1].str()), rowsN = std::stoi(m[2].str());
        if (cols < 1 || rowsN < 1 || cols * rowsN > kMaxViews) {
            return fail(usageError(fmt::format("--configs entry '{}' is out of range (expected 1..{} views)", c, kMaxViews)));
        }
        configs.push_back({cols, rowsN});
    }
    if (configs.empty()) return fail(usageError("--configs is empty (expected e.g. 1x1,2x1,3x3)"));
    std::vector<std::pair<int, int>> sizes;
    for (const std::string& sz : o.sizes) {
        auto p = parseSize(sz, "--sizes");
        if (!p) return fail(p.status());
        sizes.push_back(*p);
    }
    if (sizes.empty()) return fail(usageError("--sizes is empty (expected e.g. 800x600)"));
    for (const auto& [w, h] : sizes) {
        for (const auto& [c, r] : configs) {
            if (w / c < 1 || h / r < 1) {
                return fail(usageError(fmt::format("--sizes {}x{} is too small for {}x{} views (each view needs a pixel)", w, h, c, r)));
            }
        }
    }
    auto shading = parseShading(o.shading);
    if (!shading) return fail(shading.status());
    // Models: MODEL[@K] (K copies in a grid). Default: the shared models, smallest first.
    struct ModelSpec {
        std::string path, name;
        int copies = 1;
    };
    std::vector<ModelSpec> models;
    std::vector<std::string> given = o.models;
    if (given.empty()) {
        for (const char* name : {"suzanne.obj", "spot.obj", "teapot.obj", "stanford-bunny.obj", "stanford-bunny.obj@2"}) {
            std::string n = name;
            int k = 1;
            if (auto at = n.find('@'); at != std::string::npos) k = std::stoi(n.substr(at + 1)), n = n.substr(0, at);
            auto path = findModel("", n);
            if (!path) return fail(path.status());
            given.push_back(*path + (k > 1 ? fmt::format("@{}", k) : ""));
        }
    }
    for (const std::string& g : given) {
        ModelSpec m;
        m.path = g;
        static const std::regex kCopies(R"((.*)@(\d{1,4}))");
        std::smatch sm;
        if (std::regex_match(g, sm, kCopies)) m.path = sm[1].str(), m.copies = std::stoi(sm[2].str());
        if (m.copies < 1 || m.copies > 1024) return fail(usageError(fmt::format("model '{}': copies out of range (expected 1..1024)", g)));
        m.name = fs::path(m.path).stem().string() + (m.copies > 1 ? fmt::format("×{}", m.copies) : "");
        models.push_back(m);
    }
    Backends backends;
    backends.threads = o.common.threads;
    std::vector<std::pair<std::string, std::string>> skipped;
    auto jobsR = resolveJobs(o.methods, backends, skipped);
    if (!jobsR) return fail(jobsR.status());
    std::vector<Job> jobs = std::move(jobsR).value();
    if (jobs.empty()) return fail(unsupportedError("none of the --methods can run here"));
    const bool machineReadable = o.common.json || o.common.csv;
    const Machine machine = describeMachine(o.common.threads, backends.byName.count("gl") > 0);

    Progress progress(int(sizes.size() * models.size() * configs.size() * jobs.size()), machineReadable, o.common.progress);
    std::vector<RenderRow> rows;
    for (const auto& [w, h] : sizes) {
        for (const ModelSpec& ms : models) {
            for (const auto& [c, r] : configs) {
                SceneOptions so;
                so.models = {ms.path};
                so.grid = ms.copies;
                so.viewGrid = fmt::format("{}x{}", c, r);
                so.size = fmt::format("{}x{}", w / c, h / r);  // one buffer of w×h shared by the views
                so.shading = o.shading;
                auto prepared = so.prepare();
                if (!prepared) return fail(prepared.status());
                const Prepared& p = *prepared;
                std::vector<Measured> m = measure(jobs, p, o.common, progress, fmt::format("{} {}x{}", ms.name, c, r));
                const std::size_t first = rows.size();
                for (std::size_t j = 0; j < jobs.size(); ++j) {
                    RenderRow row = measuredRow(jobs[j], m[j], p.scene.triangleCount());
                    row.shading = o.shading, row.model = ms.name, row.copies = ms.copies;
                    row.views = c * r, row.config = fmt::format("{}x{}", c, r);
                    row.width = w / c, row.height = h / r, row.bufferW = w, row.bufferH = h;
                    rows.push_back(row);
                }
                fillSpeedups(rows, first);
            }
        }
    }
    progress.done();

    auto tables = [&] {
        for (const auto& [w, h] : sizes) {
            fmt::print("\nkalaiah2007 Table 1 — C×R views sharing one {}x{} buffer (each view {}/C × {}/R), {} shading, "
                       "{} frames after {} warm-up; cell: fps = 1000 / median wall ms [slowest–fastest frame] and "
                       "speed-up over multipass of the same backend (C = multipass, U = the one-pass method)\n\n",
                       w, h, w, h, o.shading, o.common.frames, o.common.warmup);
            std::string head = "| model (triangles) | views |", sep = "|---|---|";
            for (const Job& j : jobs) head += " " + j.spec() + " |", sep += "---|";
            fmt::print("{}\n{}\n", head, sep);
            for (const ModelSpec& ms : models) {
                for (const auto& [c, r] : configs) {
                    const std::string cfg = fmt::format("{}x{}", c, r);
                    std::string line;
                    for (const Job& j : jobs) {
                        for (const RenderRow& row : rows) {
                            if (row.model == ms.name && row.config == cfg && row.bufferW == w && row.bufferH == h &&
                                row.backend == j.backend && row.method == j.method) {
                                if (line.empty()) line = fmt::format("| {} ({}) | {} |", ms.name, row.triangles, cfg);
                                line += " " + cell(row) + " |";
                            }
                        }
                    }
                    fmt::print("{}\n", line);
                }
            }
        }
    };
    if (int rc = printRenderRows("kalaiah2007", machine, rows, skipped, o.common, tables); rc != 0) return rc;

    if (!o.common.plot.empty()) {
        std::string data;
        std::vector<std::string> panels, series;
        for (const Job& j : jobs) series.push_back(j.spec());
        for (const ModelSpec& ms : models) {
            std::size_t tris = 0;
            for (const Job& j : jobs) {
                data += fmt::format("# {} {}\n", ms.name, j.spec());
                for (const RenderRow& row : rows) {
                    if (row.model == ms.name && row.backend == j.backend && row.method == j.method &&
                        row.bufferW == sizes[0].first && row.bufferH == sizes[0].second && row.error.empty()) {
                        data += fmt::format("{} {:.4f} {:.4f} {:.4f}\n", row.views, 1000.0 / row.wall.median,
                                            1000.0 / row.wall.max, 1000.0 / row.wall.min);
                        tris = row.triangles;
                    }
                }
                data += "\n\n";
            }
            panels.push_back(fmt::format("{} ({} triangles)", ms.name, tris));
        }
        const std::string title = fmt::format("kalaiah2007 Table 1 on this machine: views sharing one {}x{} buffer — {} | {}",
                                              sizes[0].first, sizes[0].second, machine.cpu, machine.glRenderer);
        if (Status s = runGnuplot(o.common.plot, data, plotRenderScript(title, panels, series, "views", false)); !s) {
            return fail(s);
        }
    }
    return 0;
}

// ---- adelson1991 Table 1 ------------------------------------------------------------------------------

struct AdelsonOptions {
    CommonOptions common;
    bool tiny = false;
    double minBatchMs = 20.0;
    std::string only;
};

struct AdelsonRow {
    std::string algorithm, caseName, label, paperI, paperII, paperIII, opsNote, check, checkDetail;
    adelson::OpCounts opsSep, opsSim;
    Stats sepMs, simMs;      ///< thread CPU time per call of both eyes
    Stats sepWall, simWall;  ///< wall time per call
    int reps = 1;
    adelson::Savings byOps, byTime, byInterp;
    bool hasInterp = false;
};

int runAdelson(const AdelsonOptions& o) {
    if (Status s = checkCommon(o.common); !s) return fail(s);
    if (!(o.minBatchMs >= 0.0 && o.minBatchMs <= 10000.0)) {
        return fail(usageError(fmt::format("--min-batch-ms {} is out of range (expected 0..10000)", o.minBatchMs)));
    }
    const bool machineReadable = o.common.json || o.common.csv;
    const Machine machine = describeMachine(o.common.threads, false);
    std::vector<adelson::ExperimentCase> cases = adelson::adelsonCases(o.tiny);
    if (!o.only.empty()) {
        std::erase_if(cases, [&](const adelson::ExperimentCase& c) {
            std::string a = c.algorithm, q = o.only;
            std::transform(a.begin(), a.end(), a.begin(), ::tolower);
            std::transform(q.begin(), q.end(), q.begin(), ::tolower);
            return a.find(q) == std::string::npos;
        });
        if (cases.empty()) return fail(usageError(fmt::format("--only '{}' matches no algorithm of Table 1", o.only)));
    }
    Progress progress(int(cases.size()), machineReadable, o.common.progress);
    std::vector<AdelsonRow> rows;
    using Clock = std::chrono::steady_clock;
    for (adelson::ExperimentCase& c : cases) {
        AdelsonRow r;
        r.algorithm = c.algorithm, r.caseName = c.caseName, r.label = c.label, r.paperI = c.paperI, r.paperII = c.paperII,
        r.paperIII = c.paperIII, r.opsNote = c.opsNote;
        r.check = c.check(r.checkDetail);  // results must agree before anything is timed
        c.separate(&r.opsSep);
        c.simultaneous(&r.opsSim);
        for (int i = 0; i < o.common.warmup; ++i) c.separate(nullptr), c.simultaneous(nullptr);
        // Repetitions per batch: enough for --min-batch-ms of the separate version.
        const auto t0 = Clock::now();
        c.separate(nullptr);
        const double once = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        r.reps = once > 0 ? std::clamp(int(std::ceil(o.minBatchMs / once)), 1, 1000000) : 1;
        // Each batch is timed by this thread's CPU time (the algorithms are single-threaded: time
        // spent descheduled by other processes does not count) and by wall time.
        std::vector<double> sep, sim, sepWall, simWall;
        for (int b = 0; b < o.common.frames; ++b) {
            for (int which = 0; which < 2; ++which) {  // alternate which goes first
                const bool doSep = (which == 0) == (b % 2 == 0);
                const double c0 = threadCpuMs();
                const auto s0 = Clock::now();
                for (int k = 0; k < r.reps; ++k) doSep ? c.separate(nullptr) : c.simultaneous(nullptr);
                const double wall = std::chrono::duration<double, std::milli>(Clock::now() - s0).count() / r.reps;
                const double cpu = (threadCpuMs() - c0) / r.reps;
                (doSep ? sep : sim).push_back(cpu);
                (doSep ? sepWall : simWall).push_back(wall);
            }
        }
        r.sepWall = statsOf(sepWall), r.simWall = statsOf(simWall);
        r.sepMs = statsOf(sep), r.simMs = statsOf(sim);
        r.byOps = adelson::savingsFrom(double(r.opsSep.total()), double(r.opsSim.total()));
        r.byTime = adelson::savingsFrom(r.sepMs.median, r.simMs.median);
        // Interpolation counts are the paper's measure for Gouraud shading only.
        r.hasInterp = r.opsSep.interps > 0 && (r.algorithm.find("Gouraud") != std::string::npos ||
                                               r.caseName.find("Gouraud") != std::string::npos);
        if (r.hasInterp) r.byInterp = adelson::savingsFrom(double(r.opsSep.interps), double(r.opsSim.interps));
        rows.push_back(r);
        progress.step(c.algorithm + ": " + c.caseName);
    }
    progress.done();
    bool allAgree = true;
    for (const AdelsonRow& r : rows) allAgree = allAgree && r.check.empty();

    auto pct = [](double v) { return fmt::format("{:.1f}%", v * 100.0); };
    const CommonOptions& ocommon = o.common;
    if (o.common.json || !o.common.saveJson.empty()) {
#ifdef MVR_PAPERS_HAVE_JSON
        nlohmann::json j;
        j["bench"] = "adelson1991";
        j["machine"] = machineJson(machine);
        j["batches"] = o.common.frames, j["warmup"] = o.common.warmup, j["tiny"] = o.tiny;
        j["results"] = nlohmann::json::array();
        auto sav = [](const adelson::Savings& s) {
            return nlohmann::json{{"I", s.measureI}, {"II", s.measureII}, {"III", s.measureIII}};
        };
        auto ops = [](const adelson::OpCounts& c) {
            return nlohmann::json{{"adds", c.adds}, {"muls", c.muls}, {"cmps", c.cmps}, {"interps", c.interps},
                                  {"total", c.total()}};
        };
        for (const AdelsonRow& r : rows) {
            nlohmann::json e = {{"algorithm", r.algorithm}, {"case", r.caseName},
                                {"ops_separate", ops(r.opsSep)}, {"ops_simultaneous", ops(r.opsSim)},
                                {"ms_separate", statsJson(r.sepMs)}, {"ms_simultaneous", statsJson(r.simMs)},
                                {"wall_ms_separate", statsJson(r.sepWall)}, {"wall_ms_simultaneous", statsJson(r.simWall)},
                                {"reps_per_batch", r.reps},
                                {"savings_ops", sav(r.byOps)}, {"savings_time", sav(r.byTime)},
                                {"paper", {{"I", r.paperI}, {"II", r.paperII}, {"III", r.paperIII}}},
                                {"results_agree", r.check.empty()}, {"check", r.check.empty() ? r.checkDetail : r.check}};
            if (r.hasInterp) e["savings_interpolations"] = sav(r.byInterp);
            j["results"].push_back(e);
        }
        if (Status st = emitJson(j, ocommon); !st) return fail(st);
#else
        return fail(unsupportedError("--json needs nlohmann-json, which this mvr was built without"));
#endif
    }
    if (o.common.json) {
        // printed above
    } else if (o.common.csv) {
        fmt::print("# {}\n", machine.line());
        fmt::print("algorithm,case,ops_separate,ops_simultaneous,ops_I,ops_II,ops_III,interp_I,ms_separate,"
                   "ms_simultaneous,ms_separate_min,ms_separate_max,ms_simultaneous_min,ms_simultaneous_max,"
                   "time_I,time_II,time_III,paper_I,paper_II,paper_III,results_agree\n");
        for (const AdelsonRow& r : rows) {
            fmt::print("\"{}\",\"{}\",{},{},{:.4f},{:.4f},{:.4f},{},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.4f},"
                       "{:.4f},\"{}\",\"{}\",\"{}\",{}\n",
                       r.algorithm, r.caseName, r.opsSep.total(), r.opsSim.total(), r.byOps.measureI, r.byOps.measureII,
                       r.byOps.measureIII, r.hasInterp ? fmt::format("{:.4f}", r.byInterp.measureI) : "",
                       r.sepMs.median, r.simMs.median, r.sepMs.min, r.sepMs.max, r.simMs.min, r.simMs.max,
                       r.byTime.measureI, r.byTime.measureII, r.byTime.measureIII, r.paperI, r.paperII, r.paperIII,
                       r.check.empty() ? "yes" : "no");
        }
    } else {
        fmt::print("{}\n", machine.line());
        fmt::print("\nadelson1991 Table 1 — savings of the simultaneous (both eyes at once) algorithm over the "
                   "single-eye algorithm run for each eye, mvr's own implementations of both; I = 1 − sim/sep, "
                   "II = 1 − (sim − sep/2)/(sep/2), III = sep/sim; ops = additions + multiplications + comparisons "
                   "(counted in the code); time = thread CPU time, median of {} batches ({} warm-up), ms per "
                   "stereo pair [min–max]\n\n",
                   o.common.frames, o.common.warmup);
        fmt::print("| algorithm | workload | ops I | ops II | ops III | time sep ms | time sim ms | time I | time II | time III | paper I / II / III | same result |\n");
        fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (const AdelsonRow& r : rows) {
            std::string opsI = pct(r.byOps.measureI);
            if (r.hasInterp) opsI += fmt::format(" (interp. {})", pct(r.byInterp.measureI));
            fmt::print("| {} | {} | {} | {} | {:.2f} | {:.3f} [{:.3f}–{:.3f}] | {:.3f} [{:.3f}–{:.3f}] | {} | {} | {:.2f} | {} / {} / {} | {} |\n",
                       r.algorithm, r.caseName, opsI, pct(r.byOps.measureII), r.byOps.measureIII, r.sepMs.median,
                       r.sepMs.min, r.sepMs.max, r.simMs.median, r.simMs.min, r.simMs.max, pct(r.byTime.measureI),
                       pct(r.byTime.measureII), r.byTime.measureIII, r.paperI, r.paperII, r.paperIII,
                       r.check.empty() ? "yes: " + r.checkDetail : "NO: " + r.check);
        }
    }
    if (!o.common.plot.empty()) {
        std::string data;
        for (const AdelsonRow& r : rows) {
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
            gpQuote(fmt::format("adelson1991 Table 1 on this machine (measure I; 50% = both eyes for the price of one; "
                                "bars clipped at -60%) — {}", machine.cpu)));
        if (Status s = runGnuplot(o.common.plot, data, script); !s) return fail(s);
    }
    if (!allAgree) return fail(internalError("adelson: a simultaneous algorithm disagreed with its single-eye version (see the table)"));
    return 0;
}

}  // namespace

std::function<std::optional<int>()> addPaperBenches(CLI::App* bench) {
    auto so = std::make_shared<SorbierOptions>();
    CLI::App* s = bench->add_subcommand(
        "sorbier", "sorbier2008 Tables 1-2: flat/vertex/pixel shading x 1,3,5,9 bunnies (70k-630k triangles), "
                   "2 views, multipass vs every one-pass method: fps and speed-up");
    s->add_option("model", so->model, "Model (default: $MVR_SHARED_DIR/models/stanford-bunny.obj)");
    s->add_option("--copies", so->copies, "Copies of the model in a grid, comma separated")->delimiter(',')->default_str("1,3,5,9");
    s->add_option("--shadings", so->shadings, "Shading modes, comma separated")->delimiter(',')->default_str("flat,vertex,pixel");
    s->add_option("--sizes", so->sizes, "Image sizes WxH per view, comma separated")->delimiter(',')->default_str("1024x768");
    s->add_option("--methods", so->methods, "BACKEND:METHOD list (BACKEND:multipass is added as the baseline)")
        ->delimiter(',')
        ->default_str("soft:multipass,soft:unified,gl:multipass,gl:gs-mrt,gl:gs-depthmap,gl:gs-layered,...");
    addCommon(s, so->common, "Timed frames per method and configuration");

    auto ko = std::make_shared<KalaiahOptions>();
    ko->common.frames = 5;
    CLI::App* k = bench->add_subcommand(
        "kalaiah", "kalaiah2007 Table 1: views 1x1..3x3 sharing one 800x600 buffer, several models, conventional "
                   "(multipass) vs unified (one-pass) fps");
    k->add_option("models", ko->models, "Models, MODEL[@K] for K copies (default: suzanne, spot, teapot, bunny, bunny@2)");
    k->add_option("--configs", ko->configs, "View configurations CxR, comma separated")->delimiter(',')->default_str("1x1,2x1,3x1,2x2,3x2,3x3");
    k->add_option("--sizes", ko->sizes, "Shared buffer sizes WxH, comma separated")->delimiter(',')->default_str("800x600");
    k->add_option("--shading", ko->shading, "flat, vertex or pixel")->default_val(ko->shading);
    k->add_option("--methods", ko->methods, "BACKEND:METHOD list (BACKEND:multipass is added as the baseline)")
        ->delimiter(',')
        ->default_str("soft:multipass,soft:unified,gl:multipass,gl:kalaiah-emulation,gl:gs-layered,...");
    addCommon(k, ko->common, "Timed frames per method and configuration");

    auto ao = std::make_shared<AdelsonOptions>();
    ao->common.frames = 7;
    CLI::App* a = bench->add_subcommand(
        "adelson", "adelson1991 Table 1: savings of each simultaneous stereo CPU algorithm (and the village "
                   "renderer) over two single-eye runs, measures I, II, III from operation counts and time");
    a->add_flag("--tiny", ao->tiny, "Small workloads (for tests)");
    a->add_option("--min-batch-ms", ao->minBatchMs, "Repeat each algorithm until a batch takes this long")->default_val(ao->minBatchMs);
    a->add_option("--only", ao->only, "Only the algorithms whose name contains this text");
    addCommon(a, ao->common, "Timed batches per algorithm");

    return [s, k, a, so, ko, ao]() -> std::optional<int> {
        if (s->parsed()) return runSorbier(*so);
        if (k->parsed()) return runKalaiah(*ko);
        if (a->parsed()) return runAdelson(*ao);
        return std::nullopt;
    };
}

}  // namespace mvr::cli
