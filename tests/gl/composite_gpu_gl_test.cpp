// mvr::gl::composeGpu() against the CPU composites (mvr::composite::compose()): every image
// format, several view counts and sizes (odd ones included), swap-eyes / cross-eyed, lenticular
// calibrations with every flip, a tiled output, and the same errors for bad input.
//
// Tolerance, per channel INCLUDING alpha: 0 (bit-exact) for the pixel-moving formats and
// lenticular (integer copies and pair averages; lenticular's view choice in double precision
// without fused multiply-adds); 1/255 for the anaglyphs (the GPU's pow() vs the CPU's
// table-driven sRGB curve can round to the neighbouring 8-bit value).
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <epoxy/egl.h>
#include <gtest/gtest.h>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/gl/composite_gpu.h"
#include "mvr/gl/gl_backend.h"
#include "gl_test_util.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {
namespace {

Image randomImage(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    Image img(w, h);
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xFF);
    return img;
}

std::vector<Image> randomViews(int n, int w, int h, unsigned seed) {
    std::vector<Image> views;
    for (int i = 0; i < n; ++i) views.push_back(randomImage(w, h, seed * 101 + i));
    return views;
}

struct Diff {
    int maxDelta = 0;    ///< over R, G, B and A
    long differing = 0;  ///< bytes that differ at all
};

Diff diff(const Image& a, const Image& b) {
    Diff d;
    if (a.width != b.width || a.height != b.height || a.rgba.size() != b.rgba.size())
        return {256, -1};
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        const int delta = std::abs(int(a.rgba[i]) - int(b.rgba[i]));
        d.maxDelta = std::max(d.maxDelta, delta);
        d.differing += delta != 0;
    }
    return d;
}

bool isAnaglyph(const std::string& f) { return f.rfind("anaglyph-", 0) == 0; }

// Composes on both sides; returns false (test skipped) when there is no GL here.
bool compareOne(const std::string& format, const std::vector<Image>& views,
                const composite::ComposeOptions& options, const std::string& what) {
    Result<Image> gpu = composeGpu(format, views, options);
    if (!gpu && gpu.status().code() == ErrorCode::Unsupported &&
        gpu.status().message().find("EGL") != std::string::npos)
        return false;
    Result<Image> cpu = composite::compose(format, views, options);
    EXPECT_TRUE(cpu) << what << ": " << cpu.status().message();
    EXPECT_TRUE(gpu) << what << ": " << gpu.status().message();
    if (!cpu || !gpu) return true;
    const Diff d = diff(*gpu, *cpu);
    const int tolerance = isAnaglyph(format) ? 1 : 0;
    EXPECT_LE(d.maxDelta, tolerance) << what << " (" << gpu->width << "x" << gpu->height << " vs "
                                     << cpu->width << "x" << cpu->height << ")";
    std::printf("[ measured ] %-44s %5dx%-5d max delta %d, %ld bytes differ\n", what.c_str(),
                gpu->width, gpu->height, d.maxDelta, d.differing);
    return true;
}

#define MVR_COMPARE(format, views, options, what)                                            \
    do {                                                                                     \
        if (!compareOne(format, views, options, what)) MVR_SKIP(NoGlContext) << "no GL context here"; \
    } while (0)

std::string label(const std::string& format, int n, int w, int h, const std::string& extra = "") {
    return format + " " + std::to_string(n) + "v " + std::to_string(w) + "x" + std::to_string(h) +
           extra;
}

