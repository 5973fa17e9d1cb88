// Issue 44, "all or nothing": bad input gets exactly one `error:` line naming the culprit and a
// non-zero exit, never a hang nor a half-written output directory.
//  - Only regular files are read: a FIFO blocks its reader, /dev/zero and /dev/urandom never
//    end. Each `mvr` run here is wrapped in `timeout 20`, so a regression fails (exit 124)
//    instead of hanging the test run.
//  - Every --format is checked against the views and their size before anything is rendered:
//    the -o directory is left exactly as it was (not even created).
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli_util.h"

namespace mvr {
namespace {

using test::CliRun;

class AllOrNothing : public ::testing::Test {
protected:
    void SetUp() override {
        MVR_REQUIRE_MVR_BINARY(test::mvrBinary());
        std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        std::replace(name.begin(), name.end(), '/', '_');
        mDir = std::filesystem::temp_directory_path() /
               fmt::format("mvr-all-or-nothing-{}-{}", ::getpid(), name);
        std::filesystem::remove_all(mDir);
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override { std::filesystem::remove_all(mDir); }

    /// `mvr ARGS` in the test's directory, killed after 20 s (exit 124) should it hang.
    CliRun run(const std::string& args) const { return test::runMvr(mDir, args, "timeout 20 "); }

    /// Exit `code` (any non-zero one when 0), and on stderr one error line, "error: ...", holding
    /// every one of `needles` (and nothing else but a usage hint).
    static void expectOneError(const CliRun& r, const std::string& args, int code,
                               std::initializer_list<std::string> needles) {
        EXPECT_NE(r.exitCode, 124) << args << ": timed out (a hang)";
        if (code != 0) {
            EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        } else {
            EXPECT_NE(r.exitCode, 0) << args << "\n" << r.err;
        }
        EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << args << ": " << r.err;
        // The error, and for an option's value CLI11 refuses, the usage hint after it.
        const std::string rest = r.err.substr(std::min(r.err.size(), r.err.find('\n') + 1));
        EXPECT_TRUE(rest.empty() || rest.rfind("run `mvr --help`", 0) == 0)
            << args << ": " << r.err;
        EXPECT_LE(std::count(r.err.begin(), r.err.end(), '\n'), 2) << args << ": " << r.err;
        for (const std::string& needle : needles)
            EXPECT_NE(r.err.find(needle), std::string::npos)
                << args << ": no '" << needle << "' in: " << r.err;
    }

    void mkfifo(const std::string& name) const {
        ASSERT_EQ(::mkfifo((mDir / name).c_str(), 0600), 0) << name;
    }
    void symlink(const std::string& target, const std::string& name) const {
        std::filesystem::create_symlink(target, mDir / name);
    }
    void write(const std::string& name, const std::string& bytes) const {
        std::ofstream(mDir / name, std::ios::binary) << bytes;
    }
    /// The names in a directory of the test's (empty when there is none).
    std::set<std::string> listing(const std::string& name) const {
        std::set<std::string> names;
        std::error_code ec;
        for (const auto& e : std::filesystem::directory_iterator(mDir / name, ec))
            names.insert(e.path().filename().string());
        return names;
    }

    /// A one-triangle glTF 2.0 whose one buffer is the external file `bin`.
    void writeGltf(const std::string& name, const std::string& bin) const {
        write(name, fmt::format(R"({{
  "asset": {{"version": "2.0"}},
  "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "buffers": [{{"uri": "{}", "byteLength": 36}}]
}})",
                                bin));
    }

    std::filesystem::path mDir;
};

// ---- A: only regular files are read -------------------------------------------------------------

TEST_F(AllOrNothing, ComposeRefusesAFifoInput) {
    mkfifo("fifo.png");
    const std::string args = "compose fifo.png fifo.png -o out.png";
    const CliRun r = run(args);
    expectOneError(r, args, 0, {"fifo.png", "not a regular file"});
    EXPECT_FALSE(std::filesystem::exists(mDir / "out.png"));
}

