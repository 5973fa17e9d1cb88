// A format added by one row (composite::registerFormat()): the library composes and writes
// it, the gl backend's compose hook leaves it to the CPU (it has no GPU plan, so `--backend gl`
// does not fail on it), a render's session writes it on both backends and the viewer's format
// list shows it.
#include <algorithm>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/io/png.h"
#include "mvr/session/render.h"
#include "mvr_test_support.h"
#include "viewer.h"

namespace mvr {
namespace {

// "test-left": the left view as it is (a CPU-only composer, one cell, 2 views).
Result<Image> composeLeft(std::span<const Image> views, const composite::ComposeOptions&,
                          const std::string&) {
    return views[0];
}

void registerTestFormat() {
    composite::FormatInfo row{"test-left", 2, 2, false, ".png", "test: the left view",
                              composite::FormatSize{}};
    row.composer = composeLeft;
    const Status s = composite::registerFormat(row);
    ASSERT_TRUE(s || s.message().find("taken") != std::string::npos) << s.message();
}

std::vector<Image> pair() {
    Image left(4, 3), right(4, 3);
    for (std::size_t i = 0; i < left.rgba.size(); ++i) {
        left.rgba[i] = std::uint8_t(i);
        right.rgba[i] = std::uint8_t(255 - i);
    }
    return {left, right};
}

TEST(RegisteredFormat, ComposesAndWritesThroughTheLibrary) {
    registerTestFormat();
    const std::vector<std::string> names = composite::formatNames();
    EXPECT_EQ(names.back(), "test-left");
    const std::vector<Image> views = pair();
    Result<Image> image = composite::compose("test-left", views);
    ASSERT_TRUE(image) << image.status().message();
    EXPECT_EQ(image->rgba, views[0].rgba);
    composite::ComposeOptions swapped;
    swapped.swapEyes = true;
    image = composite::compose("test-left", views, swapped);
    ASSERT_TRUE(image);
    EXPECT_EQ(image->rgba, views[1].rgba);
    // compose()'s own checks come from the row.
    EXPECT_FALSE(composite::compose("test-left", std::span(views).first(1)));
    Result<composite::Size> size = composite::outputSize("test-left", 2, 4, 3);
    ASSERT_TRUE(size);
    EXPECT_EQ(*size, (composite::Size{4, 3}));
    const auto dir = std::filesystem::temp_directory_path() / "mvr_registered_format_test";
    std::filesystem::create_directories(dir);
    Result<std::filesystem::path> path = composite::writeComposite("test-left", views, {}, dir);
    ASSERT_TRUE(path) << path.status().message();
    EXPECT_EQ(path->filename(), "test-left.png");
    std::filesystem::remove_all(dir);
}

TEST(RegisteredFormat, RowsThatCannotWorkAreRefused) {
    registerTestFormat();
    composite::FormatInfo row{"test-bad", 2, 2, false, ".png", "no composer", {}};
    EXPECT_FALSE(composite::registerFormat(row));  // no composer
    row.composer = composeLeft;
    row.gpu = composite::GpuPlan::SideBySide;
    EXPECT_FALSE(composite::registerFormat(row));  // the gl backend has no shader for it
    row.gpu = composite::GpuPlan::None;
    row.name = "sbs";
    EXPECT_FALSE(composite::registerFormat(row));  // taken
}

TEST(RegisteredFormat, TheGlBackendComposesItOnTheCpu) {
    registerTestFormat();
    Result<const BackendEntry*> gl = findBackend("gl");
    if (!gl) MVR_SKIP(FeatureNotBuilt) << "no gl backend in this build";
    ASSERT_TRUE((*gl)->compose);
    const std::vector<Image> views = pair();
    // No GPU plan: the hook declines, so composeFor() composes on the CPU.
    EXPECT_FALSE((*gl)->compose("test-left", views, {}).has_value());
    // The built-in rows with a plan stay on the GPU's side; jps (a JPEG file) does not.
    EXPECT_FALSE((*gl)->compose("jps", views, {}).has_value());
    Result<std::unique_ptr<Backend>> backend = makeBackend("gl", {});
    if (!backend) MVR_SKIP(NoGlContext) << backend.status().message();
    Result<Image> image = composeFor(**backend, "test-left", views, {});
    ASSERT_TRUE(image) << image.status().message();
    EXPECT_EQ(image->rgba, views[0].rgba);
}

// `mvr render --format test-left` is this recipe (the CLI's --format accepts formatNames()):
// the session writes the row's file, on the CPU backend and on gl (composed on the CPU there).
TEST(RegisteredFormat, ARenderWritesItOnEveryBackend) {
    registerTestFormat();
    for (const std::string backend : {"soft", "gl"}) {
        SCOPED_TRACE(backend);
        const auto dir = std::filesystem::temp_directory_path() / ("mvr_registered_" + backend);
        std::filesystem::remove_all(dir);
        session::RenderRecipe recipe;
        recipe.views = 2;
        recipe.size = "32x24";
        recipe.backend = backend;
        recipe.outputs.directory = dir.string();
        recipe.outputs.formats = {"test-left"};
        Result<session::Rendered> done = session::renderStill(recipe);
        if (!done && backend == "gl" && done.status().code() == ErrorCode::Unsupported)
            MVR_SKIP(NoGlContext) << done.status().message();
        ASSERT_TRUE(done) << done.status().message();
        Result<Image> written = readPng(dir / "test-left.png");
        ASSERT_TRUE(written) << written.status().message();
        EXPECT_EQ(written->rgba, done->output.color.at(0).rgba);
        std::filesystem::remove_all(dir);
    }
}

TEST(RegisteredFormat, TheViewerListsIt) {
    registerTestFormat();
    const std::vector<std::string> formats = viewer::viewerFormats();
    ASSERT_FALSE(formats.empty());
    EXPECT_EQ(formats.back(), "quad-buffer");
    EXPECT_EQ(formats[formats.size() - 2], "test-left");
    EXPECT_EQ(std::count(formats.begin(), formats.end(), "jps"), 0);
    EXPECT_EQ(std::count(formats.begin(), formats.end(), "hdmi-frame-packing"), 0);
}

}  // namespace
}  // namespace mvr