TEST(ComposeGpu, StereoFormatsMatchTheCpu) {
    const std::vector<std::pair<int, int>> sizes = {{1, 1}, {37, 23}, {64, 48}, {2, 2}};
    for (const std::string& format : composite::formatNames()) {
        if (!composeGpuSupports(format)) continue;
        auto info = composite::findFormat(format);
        ASSERT_TRUE(info);
        if (info->minViews > 2 || info->maxViews < 2) continue;
        if (format == "hdmi-frame-packing") continue;  // own test (fixed sizes)
        for (auto [w, h] : sizes) {
            if ((format == "sbs-half" && w % 2) || (format == "tb-half" && h % 2)) continue;
            const std::vector<Image> views = randomViews(2, w, h, unsigned(w * 7 + h));
            for (int swap = 0; swap < 2; ++swap) {
                for (int cross = 0; cross < (format.rfind("sbs", 0) == 0 ? 2 : 1); ++cross) {
                    composite::ComposeOptions o;
                    o.swapEyes = swap;
                    o.crossEyed = cross;
                    MVR_COMPARE(format, views, o,
                                label(format, 2, w, h,
                                      std::string(swap ? " swap" : "") + (cross ? " cross" : "")));
                }
            }
        }
    }
}

TEST(ComposeGpu, HalfFormatsOnOddSizesOfTheOtherAxis) {
    // sbs-half squeezes x only (odd heights are fine), tb-half y only.
    const std::vector<Image> a = randomViews(2, 38, 21, 5), b = randomViews(2, 17, 30, 6);
    MVR_COMPARE("sbs-half", a, composite::ComposeOptions{}, "sbs-half 2v 38x21");
    MVR_COMPARE("tb-half", b, composite::ComposeOptions{}, "tb-half 2v 17x30");
}

TEST(ComposeGpu, HdmiFramePackingMatchesTheCpu) {
    for (auto [w, h] : {std::pair{1280, 720}, std::pair{1920, 1080}}) {
        const std::vector<Image> views = randomViews(2, w, h, 9);
        composite::ComposeOptions swap;
        swap.swapEyes = true;
        MVR_COMPARE("hdmi-frame-packing", views, composite::ComposeOptions{},
                    label("hdmi-frame-packing", 2, w, h));
        MVR_COMPARE("hdmi-frame-packing", views, swap,
                    label("hdmi-frame-packing", 2, w, h, " swap"));
    }
}

TEST(ComposeGpu, MultiViewFormatsMatchTheCpu) {
    for (const std::string format : {"rows", "columns", "quilt", "lenticular"}) {
        for (int n : {2, 3, 5, 8}) {
            for (auto [w, h] : {std::pair{31, 17}, std::pair{40, 30}}) {
                const std::vector<Image> views = randomViews(n, w, h, unsigned(n * 13 + w));
                for (int swap = 0; swap < 2; ++swap) {
                    composite::ComposeOptions o;
                    o.swapEyes = swap;
                    MVR_COMPARE(format, views, o, label(format, n, w, h, swap ? " swap" : ""));
                }
            }
        }
    }
}

TEST(ComposeGpu, QuiltGridsMatchTheCpu) {
    // One view; blank tiles (7 views in 3x3); an explicit wide grid; the Looking Glass 45.
    const std::vector<Image> one = randomViews(1, 20, 15, 1), seven = randomViews(7, 21, 11, 2);
    const std::vector<Image> many = randomViews(45, 18, 10, 3);
    composite::ComposeOptions grid33, grid71;
    grid33.quiltColumns = grid33.quiltRows = 3;
    grid71.quiltColumns = 7;
    grid71.quiltRows = 1;
    MVR_COMPARE("quilt", one, composite::ComposeOptions{}, "quilt 1v 20x15");
    MVR_COMPARE("quilt", seven, grid33, "quilt 7v 21x11 3x3");
    MVR_COMPARE("quilt", seven, grid71, "quilt 7v 21x11 7x1");
    MVR_COMPARE("quilt", many, composite::ComposeOptions{}, "quilt 45v 18x10");
}