TEST_F(AllOrNothing, ComposeRefusesDevicesBehindSymlinks) {
    symlink("/dev/zero", "z.png");
    symlink("/dev/urandom", "u.jpg");
    symlink("/dev/zero", "z.mpo");
    for (const std::string args : {"compose z.png z.png -o out.png",
                                   "compose u.jpg u.jpg -o out.png", "compose z.mpo -o out.png"}) {
        const CliRun r = run(args);
        const std::string culprit = args.substr(8, args.find(' ', 8) - 8);
        expectOneError(r, args, 0, {culprit, "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out.png")) << args;
    }
}

TEST_F(AllOrNothing, ComposeRefusesADirectoryInput) {
    std::filesystem::create_directories(mDir / "views.png");
    const std::string args = "compose views.png views.png -o out.png";
    expectOneError(run(args), args, 0, {"views.png", "not a regular file"});
}

TEST_F(AllOrNothing, GltfBufferThatIsAFifoOrADeviceIsRefused) {
    mkfifo("fifo.bin");
    writeGltf("fifo.gltf", "fifo.bin");
    symlink("/dev/zero", "zero.bin");
    writeGltf("zero.gltf", "zero.bin");
    for (const std::string model : {"fifo", "zero"}) {
        const std::string args = fmt::format("render {}.gltf --size 16x12 -o out", model);
        const CliRun r = run(args);
        expectOneError(r, args, 2, {model + ".bin", "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }
}

TEST_F(AllOrNothing, OtherInputFilesThatAreFifosAreRefused) {
    mkfifo("fifo");
    symlink("/dev/zero", "zero.json");
    struct Case {
        std::string option, file;
    };
    const Case cases[] = {
        {"--sky fifo", "fifo"},
        {"--camera-path fifo", "fifo"},
        {"--camera-path zero.json", "zero.json"},
        {"--camera-matrix fifo", "fifo"},
        {"--lenticular-calibration fifo --format lenticular", "fifo"},
        {"--lenticular-calibration zero.json --format lenticular", "zero.json"},
    };
    for (const Case& c : cases) {
        std::filesystem::remove_all(mDir / "out");
        const std::string args = "render --size 16x12 -o out " + c.option;
        expectOneError(run(args), args, 0, {c.file, "not a regular file"});
        EXPECT_FALSE(std::filesystem::exists(mDir / "out")) << args;
    }
}

// ---- B: formats are checked before anything is written ------------------------------------------

TEST_F(AllOrNothing, AFormatTheViewsCannotMakeWritesNothing) {
    struct Case {
        std::string args, format, why;
    };
    const Case cases[] = {
        {"--size 64x48 --views 4 --format jps", "jps", "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format sbs", "sbs", "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format anaglyph-dubois", "anaglyph-dubois",
         "needs 2 views (got 4)"},
        {"--size 64x48 --views 4 --format anaglyph-dubois-gm", "anaglyph-dubois-gm",
         "needs 2 views (got 4)"},
        {"--size 64x48 --format hdmi-frame-packing", "hdmi-frame-packing",
         "no HDMI 1.4a frame packing"},
        {"--size 63x48 --format sbs-half", "sbs-half", "odd"},
        {"--size 64x48 --views 4 --format sbs --frames 1", "sbs", "needs 2 views (got 4)"},
        {"--size 64x48 --views 1 --format mpo", "mpo", "views (got 1)"},
    };
    for (const Case& c : cases) {
        for (const bool existed : {false, true}) {
            std::filesystem::remove_all(mDir / "o");
            if (existed) {
                std::filesystem::create_directories(mDir / "o");
                write("o/keep.txt", "kept");
            }
            const std::string args = "render " + c.args + " -o o";
            const CliRun r = run(args);
            expectOneError(r, args, 1, {"--format " + c.format, c.why});
            if (existed) {
                EXPECT_EQ(listing("o"), std::set<std::string>{"keep.txt"}) << args;
                EXPECT_EQ(test::slurp(mDir / "o" / "keep.txt"), "kept") << args;
            } else {
                EXPECT_FALSE(std::filesystem::exists(mDir / "o")) << args;
            }
        }
    }
}

// ---- C: nonsense refused, with the code the README's table gives (docs/errors.md) ---------------

/// A one-triangle glTF 2.0 (a data URI buffer) whose node 0 has `node` added and whose document
/// has `extra` (",\"cameras\": [...]" etc.) added at the top level.
std::string gltfWith(const std::string& node, const std::string& extra = {}) {
    return fmt::format(R"({{
  "asset": {{"version": "2.0"}},
  "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0{}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "buffers": [{{"uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA",
               "byteLength": 36}}]{}
}})",
                       node, extra);
}

