// Goldens: soft:multipass views of a few scenes, framed as `mvr render` frames them
// (mvr::frameScene), against the PNGs under tests/golden/<case>/view-N.png — the files that
// `mvr render` writes for the case (renderArgs(); GoldenCli checks it; README.md lists them).
//
// Exact, byte for byte (alpha included), and that is the right bound: the soft backend
// rasterizes with exact int64 edge functions on 1/256-pixel snapped vertices and shades in a
// fixed order of float operations built without contraction (-ffp-contract=off), so neither the
// SIMD path (tests/raster check AVX2 / AVX-512 == scalar bit for bit; this test renders the
// scalar path too) nor the number of threads nor the CPU changes a pixel, and soft:unified
// equals soft:multipass bit for bit. Any difference is a change of behaviour to look at, not
// noise. (What could legitimately move a pixel is another compiler or libm computing the
// scene's or camera's sin / cos / tan differently; then regenerate and review the images.)
//
// On a mismatch the test prints the largest and mean channel delta, the number of differing
// pixels and the worst one, and writes the actual view and a diff image into the build tree
// (tests/golden/actual/<case>/<variant>/ and …/diff/…), printing their paths.
// MVR_UPDATE_GOLDENS=1 rewrites the expected images from soft:multipass instead (review them
// like code before committing).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/core/framing.h"
#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/core/scene.h"
#include "mvr/io/mesh_io.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

namespace fs = std::filesystem;

fs::path sharedModels() {
    const char* dir = std::getenv("MVR_SHARED_DIR");
    return fs::path(dir ? dir : MVR_TEST_SHARED_DIR) / "models";
}

bool updating() {
    const char* u = std::getenv("MVR_UPDATE_GOLDENS");
    return u && std::string(u) == "1";
}

/// One golden: a scene, a view grid, a shading and a size.
struct GoldenCase {
    const char* name;   ///< folder under tests/golden
    const char* model;  ///< file in shared/models; "" = the procedural default scene
    int columns, rows;
    Shading shading;
    int width, height;
};

const GoldenCase kCases[] = {
    {"default-stereo", "", 2, 1, Shading::Vertex, 160, 120},
    {"bunny-stereo", "stanford-bunny.obj", 2, 1, Shading::Vertex, 160, 120},
    {"default-3x3", "", 3, 3, Shading::Pixel, 128, 96},
};

/// The arguments of the `mvr render` call that writes the case's view-N.png.
std::string renderArgs(const GoldenCase& g, const std::string& models) {
    std::string args = "render";
    if (*g.model != '\0') args += " " + models + "/" + g.model;
    args += g.rows > 1 ? fmt::format(" --view-grid {}x{}", g.columns, g.rows)
                       : (g.columns != 2 ? fmt::format(" --views {}", g.columns) : "");
    args += fmt::format(" --size {}x{}", g.width, g.height);
    if (g.shading != Shading::Vertex) args += std::string(" --shading ") + shadingName(g.shading);
    return args;
}

/// How the views are rendered; every variant must give the same bytes.
struct Variant {
    const char* name;
    const char* method;
    const char* simd;
    int threads;
};

const Variant kVariants[] = {
    {"multipass", "multipass", "auto", 0},           // the reference; MVR_UPDATE_GOLDENS writes it
    {"multipass-scalar", "multipass", "scalar", 1},  // the scalar path on one thread
    {"unified", "unified", "auto", 0},
};

struct Param {
    const GoldenCase* golden;
    const Variant* variant;
};

void PrintTo(const Param& p, std::ostream* os) { *os << p.golden->name << " " << p.variant->name; }

std::string paramName(const testing::TestParamInfo<Param>& i) {
    std::string s = std::string(i.param.golden->name) + "__" + i.param.variant->name;
    std::replace(s.begin(), s.end(), '-', '_');
    return s;
}