TEST(ComposeGpu, OutputsLargerThanATileAreDrawnInTiles) {
    // 3 x 1500 = 4500 columns: more than the 4096-pixel tile, so two tiles across.
    const std::vector<Image> views = randomViews(3, 1500, 9, 4);
    composite::ComposeOptions grid;
    grid.quiltColumns = 3;
    grid.quiltRows = 1;
    MVR_COMPARE("quilt", views, grid, "quilt 3v 1500x9 3x1 (tiled)");
    MVR_COMPARE("sbs", randomViews(2, 2100, 5, 5), composite::ComposeOptions{},
                "sbs 2v 2100x5 (tiled)");
}

TEST(ComposeGpu, LenticularCalibrationsMatchTheCpu) {
    const std::vector<Image> views = randomViews(9, 48, 64, 11);
    for (int flags = 0; flags < 16; ++flags) {
        composite::ComposeOptions o;
        o.lenticular.bgr = flags & 1;
        o.lenticular.invertViews = flags & 2;
        o.lenticular.flipX = flags & 4;
        o.lenticular.flipY = flags & 8;
        MVR_COMPARE("lenticular", views, o,
                    std::string("lenticular 9v 48x64") + (flags & 1 ? " bgr" : "") +
                        (flags & 2 ? " invert" : "") + (flags & 4 ? " flipX" : "") +
                        (flags & 8 ? " flipY" : ""));
    }
    // Another panel: positive slope, other pitch / centre, a screen larger and smaller than the
    // views (nearest-pixel resampling), the 45 views of a Looking Glass quilt.
    composite::ComposeOptions panel;
    panel.lenticular.pitch = 47.5;
    panel.lenticular.slope = 5.3;
    panel.lenticular.center = 0.13;
    panel.lenticular.dpi = 338;
    panel.lenticular.screenWidth = 97;
    panel.lenticular.screenHeight = 131;
    MVR_COMPARE("lenticular", views, panel, "lenticular 9v 48x64 -> 97x131 slope 5.3");
    panel.lenticular.screenWidth = 23;
    panel.lenticular.screenHeight = 19;
    panel.swapEyes = true;
    MVR_COMPARE("lenticular", views, panel, "lenticular 9v 48x64 -> 23x19 swap");
    composite::ComposeOptions lg;
    MVR_COMPARE("lenticular", randomViews(45, 30, 40, 12), lg, "lenticular 45v 30x40");
}

// The part of a compose() error after "who: " (and the format name compose() adds).
std::string errorTail(const std::string& message, const std::string& format) {
    std::string tail = message;
    if (const auto at = tail.find("): "); at != std::string::npos) tail = tail.substr(at + 3);
    if (tail.rfind(format + ": ", 0) == 0) tail = tail.substr(format.size() + 2);
    return tail;
}

TEST(ComposeGpu, BadInputGivesComposesErrors) {
    struct Case {
        std::string format;
        std::vector<Image> views;
        composite::ComposeOptions options;
    };
    composite::ComposeOptions badGrid, smallGrid, badLens;
    badGrid.quiltColumns = 3;  // rows 0: both or neither
    smallGrid.quiltColumns = smallGrid.quiltRows = 2;
    badLens.lenticular.slope = 0;
    std::vector<Image> mixed = randomViews(2, 8, 8, 1);
    mixed.push_back(randomImage(9, 8, 2));
    std::vector<Image> withEmpty = randomViews(2, 8, 8, 3);
    withEmpty.push_back(Image());
    const std::vector<Case> cases = {
        {"nonsense", randomViews(2, 4, 4, 1), {}},
        {"sbs", randomViews(3, 4, 4, 1), {}},
        {"anaglyph-dubois", randomViews(1, 4, 4, 1), {}},
        {"rows", randomViews(1, 4, 4, 1), {}},
        {"columns", mixed, {}},
        {"quilt", withEmpty, {}},
        {"sbs-half", randomViews(2, 7, 4, 1), {}},
        {"tb-half", randomViews(2, 4, 7, 1), {}},
        {"hdmi-frame-packing", randomViews(2, 640, 480, 1), {}},
        {"quilt", randomViews(5, 4, 4, 1), badGrid},
        {"quilt", randomViews(5, 4, 4, 1), smallGrid},
        {"lenticular", randomViews(3, 4, 4, 1), badLens},
    };
    for (const Case& c : cases) {
        Result<Image> cpu = composite::compose(c.format, c.views, c.options);
        Result<Image> gpu = composeGpu(c.format, c.views, c.options);
        ASSERT_FALSE(cpu) << c.format;
        ASSERT_FALSE(gpu) << c.format;
        EXPECT_EQ(gpu.status().code(), cpu.status().code()) << c.format;
        const std::string tail = errorTail(cpu.status().message(), c.format);
        EXPECT_NE(gpu.status().message().find(tail), std::string::npos)
            << "GPU: " << gpu.status().message() << "\nCPU: " << cpu.status().message();
        if (c.format != "nonsense") {
            EXPECT_EQ(gpu.status().message().rfind("mvr::", 0), 0u) << gpu.status().message();
        }
    }
}