TEST_F(AllOrNothing, NonsenseOptionsAreUsageErrorsNamingTheOptionAndValue) {
    write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    struct Case {
        std::string args;
        std::vector<std::string> needles;
    };
    const Case cases[] = {
        {"render --frames 0", {"--frames: 0 is out of range", "1..1000000"}},
        {"render --frames 2.5", {"--frames: '2.5' is not a whole number"}},
        {"render --display ''", {"--display: '' is empty", "mvr info --displays"}},
        {"render --method ''", {"--method: '' is empty"}},
        // Any other option given an empty value (an unset shell variable), and an orbit no
        // frame count can follow.
        {"render --orbit ''", {"--orbit '': expected a value"}},
        {"render --camera-position ''", {"--camera-position '': expected a value"}},
        {"render --write ''", {"--write '': expected a value"}},
        {"render --sky ''", {"--sky '': expected a value"}},
        {"render --frames 2 --video ''", {"--video '': expected a value"}},
        {"render --orbit 1e30", {"--orbit 1e+30", "at most 360000 degrees"}},
        {"render --threads -1 --frames 1", {"--threads: -1 is out of range", "0..1024"}},
        {"render --threads 5000 --frames 1", {"--threads: 5000 is out of range", "0..1024"}},
        {"render --label 'hi@2,0.5'", {"--label 'hi@2,0.5'", "outside the view", "0..1"}},
        {"render --label 'hi@0.5,-0.1'", {"--label 'hi@0.5,-0.1'", "outside the view"}},
        {"render --label-anchor 'hi@1e30,0,0'", {"--label-anchor 'hi@1e30,0,0'", "1e12"}},
        {"render --format jps --jpeg-quality 0", {"--jpeg-quality: 0 is out of range", "1..100"}},
        {"compose a.png b.png -o o.png --format lenticular --lenticular-pitch 1e30",
         {"--lenticular-pitch: 1e30 is out of range", "must be > 0 and at most 10000"}},
        {"compose a.png b.png -o o.png --format lenticular --lenticular-pitch 0",
         {"--lenticular-pitch: 0 is out of range", "must be > 0"}},
        {"compose a.png b.png -o o.png --format lenticular --lenticular-center 1e30",
         {"--lenticular-center: 1e30 is out of range", "-1000000..1000000"}},
        {"compose a.png b.png -o o.png --format lenticular --lenticular-dpi 1e30",
         {"--lenticular-dpi: 1e30 is out of range", "at most 10000"}},
        {"compose a.png b.png -o o.png --format lenticular --lenticular-slope 0",
         {"--lenticular-slope: 0 is out of range", "non-zero"}},
        {"compose a.png b.png -o o.png --format mpo --baseline 1e30",
         {"--baseline: 1e30 is out of range", "0..1000000"}},
        {"render tri.obj@1e30,0,0", {"tri.obj@1e30,0,0", "X = 1e+30 out of range",
                                     "|X|, |Y|, |Z| at most 1e+06", "SCALE 1e-06..1e+06"}},
        {"render tri.obj@0,0,0,1e30", {"SCALE = 1e+30 out of range"}},
        {"render tri.obj@0,0,0,1,1000", {"YAW = 1000 out of range", "|YAW| at most 360"}},
        {"render --format quilt --views 4 --quilt 9x", {"--quilt '9x'", "expected CxR"}},
    };
    for (const Case& c : cases) {
        std::filesystem::remove_all(mDir / "o");
        const std::string args = c.args + (c.args.find(" -o ") == std::string::npos
                                               ? " --size 16x12 -o o" : "");
        const CliRun r = run(args);
        expectOneError(r, args, 1, {});
        for (const std::string& needle : c.needles)
            EXPECT_NE(r.err.find(needle), std::string::npos)
                << args << ": no '" << needle << "' in: " << r.err;
        // Readable: a bound is never the largest double in full, the option named once.
        EXPECT_LT(r.err.find('\n'), 240u) << args << ": " << r.err;
        EXPECT_EQ(r.err.find("0000000000"), std::string::npos) << args << ": " << r.err;
        const std::string option = r.err.substr(7, r.err.find_first_of(": '", 7) - 7);
        if (option.rfind("--", 0) == 0) {
            std::size_t n = 0;
            for (std::size_t at = r.err.find(option + " "); at != std::string::npos;
                 at = r.err.find(option + " ", at + 1))
                ++n;
            for (std::size_t at = r.err.find(option + ":"); at != std::string::npos;
                 at = r.err.find(option + ":", at + 1))
                ++n;
            EXPECT_LE(n, 1u) << args << ": the option is named more than once: " << r.err;
        }
        EXPECT_FALSE(std::filesystem::exists(mDir / "o")) << args;
        EXPECT_FALSE(std::filesystem::exists(mDir / "o.png")) << args;
    }
}