std::vector<Param> allParams() {
    std::vector<Param> out;
    for (const GoldenCase& g : kCases) {
        for (const Variant& v : kVariants) out.push_back({&g, &v});
    }
    return out;
}

/// Where a view's diff shows: differing pixels red (brighter for larger deltas), equal ones
/// the expected image at a quarter of its brightness.
Image diffImage(const Image& expected, const Image& actual) {
    Image out(actual.width, actual.height);
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const Rgba8 a = actual.at(x, y);
            if (x >= expected.width || y >= expected.height) {
                out.set(x, y, {255, 0, 255, 255});
                continue;
            }
            const Rgba8 e = expected.at(x, y);
            const int delta = std::max({std::abs(a.r - e.r), std::abs(a.g - e.g),
                                        std::abs(a.b - e.b), std::abs(a.a - e.a)});
            if (delta == 0) {
                out.set(x, y,
                        {std::uint8_t(e.r / 4), std::uint8_t(e.g / 4), std::uint8_t(e.b / 4), 255});
            } else {
                out.set(x, y, {std::uint8_t(std::min(255, 128 + 8 * delta)), 0, 0, 255});
            }
        }
    }
    return out;
}

/// Compares one view exactly with `expected` (read from `expectedPath`, or its error); on a
/// mismatch writes the actual view and the diff into the build tree and prints where.
void expectSame(const GoldenCase& g, const Variant& variant, int view, const Image& actual,
                const Result<Image>& expected, const fs::path& expectedPath) {
    const std::string file = fmt::format("view-{}.png", view);
    const fs::path outDir = fs::path(MVR_TEST_BINARY_DIR) / "tests" / "golden";
    const fs::path actualPath = outDir / "actual" / g.name / variant.name / file;
    const fs::path diffPath = outDir / "diff" / g.name / variant.name / file;
    const bool same = expected && expected->width == actual.width &&
                      expected->height == actual.height && expected->rgba == actual.rgba;
    if (same) return;

    fs::create_directories(actualPath.parent_path());
    const Status wrote = writePng(actualPath, actual);
    if (!expected) {
        ADD_FAILURE() << expected.status().message()
                      << " (MVR_UPDATE_GOLDENS=1 writes it); actual: "
                      << (wrote ? actualPath.string() : wrote.message());
        return;
    }
    fs::create_directories(diffPath.parent_path());
    const Status wroteDiff = writePng(diffPath, diffImage(*expected, actual));
    const ImageDiff d = compareImages(*expected, actual, 0);
    long alphaOnly = 0;
    if (expected->rgba.size() == actual.rgba.size()) {
        for (std::size_t i = 3; i < actual.rgba.size(); i += 4) {
            alphaOnly += expected->rgba[i] != actual.rgba[i];
        }
    }
    ADD_FAILURE() << g.name << " " << variant.name << " view " << view << " differs from "
                  << expectedPath.string() << ": " << expected->width << "x" << expected->height
                  << " expected, " << actual.width << "x" << actual.height
                  << " rendered; max delta " << d.maxDelta << ", mean delta " << d.meanDelta << ", "
                  << d.differingPixels << " pixels differ in RGB (" << alphaOnly
                  << " in alpha), worst at (" << d.worstX << ", " << d.worstY
                  << ")\n  actual: " << (wrote ? actualPath.string() : wrote.message())
                  << "\n  diff:   " << (wroteDiff ? diffPath.string() : wroteDiff.message());
}

fs::path goldenPath(const GoldenCase& g, int view) {
    return fs::path(MVR_TEST_GOLDEN_DIR) / g.name / fmt::format("view-{}.png", view);
}

/// Frames the case as `mvr render` does and renders it with the variant.
Result<RenderOutput> renderCase(const GoldenCase& g, const Scene& scene, const Variant& variant) {
    FramingParams params;
    params.columns = g.columns;
    params.rows = g.rows;
    RenderSettings settings;
    settings.width = g.width;
    settings.height = g.height;
    settings.shading = g.shading;
    auto request = frameScene(scene, params, settings);
    if (!request) return request.status();
    auto backend = makeBackend("soft", {.threads = variant.threads, .simd = variant.simd});
    if (!backend) return backend.status();
    return (*backend)->render(scene, request->rig, request->settings, variant.method);
}

