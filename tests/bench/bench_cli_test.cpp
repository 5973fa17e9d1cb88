// `mvr bench` and its paper subcommands end to end on tiny scenes (64x48, one small model,
// one frame): they run, --json parses with nlohmann_json and has the documented fields,
// --csv has a header and rows, --plot writes a PNG/SVG through gnuplot, bad options give one
// `error:` line and exit code 1 (usage) or 2 (input).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/core.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "mvr_test_support.h"

namespace {

namespace fs = std::filesystem;

using mvr::test::CliRun;
using mvr::test::mvrBinary;

std::string model(const char* name) { return (mvr::test::sharedModels() / name).string(); }

class BenchCli : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               fmt::format("mvr-bench-test-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }

    CliRun run(const std::string& args) const { return mvr::test::runMvr(mDir, args); }

    nlohmann::json runJson(const std::string& args) const {
        const CliRun r = run(args);
        EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
        EXPECT_TRUE(nlohmann::json::accept(r.out)) << args << "\n" << r.out;
        if (!nlohmann::json::accept(r.out)) return {};
        return nlohmann::json::parse(r.out);
    }

    void expectError(const std::string& args, int code, const std::string& needle) const {
        const CliRun r = run(args);
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        EXPECT_NE(r.err.substr(0, r.err.find('\n')).find(needle), std::string::npos)
            << args << ": " << r.err;
        EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }

    static bool haveGnuplot() { return std::system("gnuplot --version >/dev/null 2>&1") == 0; }

    fs::path mDir;
};

void expectMachine(const nlohmann::json& j) {
    ASSERT_TRUE(j.contains("machine"));
    EXPECT_TRUE(j["machine"]["cpu"].is_string());
    EXPECT_TRUE(j["machine"]["simd"].is_string());
    EXPECT_GE(j["machine"]["threads"].get<int>(), 1);
    EXPECT_TRUE(j["machine"]["gl_renderer"].is_string());
}

/// Every result either rendered (fps > 0, wall_ms stats) or says why not.
void expectRenderResults(const nlohmann::json& j) {
    ASSERT_TRUE(j["results"].is_array());
    ASSERT_FALSE(j["results"].empty());
    for (const auto& r : j["results"]) {
        EXPECT_TRUE(r["backend"].is_string());
        EXPECT_TRUE(r["method"].is_string());
        EXPECT_GT(r["triangles"].get<long>(), 0);
        if (r.contains("error")) continue;
        EXPECT_GT(r["fps"].get<double>(), 0.0);
        EXPECT_GT(r["speedup_vs_multipass"].get<double>(), 0.0);
        for (const char* k : {"median", "min", "max", "q1", "q3"})
            EXPECT_GT(r["wall_ms"][k].get<double>(), 0.0) << k;
        EXPECT_LE(r["wall_ms"]["min"].get<double>(), r["wall_ms"]["median"].get<double>());
        EXPECT_LE(r["wall_ms"]["median"].get<double>(), r["wall_ms"]["max"].get<double>());
        if (r["method"] == "multipass")
            EXPECT_DOUBLE_EQ(r["speedup_vs_multipass"].get<double>(), 1.0);
    }
    EXPECT_TRUE(j["skipped"].is_array());
}

TEST_F(BenchCli, SorbierJsonEveryDefaultMethod) {
    const nlohmann::json j =
        runJson(fmt::format("bench sorbier '{}' --sizes 64x48 --copies 1 --frames 1 --warmup 0 "
                            "--shadings flat --json",
                            model("suzanne.obj")));
    EXPECT_EQ(j["bench"], "sorbier2008");
    expectMachine(j);
    expectRenderResults(j);
    bool sawUnified = false;
    for (const auto& r : j["results"]) {
        EXPECT_EQ(r["views"], 2);
        EXPECT_EQ(r["width"], 64);
        EXPECT_EQ(r["height"], 48);
        EXPECT_EQ(r["shading"], "flat");
        sawUnified = sawUnified ||
                     (r["backend"] == "soft" && r["method"] == "unified" && !r.contains("error"));
    }
    EXPECT_TRUE(sawUnified);
}

// Each one-pass method's artifacts for the bench's own camera: per eye, the percentage of
// pixels more than 2/255 off its backend's multipass (gs-mrt's and gs-depthmap's are not 0).
TEST_F(BenchCli, SorbierReportsArtifactsPerEye) {
    const nlohmann::json j = runJson(
        fmt::format("bench sorbier '{}' --sizes 160x120 --copies 1 --frames 1 --warmup 0 "
                    "--shadings vertex --methods soft:unified,gl:gs-mrt,gl:gs-depthmap --json",
                    model("suzanne.obj")));
    int measured = 0;
    for (const auto& r : j["results"]) {
        if (r.contains("error")) continue;
        if (r["method"] == "multipass") {
            EXPECT_FALSE(r.contains("artifact_percent")) << r.dump();
            continue;
        }
        ASSERT_TRUE(r.contains("artifact_percent")) << r.dump();
        ASSERT_EQ(r["artifact_percent"].size(), 2u);
        ++measured;
        const double left = r["artifact_percent"][0], right = r["artifact_percent"][1];
        if (r["method"] == "unified") {
            EXPECT_EQ(left, 0.0);
            EXPECT_EQ(right, 0.0);
            EXPECT_EQ(r["artifact_max_delta"], 0);
        } else if (r["method"] == "gs-mrt") {
            EXPECT_GT(left, 0.5) << "gs-mrt draws hidden faces of suzanne";
        } else if (r["method"] == "gs-depthmap") {
            EXPECT_LT(left, 0.2) << "gs-depthmap's left eye is exact";
            EXPECT_GT(right, 0.0) << "its right eye loses disocclusions";
        }
    }
    EXPECT_GE(measured, 1);
    const CliRun table =
        run(fmt::format("bench sorbier '{}' --sizes 64x48 --copies 1 --frames 1 --warmup 0 "
                        "--shadings flat --methods soft:unified",
                        model("suzanne.obj")));
    EXPECT_NE(table.out.find("| flat | soft:unified | "), std::string::npos) << table.out;
    EXPECT_NE(table.out.find(" wrong px 0.00/0.00 % |"), std::string::npos) << table.out;
}

TEST_F(BenchCli, SorbierTableAddsTheMultipassBaseline) {
    const CliRun r =
        run(fmt::format("bench sorbier '{}' --sizes 64x48 --copies 1,2 --frames 1 --warmup 0 "
                        "--methods soft:unified",
                        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.out.rfind("machine: ", 0), 0u) << r.out;
    EXPECT_NE(r.out.find("| flat | soft:multipass |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("| pixel | soft:unified |"), std::string::npos) << r.out;
    EXPECT_TRUE(r.err.empty()) << r.err;  // no progress bar when stderr is not a terminal
}

TEST_F(BenchCli, SorbierCsvAndProgressLines) {
    const CliRun r =
        run(fmt::format("bench sorbier '{}' --sizes 64x48 --copies 1 --frames 1 --warmup 0 "
                        "--methods soft:unified --shadings vertex --csv --progress "
                        "--textured-model none",
                        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::istringstream in(r.out);
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(in, line)) lines.push_back(line);
    // (without the textured row: --textured-model none)
    ASSERT_EQ(lines.size(), 4u) << r.out;  // # machine, header, multipass, unified
    EXPECT_EQ(lines[0].rfind("# machine: ", 0), 0u);
    EXPECT_EQ(lines[1].rfind("bench,backend,method,", 0), 0u);
    EXPECT_EQ(lines[2].rfind("sorbier2008,soft,multipass,", 0), 0u);
    EXPECT_NE(r.err.find("[2/2]"), std::string::npos) << r.err;
}

// The textured row (issue 14): spot.obj with a generated texture, marked "textured" in JSON,
// after the untextured rows (which say "textured": false).
TEST_F(BenchCli, SorbierTexturedRow) {
    const nlohmann::json j = runJson(
        fmt::format("bench sorbier '{}' --textured-model '{}' --sizes 64x48 --copies 1 --frames 1 "
                    "--warmup 0 --methods soft:unified --shadings pixel --json",
                    model("suzanne.obj"), model("spot.obj")));
    int textured = 0, plain = 0;
    for (const auto& r : j["results"]) {
        if (r["textured"] == true) {
            ++textured;
            EXPECT_EQ(r["model"], "spot.obj (textured)");
            EXPECT_FALSE(r.contains("error")) << r.dump();
        } else {
            ++plain;
            EXPECT_EQ(r["model"], "suzanne.obj");
        }
    }
    EXPECT_EQ(textured, 2);  // soft:multipass (the baseline) and soft:unified
    EXPECT_EQ(plain, 2);
}

TEST_F(BenchCli, KalaiahJsonViewsShareTheBuffer) {
    const nlohmann::json j = runJson(
        fmt::format("bench kalaiah '{}' '{}@2' --sizes 64x48 --configs 1x1,2x1,2x2 "
                    "--frames 1 --warmup 0 --methods soft:unified,gl:kalaiah-emulation --json",
                    model("suzanne.obj"), model("suzanne.obj")));
    EXPECT_EQ(j["bench"], "kalaiah2007");
    expectMachine(j);
    expectRenderResults(j);
    int seen = 0;
    for (const auto& r : j["results"]) {
        const int views = r["views"];
        if (views == 2) {
            EXPECT_EQ(r["width"], 32);
            EXPECT_EQ(r["height"], 48);
        }
        if (views == 4) {
            EXPECT_EQ(r["width"], 32);
            EXPECT_EQ(r["height"], 24);
        }
        seen += r["backend"] == "soft";
    }
    EXPECT_EQ(seen, 2 * 3 * 2);  // soft:multipass + soft:unified, 3 configs, 2 models
}

TEST_F(BenchCli, AdelsonJsonEveryRowAgrees) {
    const nlohmann::json j =
        runJson("bench adelson --tiny --frames 1 --warmup 0 --min-batch-ms 0 --json");
    EXPECT_EQ(j["bench"], "adelson1991");
    expectMachine(j);
    ASSERT_TRUE(j["results"].is_array());
    std::set<std::string> algorithms;
    for (const auto& r : j["results"]) {
        algorithms.insert(r["algorithm"].get<std::string>());
        EXPECT_TRUE(r["results_agree"].get<bool>()) << r["algorithm"] << ": " << r["check"];
        EXPECT_GT(r["ops_separate"]["total"].get<long>(), 0);
        for (const char* k : {"I", "II", "III"}) {
            EXPECT_TRUE(r["savings_ops"][k].is_number()) << k;
            EXPECT_TRUE(r["savings_time"][k].is_number()) << k;
        }
        EXPECT_GT(r["ms_separate"]["median"].get<double>(), 0.0);
    }
    EXPECT_EQ(algorithms.size(), 9u);  // every row of adelson1991 Table 1
}

TEST_F(BenchCli, AdelsonCsvOnly) {
    const CliRun r =
        run("bench adelson --tiny --frames 1 --warmup 0 --min-batch-ms 0 --only clipping --csv");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4)
        << r.out;  // machine, header, line, polygon
    EXPECT_NE(r.out.find("\"Liang-Barsky line clipping\""), std::string::npos);
}

TEST_F(BenchCli, Plots) {
    if (!haveGnuplot()) MVR_SKIP(ToolMissing) << "gnuplot is not installed";
    CliRun r = run(fmt::format(
        "bench sorbier '{}' --sizes 64x48 --copies 1,2 --frames 1 --warmup 0 --methods soft:unified "
        "--plot s.png",
        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::ifstream png(mDir / "s.png", std::ios::binary);
    char magic[8] = {};
    png.read(magic, 8);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG");
    r = run(
        "bench adelson --tiny --frames 1 --warmup 0 --min-batch-ms 0 --only projection --plot a.svg");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::ifstream svg(mDir / "a.svg");
    std::stringstream ss;
    ss << svg.rdbuf();
    EXPECT_NE(ss.str().find("<svg"), std::string::npos);
    r = run(fmt::format(
        "bench kalaiah '{}' --sizes 64x48 --configs 1x1,2x1 --frames 1 --warmup 0 --methods soft:unified "
        "--plot k.png",
        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::file_size(mDir / "k.png") > 1000);
}

TEST_F(BenchCli, PlotWithoutGnuplotIsOneClearError) {
    // Checked before anything is measured; exit code 3 (unsupported here).
    const fs::path err = mDir / "err.txt";
    const std::string cmd = fmt::format(
        "cd '{}' && PATH=/nonexistent '{}' bench adelson --tiny --frames 1 --plot x.png "
        ">/dev/null 2>'{}'",
        mDir.string(), mvrBinary().string(), err.string());
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 3);
    std::ifstream in(err);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line.rfind("error: --plot: gnuplot is not installed", 0), 0u) << line;
    EXPECT_FALSE(fs::exists(mDir / "x.png"));
}

TEST_F(BenchCli, PlainBenchKeepsItsJsonContract) {
    const nlohmann::json j = runJson(
        fmt::format("bench '{}' --size 64x48 --frames 1 --warmup 0 --json", model("suzanne.obj")));
    for (const char* k : {"machine", "scene", "results"}) EXPECT_TRUE(j.contains(k)) << k;
    for (const auto& r : j["results"]) {
        for (const char* k : {"backend", "method", "views", "triangles", "median_ms", "min_ms",
                              "speedup_vs_first"}) {
            EXPECT_TRUE(r.contains(k)) << k;
        }
    }
}

// A result's GPU-backend timings (issue 36): a gl row has draw_ms, readback_ms (>= 0), gpu_ms
// (null, or >= 0), gpu_frames (the frames whose GPU timer was kept: 0 exactly when gpu_ms is
// null) and per_frame {draw_ms, readback_ms, gpu_ms}: one entry per timed frame, each GPU timer
// null or at most its frame's draw time (a sample above it, like llvmpipe's first
// GL_TIME_ELAPSED, is dropped). A soft row has none of these fields. Not a timing check.
// Returns whether the row is a gl row.
bool expectDeviceTimes(const nlohmann::json& r, int frames) {
    const std::string ran = r.contains("ran") ? r["ran"].get<std::string>() : "";
    // vk rows (issue 41) report the same device timings (gpu_ms null: no GPU timer yet).
    const bool gl = r["backend"] == "gl" || ran.rfind("gl:", 0) == 0 || r["backend"] == "vk" ||
                    ran.rfind("vk:", 0) == 0;
    if (!gl) {
        for (const char* k : {"draw_ms", "readback_ms", "gpu_ms", "gpu_frames", "per_frame"})
            EXPECT_FALSE(r.contains(k)) << k << ": " << r.dump();
        return false;
    }
    for (const char* k : {"draw_ms", "readback_ms", "gpu_ms", "gpu_frames", "per_frame"})
        EXPECT_TRUE(r.contains(k)) << k << ": " << r.dump();
    if (!r.contains("per_frame")) return true;
    EXPECT_GE(r["draw_ms"].get<double>(), 0.0) << r.dump();
    EXPECT_GE(r["readback_ms"].get<double>(), 0.0) << r.dump();
    EXPECT_EQ(r["gpu_ms"].is_null(), r["gpu_frames"].get<int>() == 0) << r.dump();
    if (!r["gpu_ms"].is_null()) {
        EXPECT_GE(r["gpu_ms"].get<double>(), 0.0) << r.dump();
    }
    const auto& f = r["per_frame"];
    EXPECT_EQ(f["draw_ms"].size(), std::size_t(frames)) << r.dump();
    EXPECT_EQ(f["readback_ms"].size(), std::size_t(frames)) << r.dump();
    EXPECT_EQ(f["gpu_ms"].size(), std::size_t(frames)) << r.dump();
    int kept = 0;
    for (std::size_t i = 0; i < f["gpu_ms"].size() && i < f["draw_ms"].size(); ++i) {
        EXPECT_GE(f["draw_ms"][i].get<double>(), 0.0) << r.dump();
        EXPECT_GE(f["readback_ms"][i].get<double>(), 0.0) << r.dump();
        if (f["gpu_ms"][i].is_null()) continue;
        ++kept;
        EXPECT_GE(f["gpu_ms"][i].get<double>(), 0.0) << r.dump();
        EXPECT_LE(f["gpu_ms"][i].get<double>(), f["draw_ms"][i].get<double>()) << r.dump();
    }
    EXPECT_EQ(kept, r["gpu_frames"].get<int>()) << r.dump();
    return true;
}

/// The JSON of a bench run with gl methods; nullopt (the test skips) where gl cannot run here:
/// exit code 3, or gl's jobs listed as skipped.
std::optional<nlohmann::json> glBenchJson(const CliRun& r) {
    if (r.exitCode == 3) return std::nullopt;
    EXPECT_EQ(r.exitCode, 0) << r.err;
    if (!nlohmann::json::accept(r.out)) {
        ADD_FAILURE() << r.out;
        return std::nullopt;
    }
    nlohmann::json j = nlohmann::json::parse(r.out);
    if (j.contains("skipped") && !j["skipped"].empty()) return std::nullopt;
    return j;
}

// `mvr bench`: every gl row carries the draw / readback / GPU timer medians (JSON and a column
// each in the table), soft rows none ('-'). --warmup 0: the first frame's GPU timer (llvmpipe's
// 5.9e6 ms) is among the samples and must be dropped.
TEST_F(BenchCli, PlainBenchGlRowsCarryDeviceTimes) {
    const std::string args = fmt::format(
        "bench '{}' --size 64x48 --frames 3 --warmup 0 --methods soft:unified,gl:multipass",
        model("suzanne.obj"));
    const CliRun r = run(args + " --json");
    if (r.exitCode == 3) MVR_SKIP(NoGlContext) << r.err;
    const auto j = glBenchJson(r);
    ASSERT_TRUE(j);
    int gl = 0;
    for (const auto& row : (*j)["results"]) gl += expectDeviceTimes(row, 3);
    EXPECT_EQ(gl, 1);
    const CliRun table = run(args);
    ASSERT_EQ(table.exitCode, 0) << table.err;
    for (const char* column : {"draw ms", "read ms", "gpu ms"})
        EXPECT_NE(table.out.find(column), std::string::npos) << table.out;
    std::istringstream in(table.out);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("soft:unified ", 0) == 0) {
            EXPECT_NE(line.find(" - "), std::string::npos) << line;
        }
    }
}

// The paper benches: every gl row carries them too (JSON), the tables a twin table of
// draw / readback / gpu cells.
TEST_F(BenchCli, PaperBenchGlRowsCarryDeviceTimes) {
    const std::string m = "'" + model("suzanne.obj") + "'";
    const std::string timing = " --frames 2 --warmup 0 --json";
    const std::vector<std::string> benches = {
        "bench sorbier " + m +
            " --sizes 64x48 --copies 1 --shadings flat --textured-model none "
            "--methods soft:unified,gl:gs-layered",
        "bench kalaiah " + m +
            " --sizes 64x48 --configs 2x1 --methods soft:unified,gl:kalaiah-emulation",
        "bench views " + m + " --counts 1,2 --size 32x24 --methods soft:unified,gl:viewport-array",
        "bench shadows " + m + " --lights 1,2 --map-size 64 --methods soft:unified,gl:gs-layered"};
    int ran = 0;
    for (const std::string& args : benches) {
        const auto j = glBenchJson(run(args + timing));
        if (!j) continue;
        ++ran;
        int gl = 0;
        for (const auto& row : (*j)["results"]) {
            ASSERT_FALSE(row.contains("error")) << args << ": " << row.dump();
            gl += expectDeviceTimes(row, 2);
        }
        EXPECT_GT(gl, 0) << args;
        const CliRun table = run(args + " --frames 1 --warmup 0");
        ASSERT_EQ(table.exitCode, 0) << table.err;
        EXPECT_NE(table.out.find("cell: draw / readback / gpu ms"), std::string::npos)
            << args << "\n"
            << table.out;
    }
    if (ran == 0) MVR_SKIP(NoGlContext) << "gl cannot run here";
}

// Soft-only tables have no GPU-timing table; the CSV has the columns, empty for soft rows.
TEST_F(BenchCli, SoftRowsHaveNoDeviceTimes) {
    const std::string m = "'" + model("suzanne.obj") + "'";
    const CliRun table =
        run("bench views " + m +
            " --counts 1 --size 32x24 --frames 1 --warmup 0 --methods soft:unified");
    ASSERT_EQ(table.exitCode, 0) << table.err;
    EXPECT_EQ(table.out.find("draw / readback / gpu"), std::string::npos) << table.out;
    const CliRun csv =
        run("bench views " + m +
            " --counts 1 --size 32x24 --frames 1 --warmup 0 --methods soft:unified --csv");
    ASSERT_EQ(csv.exitCode, 0) << csv.err;
    EXPECT_NE(csv.out.find(",draw_ms,readback_ms,gpu_ms,error"), std::string::npos) << csv.out;
    EXPECT_NE(csv.out.find(",,,\"\""), std::string::npos) << csv.out;
    const nlohmann::json j = runJson("bench views " + m +
                                     " --counts 1 --size 32x24 --frames 1 --warmup 0 "
                                     "--methods soft:unified --json");
    for (const auto& row : j["results"]) EXPECT_FALSE(expectDeviceTimes(row, 1));
}

// The auto backend (--backend auto, auto:auto in --methods): its row says what it picked
// ("ran": BACKEND:METHOD, one of the candidates), with the GPU timings where that is gl; the
// paper benches refuse it like any "auto" method; `mvr render --backend auto` prints the pick
// and the measured times in its note, and --method other than auto is one usage error.
TEST_F(BenchCli, AutoBackendRowsAndRender) {
    const std::string m = "'" + model("suzanne.obj") + "'";
    const nlohmann::json j =
        runJson("bench " + m +
                " --size 64x48 --frames 2 --warmup 1 --methods soft:unified,auto:auto --json");
    ASSERT_EQ(j["results"].size(), 2u) << j.dump();
    const auto& a = j["results"][1];
    EXPECT_EQ(a["backend"], "auto");
    EXPECT_EQ(a["method"], "auto");
    ASSERT_TRUE(a.contains("ran")) << a.dump();
    const std::string ran = a["ran"];
    // Any registered backend may win (soft, gl, vk: whichever measured fastest here), with a
    // real method of it, never "auto".
    EXPECT_TRUE(ran == "soft:unified" ||
                ((ran.rfind("gl:", 0) == 0 || ran.rfind("vk:", 0) == 0) &&
                 ran.substr(3) != "auto" && ran.size() > 3))
        << ran;
    expectDeviceTimes(a, 2);
    expectError("bench sorbier " + m + " --methods auto:auto", 1, "'auto' is not a method");

    const CliRun r = run("render " + m + " --size 64x48 --backend auto -o out");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("auto picked "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("soft:unified "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" ms"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::exists(mDir / "out" / "view-1.png"));
    expectError("render " + m + " --size 64x48 --backend auto --method multipass -o out", 1,
                "backend auto has one method, auto");
    const CliRun info = run("info");
    EXPECT_NE(info.out.find("backend auto:"), std::string::npos) << info.out;
}

TEST_F(BenchCli, BadOptions) {
    const std::string m = "'" + model("suzanne.obj") + "'";
    expectError("bench sorbier " + m + " --methods soft:bogus", 1, "unknown method 'bogus'");
    expectError("bench sorbier " + m + " --methods nope:multipass", 1, "unknown backend 'nope'");
    expectError("bench sorbier " + m + " --methods unified", 1, "BACKEND:METHOD");
    expectError("bench sorbier " + m + " --sizes 0x48", 1, "--sizes '0x48'");
    expectError("bench sorbier " + m + " --copies 0", 1, "--copies 0");
    expectError("bench sorbier " + m + " --shadings glossy", 1, "glossy");
    expectError("bench sorbier " + m + " --frames 0", 1, "--frames 0");
    expectError("bench sorbier " + m + " --plot out.gif", 1, "--plot 'out.gif'");
    expectError("bench sorbier /nonexistent/model.obj --sizes 64x48", 2, "/nonexistent/model.obj");
    expectError("bench kalaiah " + m + " --configs 9", 1, "--configs entry '9'");
    expectError("bench kalaiah " + m + " --configs 12x12", 1, "out of range");
    expectError("bench kalaiah " + m + " --sizes 2x2 --configs 3x1", 1, "too small");
    expectError("bench adelson --only nothing-like-this", 1, "--only");
    expectError("bench adelson --min-batch-ms -1", 1, "--min-batch-ms");
    expectError("bench views " + m + " --counts 0", 1, "--counts entry 0");
    expectError("bench views " + m + " --counts 129", 1, "out of range");
    expectError("bench views " + m + " --grid-views 3", 1, "--grid-views entry '3'");
    expectError("bench views " + m + " --size 0x2", 1, "--size");
    expectError("bench views " + m + " --rounds 0", 1, "--rounds 0 is out of range");
}

// `mvr bench views`: per N, time, × one view and speed-up over the backend's multipass; the
// structure and that the numbers are positive and consistent, not a speed.
void expectViewsJson(const nlohmann::json& j, const std::vector<std::string>& specs) {
    EXPECT_EQ(j["bench"], "views");
    expectMachine(j);
    expectRenderResults(j);
    std::map<std::string, double> oneView;
    int rows = 0;
    for (const auto& r : j["results"]) {
        ASSERT_FALSE(r.contains("error")) << r["method"] << ": " << r["error"];
        const std::string spec =
            r["backend"].get<std::string>() + ":" + r["method"].get<std::string>();
        EXPECT_NE(std::find(specs.begin(), specs.end(), spec), specs.end()) << spec;
        EXPECT_EQ(r["width"], 32);
        EXPECT_EQ(r["height"], 24);
        const int views = r["views"];
        EXPECT_EQ(r["config"], fmt::format("{}x1", views));
        ASSERT_TRUE(r.contains("times_one_view")) << spec;
        const double times = r["times_one_view"];
        EXPECT_GT(times, 0.0);
        if (views == 1) {
            EXPECT_DOUBLE_EQ(times, 1.0) << spec;
            oneView[spec] = r["wall_ms"]["median"];
        } else {
            ASSERT_TRUE(oneView.count(spec)) << spec;  // N = 1 is measured first
            EXPECT_NEAR(times, r["wall_ms"]["median"].get<double>() / oneView[spec], 1e-9 * times);
        }
        EXPECT_GE(r["passes"].get<int>(), 1);
        ++rows;
    }
    EXPECT_EQ(rows, 3 * int(specs.size()));
}

TEST_F(BenchCli, ViewsJsonSoft) {
    // Plain, and with --rounds: the sweep runs that many times and each cell pools every round's
    // frames (the multiples of one view are still time(N) / time(1) of the pooled medians).
    const std::pair<const char*, int> timings[] = {{"--frames 1 --warmup 0", 1},
                                                   {"--frames 2 --warmup 0 --rounds 3", 6}};
    for (const auto& [timing, samples] : timings) {
        const nlohmann::json j =
            runJson(fmt::format("bench views '{}' --counts 1,2,3 --size 32x24 {} "
                                "--methods soft:multipass,soft:unified --json",
                                model("suzanne.obj"), timing));
        expectViewsJson(j, {"soft:multipass", "soft:unified"});
        for (const auto& r : j["results"]) EXPECT_EQ(r["wall_ms"]["n"], samples) << r.dump();
    }
}

// --aa: each count at each sample count, × one sample of the same job, and the path the backend
// took (drawn_samples: RenderStats::samples, N multisampled on gl where the driver takes N, 1
// for soft's sub-pixel passes).
TEST_F(BenchCli, ViewsAaSaysTimesOneSampleAndThePath) {
    const CliRun r =
        run(fmt::format("bench views '{}' --counts 2 --size 32x24 --frames 1 --warmup 0 "
                        "--aa 1,4 --methods soft:unified,gl:multipass --json",
                        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode == 3 ? 3 : 0, r.exitCode) << r.err;
    if (r.exitCode == 3) MVR_SKIP(NoGlContext) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    std::map<std::string, double> oneSample;
    int aaRows = 0;
    for (const auto& row : j["results"]) {
        ASSERT_FALSE(row.contains("error")) << row.dump();
        const std::string spec =
            row["backend"].get<std::string>() + ":" + row["method"].get<std::string>();
        if (!row.contains("samples")) {
            EXPECT_EQ(row["config"], "2x1") << row.dump();
            oneSample[spec] = row["wall_ms"]["median"];
            continue;
        }
        ++aaRows;
        EXPECT_EQ(row["samples"], 4) << row.dump();
        EXPECT_EQ(row["config"], "2x1 aa4") << row.dump();
        ASSERT_TRUE(oneSample.count(spec)) << spec;  // one sample is measured first
        EXPECT_NEAR(row["times_one_sample"].get<double>(),
                    row["wall_ms"]["median"].get<double>() / oneSample[spec], 1e-9);
        const int drawn = row["drawn_samples"];
        if (spec.rfind("soft:", 0) == 0) EXPECT_EQ(drawn, 1) << spec;
        if (spec.rfind("gl:", 0) == 0) EXPECT_TRUE(drawn == 1 || drawn == 4) << spec;
    }
    EXPECT_EQ(aaRows, 3);  // soft:unified, soft:multipass (its baseline), gl:multipass
}

// --rounds in the table's caption and in the progress lines.
TEST_F(BenchCli, ViewsRoundsAreReported) {
    const CliRun table =
        run(fmt::format("bench views '{}' --counts 1,2 --size 32x24 --frames 1 --warmup 0 "
                        "--rounds 2 --methods soft:unified --progress",
                        model("suzanne.obj")));
    ASSERT_EQ(table.exitCode, 0) << table.err;
    EXPECT_NE(table.out.find("2 rounds over the view counts of 1 frames"), std::string::npos)
        << table.out;
    EXPECT_NE(table.err.find("2 views, round 2/2"), std::string::npos) << table.err;
}

// --methods takes one comma-separated list, so a model named after it is the model (it used
// to be swallowed as a method). The triangle count is the file's, counted here from its faces.
TEST_F(BenchCli, ModelNamedAfterMethodsIsTheModel) {
    const std::string path = model("suzanne.obj");
    std::ifstream in(path);
    std::string line;
    long triangles = 0;
    while (std::getline(in, line)) {
        if (line.rfind("f ", 0) != 0) continue;
        std::istringstream words(line.substr(2));
        long corners = 0;
        for (std::string w; words >> w;) ++corners;
        triangles += corners - 2;
    }
    ASSERT_GT(triangles, 0);
    const nlohmann::json j =
        runJson(fmt::format("bench views --counts 2 --size 32x24 --frames 1 --warmup 0 "
                            "--methods soft:multipass,soft:unified '{}' --json",
                            path));
    ASSERT_EQ(j["results"].size(), 2u) << j.dump();
    for (const auto& r : j["results"]) EXPECT_EQ(r["triangles"], triangles) << r.dump();
}

TEST_F(BenchCli, ViewsJsonGlAndPlot) {
    // gl:multipass is added as the baseline of gl:viewport-array; skipped where gl cannot run.
    const CliRun r =
        run(fmt::format("bench views '{}' --counts 1,2,3 --size 32x24 --frames 1 --warmup 0 "
                        "--methods gl:viewport-array --json --plot v.png",
                        model("suzanne.obj")));
    ASSERT_EQ(r.exitCode == 3 ? 3 : 0, r.exitCode) << r.err;
    if (r.exitCode == 3) MVR_SKIP(NoGlContext) << r.err;
    ASSERT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    if (!j["skipped"].empty()) MVR_SKIP(MethodUnsupportedByDriver) << j["skipped"].dump();
    expectViewsJson(j, {"gl:multipass", "gl:viewport-array"});
    EXPECT_TRUE(fs::file_size(mDir / "v.png") > 1000);
}

}  // namespace

namespace {

// `mvr bench outputs` (issue 37) on its tiny configurations: every configuration's row, in the
// table and in the JSON, with times that are there and add up; not a speed.
TEST_F(BenchCli, OutputsTinyTableAndJson) {
    const nlohmann::json j = runJson("bench outputs --tiny --json");
    EXPECT_EQ(j["bench"], "outputs");
    expectMachine(j);
    EXPECT_EQ(j["runs"], 1);
    EXPECT_GE(j["queue"].get<int>(), 0);
    std::vector<std::string> want = {"views", "portrait", "sbs", "portrait-video", "sbs-video"};
    const bool video = j["skipped"].empty();
    if (!video) want.resize(3);  // built without FFmpeg: the videos are listed as skipped
    ASSERT_EQ(j["results"].size(), want.size()) << j.dump(1);
    for (std::size_t i = 0; i < want.size(); ++i) {
        const auto& r = j["results"][i];
        EXPECT_EQ(r["config"], want[i]);
        const bool sequence = i >= 3;
        EXPECT_EQ(r["frames"].get<int>(), sequence ? 2 : 1) << r.dump();
        EXPECT_EQ(r["views"].get<int>(), want[i].rfind("sbs", 0) == 0 ? 2 : 48) << r.dump();
        EXPECT_GT(r["render_ms"].get<double>(), 0.0) << r.dump();
        EXPECT_GT(r["end_to_end_s"].get<double>(), 0.0) << r.dump();
        EXPECT_NEAR(r["fps"].get<double>(),
                    r["frames"].get<double>() / r["end_to_end_s"].get<double>(),
                    1e-2 * r["fps"].get<double>() + 1e-3);
        for (const char* key : {"setup_s", "compose_ms", "encode_ms", "write_ms", "video_ms", "cpu_s"})
            EXPECT_GE(r[key].get<double>(), 0.0) << key << r.dump();
        if (sequence) {
            EXPECT_GT(r["video_ms"].get<double>(), 0.0) << r.dump();
        } else {
            EXPECT_GT(r["encode_ms"].get<double>(), 0.0) << r.dump();
            EXPECT_GE(r["files"].get<int>(), want[i] == "views" ? 48 : 1) << r.dump();
        }
    }
    // The table: a header and one line per configuration, every cell filled.
    const CliRun t = run("bench outputs --tiny --configs sbs,views");
    ASSERT_EQ(t.exitCode, 0) << t.err;
    EXPECT_EQ(t.out.rfind("machine: ", 0), 0u) << t.out;
    EXPECT_NE(t.out.find("| config | views | frames | set-up s | render ms | compose ms | encode ms "
                         "| write ms | video ms | end to end s | frames/s | cpu s |"),
              std::string::npos)
        << t.out;
    for (const char* config : {"views", "sbs"}) {
        const auto at = t.out.find(fmt::format("\n| {} | ", config));
        ASSERT_NE(at, std::string::npos) << config << "\n" << t.out;
        const std::string line = t.out.substr(at + 1, t.out.find('\n', at + 1) - at - 1);
        EXPECT_EQ(std::count(line.begin(), line.end(), '|'), 13) << line;
    }
    EXPECT_LT(t.out.find("| views | "), t.out.find("| sbs | ")) << "in the table's order";
    expectError("bench outputs --configs nope", 1, "--configs nope: unknown");
    expectError("bench outputs --tiny --runs 101", 1, "--runs 101");
    expectError("bench outputs --tiny --frames -1", 1, "--frames -1");
}

}  // namespace