TEST_F(AllOrNothing, AFilesFaultIsExit2NamingTheFileAndThePlace) {
    write("big.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n");
    write("big.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0\n0 1e30 0\n1 0 0\n3 0 1 2\n");
    write("bad-pitch.json", R"({"pitch": "x", "slope": -5.4, "center": 0.1, "DPI": 324})");
    write("huge-pitch.json", R"({"pitch": 1e30, "slope": -5.4, "center": 0.1, "DPI": 324})");
    write("cut.json", R"({"pitch": 52.5, "slope": -5.4)");
    write("abc.gltf", gltfWith(R"(, "translation": ["abc", 0, 0])"));
    write("short.gltf", gltfWith(R"(, "translation": [0, 0])"));
    write("rot.gltf", gltfWith(R"(, "rotation": [0, 0, 0, 1e39])"));
    write("scale.gltf", gltfWith(R"(, "scale": {"x": 1})"));
    write("matrix.gltf", gltfWith(R"(, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0])"));
    write("cam.gltf", gltfWith(R"(, "camera": 0)",
                               R"(, "cameras": [{"type": "perspective",
                                   "perspective": {"yfov": "wide", "znear": 0.1}}])"));
    write("light.gltf",
          gltfWith("", R"(, "extensions": {"KHR_lights_punctual": {"lights": [
                             {"type": "point", "color": [1, 1]}]}})"));
    write("spot.gltf",
          gltfWith("", R"(, "extensions": {"KHR_lights_punctual": {"lights": [
                             {"type": "spot", "spot": {"outerConeAngle": 3}}]}})"));
    write("mat.gltf", gltfWith("", R"(, "materials": [{"pbrMetallicRoughness":
                                        {"baseColorFactor": [1, 1, "red", 1]}}])"));
    write("emit.gltf", gltfWith("", R"(, "materials": [{"emissiveFactor": [1, 1, null]}])"));
    write("rough.gltf", gltfWith("", R"(, "materials": [{"pbrMetallicRoughness":
                                        {"roughnessFactor": 7}}])"));
    write("cutoff.gltf", gltfWith("", R"(, "materials": [{"alphaCutoff": "half"}])"));
    write("sampler.gltf", gltfWith("", R"(, "samplers": [{"wrapS": 5}])"));
    write("textx.gltf", gltfWith("", R"(, "materials": [{"name": "Wood", "pbrMetallicRoughness":
                                         {"baseColorTexture": {"index": 0, "extensions":
                                         {"KHR_texture_transform": {"offset": [1e39, 0]}}}}}])"));
    write("texset.gltf", gltfWith("", R"(, "materials": [{"name": "Wood",
                                          "normalTexture": {"index": 0, "texCoord": 2}}])"));
    struct Case {
        std::string args;
        std::vector<std::string> needles;
    };
    const Case cases[] = {
        {"render big.obj", {"big.obj", "line 2", "vertex 2", "1e+30", "at most 1e+12"}},
        {"render big.ply", {"big.ply", "vertex 1", "1e+30", "at most 1e+12"}},
        {"render --lenticular-calibration bad-pitch.json --format lenticular --views 4",
         {"bad-pitch.json", "\"pitch\"", "not a number"}},
        {"render --lenticular-calibration huge-pitch.json --format lenticular --views 4",
         {"huge-pitch.json", "pitch 1e+30 is out of range", "at most 10000"}},
        {"render --lenticular-calibration cut.json --format lenticular --views 4",
         {"cut.json", "not a complete JSON object"}},
        {"render abc.gltf", {"abc.gltf", "nodes[0].translation", "expected 3 numbers",
                             R"(["abc",0,0])"}},
        {"render short.gltf", {"short.gltf", "nodes[0].translation", "expected 3 numbers",
                               "[0,0]"}},
        {"render rot.gltf", {"rot.gltf", "nodes[0].rotation", "expected 4 numbers"}},
        {"render scale.gltf", {"scale.gltf", "nodes[0].scale", "expected 3 numbers"}},
        {"render matrix.gltf", {"matrix.gltf", "nodes[0].matrix", "expected 16 numbers"}},
        {"render cam.gltf", {"cam.gltf", "cameras[0].perspective.yfov", "expected a number"}},
        {"render light.gltf",
         {"light.gltf", "KHR_lights_punctual.lights[0].color", "expected 3 numbers"}},
        {"render spot.gltf",
         {"spot.gltf", "lights[0].spot.outerConeAngle", "3 is out of range"}},
        {"render mat.gltf", {"mat.gltf", "materials[0].pbrMetallicRoughness.baseColorFactor",
                             "expected 4 numbers"}},
        {"render emit.gltf", {"emit.gltf", "materials[0].emissiveFactor", "expected 3 numbers"}},
        {"render rough.gltf",
         {"rough.gltf", "pbrMetallicRoughness.roughnessFactor", "7 is out of range"}},
        {"render cutoff.gltf", {"cutoff.gltf", "materials[0].alphaCutoff", "expected a number"}},
        {"render sampler.gltf", {"sampler.gltf", "samplers[0].wrapS", "not one of glTF's values"}},
        {"render textx.gltf",
         {"textx.gltf", "material 'Wood' (materials[0])",
          "baseColorTexture.extensions.KHR_texture_transform.offset",
          "expected 2 finite numbers, got [1e+39,0]"}},
        {"render texset.gltf",
         {"texset.gltf", "material 'Wood' (materials[0]): normalTexture.texCoord",
          "2 is not a texture coordinate set mvr reads (0 or 1)"}},
    };
    for (const Case& c : cases) {
        std::filesystem::remove_all(mDir / "o");
        const std::string args = c.args + " --size 16x12 -o o";
        const CliRun r = run(args);
        expectOneError(r, args, 2, {});
        for (const std::string& needle : c.needles)
            EXPECT_NE(r.err.find(needle), std::string::npos)
                << args << ": no '" << needle << "' in: " << r.err;
        EXPECT_FALSE(std::filesystem::exists(mDir / "o")) << args;
    }
    // The same glTF with good values renders (the check refuses only what is wrong).
    write("good.gltf", gltfWith(R"(, "translation": [0, 0, 1], "rotation": [0, 0, 0, 1])",
                                R"(, "samplers": [{"wrapS": 33071, "magFilter": 9729}])"));
    const CliRun ok = run("render good.gltf --size 16x12 -o o");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
}

}  // namespace
}  // namespace mvr