TEST(ComposeGpu, JpegFilesStayOnTheCpu) {
    const std::vector<Image> views = randomViews(2, 4, 4, 1);
    EXPECT_FALSE(composeGpuSupports("jps"));
    EXPECT_FALSE(composeGpuSupports("mpo"));
    EXPECT_FALSE(composeGpuSupports("nonsense"));
    EXPECT_TRUE(composeGpuSupports("lenticular"));
    for (const char* f : {"jps", "mpo"}) {
        Result<Image> r = composeGpu(f, views, {});
        ASSERT_FALSE(r);
        EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
        EXPECT_NE(r.status().message().find("JPEG file"), std::string::npos)
            << r.status().message();
    }
}

TEST(ComposeGpu, WorksFromAnotherThreadAndLeavesNoContextCurrent) {
    const EGLContext before = eglGetCurrentContext();  // a backend's, when other tests ran
    const std::vector<Image> views = randomViews(2, 16, 8, 21);
    Result<Image> here = composeGpu("checkerboard", views, {});
    if (!here && here.status().code() == ErrorCode::Unsupported)
        MVR_SKIP(MethodUnsupportedByDriver) << here.status().message();
    ASSERT_TRUE(here) << here.status().message();
    Result<Image> there = internalError("not run");
    std::thread t([&] { there = composeGpu("checkerboard", views, {}); });
    t.join();
    ASSERT_TRUE(there) << there.status().message();
    EXPECT_EQ(diff(*here, *there).maxDelta, 0);
    Result<Image> again = composeGpu("anaglyph-color", views, {});
    ASSERT_TRUE(again) << again.status().message();
    EXPECT_EQ(eglGetCurrentContext(), before);  // not the composite context
}

TEST(ComposeGpu, GivesBackTheCallersCurrentContext) {
    // A gl backend's render leaves its own context current on this thread; a composite in
    // between must not take it away.
    std::unique_ptr<mvr::Backend> backend = makeGlBackend();
    if (Status s = backend->supports("multipass"); !s) MVR_SKIP(NoGlContext) << s.message();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1);
    RenderSettings settings;
    settings.width = 32;
    settings.height = 24;
    auto first = backend->render(scene, rig, settings, "multipass");
    ASSERT_TRUE(first) << first.status().message();
    const EGLContext before = eglGetCurrentContext();
    ASSERT_NE(before, EGL_NO_CONTEXT);
    Result<Image> c = composeGpu("sbs", first->color, {});
    ASSERT_TRUE(c) << c.status().message();
    EXPECT_EQ(eglGetCurrentContext(), before);
    auto second = backend->render(scene, rig, settings, "multipass");
    ASSERT_TRUE(second) << second.status().message();
    EXPECT_EQ(diff(first->color[0], second->color[0]).maxDelta, 0);
}

}  // namespace
}  // namespace mvr::gl::test