class Golden : public testing::TestWithParam<Param> {};

TEST_P(Golden, MatchesReferenceImages) {
    const GoldenCase& g = *GetParam().golden;
    const Variant& variant = *GetParam().variant;
    Scene scene;
    if (*g.model == '\0') {
        scene = makeDefaultScene();
    } else {
        auto mesh = loadMesh(sharedModels() / g.model);
        if (!mesh) MVR_SKIP(ModelsMissing) << mesh.status().message() << " (set MVR_SHARED_DIR)";
        std::vector<Mesh> meshes;
        meshes.push_back(std::move(mesh).value());
        scene = makeGridScene(std::move(meshes), 1);  // as `mvr render MODEL` lays it out
    }
    auto out = renderCase(g, scene, variant);
    ASSERT_TRUE(out) << out.status().message();
    const int views = g.columns * g.rows;
    ASSERT_EQ(out->color.size(), static_cast<std::size_t>(views));
    const bool reference = &variant == &kVariants[0];
    if (updating() && reference) {
        for (int v = 0; v < views; ++v) {
            const fs::path path = goldenPath(g, v);
            fs::create_directories(path.parent_path());
            const Status s = writePng(path, out->color[static_cast<std::size_t>(v)]);
            ASSERT_TRUE(s) << s.message();
            std::printf("[ updated  ] %s\n", path.string().c_str());
        }
        return;
    }
    // While the goldens are rewritten (possibly by a test running in parallel), the other
    // variants compare with the reference variant rendered here rather than with the files.
    std::optional<RenderOutput> fresh;
    if (updating()) {
        auto r = renderCase(g, scene, kVariants[0]);
        ASSERT_TRUE(r) << r.status().message();
        fresh = std::move(r).value();
    }
    for (int v = 0; v < views; ++v) {
        const auto i = static_cast<std::size_t>(v);
        const fs::path path = goldenPath(g, v);
        expectSame(g, variant, v, out->color[i],
                   fresh ? Result<Image>(fresh->color[i]) : readPng(path),
                   fresh ? fs::path(std::string(kVariants[0].name) + " rendered now") : path);
    }
}

INSTANTIATE_TEST_SUITE_P(Soft, Golden, testing::ValuesIn(allParams()), paramName);

// The goldens are what `mvr render` writes: the built mvr, run with each case's arguments,
// writes the same view-N.png pixels.
TEST(GoldenCli, MvrRenderWritesTheGoldens) {
    const fs::path mvr = ::mvr::test::mvrBinary();
    if (!fs::exists(mvr)) FAIL() << mvr << " is not built";
    if (updating()) MVR_SKIP(NotApplicable) << "MVR_UPDATE_GOLDENS=1: the goldens are being rewritten";
    const Variant cli{"mvr-render", "", "", 0};
    for (const GoldenCase& g : kCases) {
        if (*g.model != '\0' && !fs::exists(sharedModels() / g.model)) continue;
        const fs::path dir = fs::path(MVR_TEST_BINARY_DIR) / "tests" / "golden" / "cli" / g.name;
        fs::remove_all(dir);
        const std::string cmd = fmt::format("'{}' {} -q -o '{}'", mvr.string(),
                                            renderArgs(g, sharedModels().string()), dir.string());
        ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
        for (int v = 0; v < g.columns * g.rows; ++v) {
            auto written = readPng(dir / fmt::format("view-{}.png", v));
            ASSERT_TRUE(written) << written.status().message();
            expectSame(g, cli, v, *written, readPng(goldenPath(g, v)), goldenPath(g, v));
        }
    }
}

}  // namespace
}  // namespace mvr
