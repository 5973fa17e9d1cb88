// One recipe rendered three ways — through the library (session::renderStill: prepare(), the
// registry's first backend, writeOutputs()), through `mvr render` and through Python's mvr.render() (when
// the module is built) — gives the same files, byte for byte: views, depth, the anaglyph,
// composites and the comfort report's JSON.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "cli_util.h"
#include "mvr/session/recipe.h"
#include "mvr/session/render.h"

namespace mvr::session {
namespace {

namespace fs = std::filesystem;

/// The recipe of the test, as the three callers spell it.
RenderRecipe recipe(const fs::path& dir) {
    RenderRecipe r;
    r.views = 2;
    r.size = "64x48";
    r.shading = "pixel";
    r.convergenceAuto = true;
    r.surfaces.sky = "gradient";
    r.surfaces.labels = {"HI@0.5,0.4"};
    r.outputs.directory = dir.string();
    r.outputs.depth = true;
    r.outputs.formats = {"sbs", "jps"};
    r.outputs.reportJson = (dir / "report.json").string();
    return r;
}
const char* kCliArgs =
    "render --views 2 --size 64x48 --shading pixel --convergence auto --sky gradient "
    "--label HI@0.5,0.4 --depth --format sbs --format jps -q -o cli --report-json "
    "cli/report.json";
const char* kPython =
    "import mvr; mvr.render(views=2, size=(64, 48), shading='pixel', convergence='auto', "
    "sky='gradient', label='HI@0.5,0.4', depth=True, format=['sbs', 'jps'], output='py', "
    "report_json='py/report.json')";

std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
}

void expectSameFiles(const fs::path& a, const fs::path& b) {
    ASSERT_EQ(listing(a), listing(b)) << a << " vs " << b;
    for (const std::string& name : listing(a))
        EXPECT_EQ(test::slurp(a / name), test::slurp(b / name)) << name << ": " << a << " vs " << b;
}

TEST(SessionSameFiles, LibraryCliAndPythonWriteTheSameBytes) {
    const fs::path dir = fs::path(testing::TempDir()) / "mvr_session_same_files";
    fs::remove_all(dir);
    fs::create_directories(dir / "lib");
    auto still = renderStill(recipe(dir / "lib"));  // `mvr render` in one library call
    ASSERT_TRUE(still) << still.status().message();
    EXPECT_EQ(still->files.size(), 8u);
    EXPECT_EQ(still->prepared.notes.size(), 1u);  // what --convergence auto chose

    const test::CliRun cli = test::runMvr(dir, kCliArgs);
    ASSERT_EQ(cli.exitCode, 0) << cli.err;
    expectSameFiles(dir / "lib", dir / "cli");
    EXPECT_EQ(listing(dir / "cli"),
              (std::vector<std::string>{"anaglyph.png", "depth-0.png", "depth-1.png", "jps.jps",
                                        "report.json", "sbs.png", "view-0.png", "view-1.png"}));

#ifdef MVR_TEST_PYTHON
    const std::string cmd = fmt::format("cd '{}' && PYTHONPATH='{}' '{}' -c \"{}\" 2>py.err",
                                        dir.string(), MVR_TEST_PYTHON_DIR, MVR_TEST_PYTHON,
                                        kPython);
    ASSERT_EQ(std::system(cmd.c_str()), 0) << test::slurp(dir / "py.err");
    expectSameFiles(dir / "lib", dir / "py");
#else
    GTEST_LOG_(INFO) << "no Python module in this build: library and CLI only";
#endif
    fs::remove_all(dir);
}

TEST(SessionRenderStill, RefusesASequenceAndReportsTheBackend) {
    RenderRecipe r;
    r.size = "16x12";
    r.sequence.frames = 3;
    auto refused = renderStill(r);
    ASSERT_FALSE(refused);
    EXPECT_EQ(refused.status().code(), ErrorCode::Usage);
    r.sequence.frames = 0;
    r.backend = "nope";
    auto bad = renderStill(r);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().message().rfind("--backend nope: ", 0), 0u) << bad.status().message();
    r.backend.clear();
    auto ok = renderStill(r);
    ASSERT_TRUE(ok) << ok.status().message();
    EXPECT_EQ(ok->output.color.size(), 2u);
    EXPECT_TRUE(ok->files.empty());
    ASSERT_TRUE(ok->comfort);
}

}  // namespace
}  // namespace mvr::session
