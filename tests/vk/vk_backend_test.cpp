// Tests of the vk backend (include/mvr/vk/vk_backend.h) on the machine's Vulkan device (lavapipe
// in CI), validation layers on (validation_env.cpp): the registry row, `mvr info`'s lines,
// batching past maxMultiviewViewCount, every method against vk:multipass and soft:multipass,
// depth on and off, and the Unsupported messages. The conformance suite (tests/conformance)
// compares every vk method with soft:multipass on all its scenes.
#include <algorithm>
#include <cstdlib>
#include <regex>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "test_scenes.h"
#include "../conformance/tolerances.h"
#include "mvr/backends.h"
#include "mvr/vk/vk_backend.h"
#include "mvr_test_support.h"

namespace mvr::vk::test {
namespace {

using ::mvr::test::defaultScene;
using ::mvr::test::rigFor;

constexpr int kW = 96, kH = 72;

// One backend (one device) for the process, destroyed before main() returns: Mesa's drivers
// tear their threads down in exit handlers, after which no Vulkan object can be destroyed.
std::unique_ptr<Backend>& holder() {
    static std::unique_ptr<Backend> b;
    return b;
}
Backend& backend() {
    if (!holder()) holder() = makeVkBackend();
    return *holder();
}
class ReleaseBackend : public testing::Environment {
public:
    void TearDown() override { holder().reset(); }
};
const testing::Environment* const kRelease =
    testing::AddGlobalTestEnvironment(new ReleaseBackend);

/// Skips without a Vulkan device; fails instead under MVR_REQUIRE_GL=1 (CI has lavapipe).
#define MVR_SKIP_WITHOUT_VK()                                                       \
    do {                                                                            \
        const ::mvr::Status s_ = backend().supports("multipass");                   \
        if (!s_) MVR_SKIP(NoVulkanDevice) << s_.message();                          \
    } while (0)

RenderSettings small(Shading shading = Shading::Vertex) {
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.shading = shading;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    return s;
}

int multiviewLimit() {
    const std::regex re(R"(maxMultiviewViewCount (\d+))");
    for (const std::string& line : backend().info()) {
        std::smatch m;
        if (std::regex_search(line, m, re)) return std::stoi(m[1]);
    }
    return 0;
}

/// Share of pixels with a channel more than `channel` apart.
double offShare(const Image& a, const Image& b, int channel) {
    return double(compareImages(a, b, channel).differingPixels) / (double(a.width) * a.height);
}

TEST(VkBackend, IsInTheRegistryAndNamesItsMethods) {
    auto entry = findBackend("vk");
    ASSERT_TRUE(entry) << entry.status().message();
    EXPECT_TRUE((*entry)->gpu);
    const auto& names = vkMethodNames();
    EXPECT_EQ(names.front(), "multipass");
    EXPECT_EQ(names.back(), "auto");
    EXPECT_EQ(backend().supports("gs-mrt").code(), ErrorCode::Usage);
}

TEST(VkBackend, InfoNamesDeviceDriverAndMultiviewLimit) {
    MVR_SKIP_WITHOUT_VK();
    const auto info = backend().info();
    auto has = [&](const std::string& prefix) {
        return std::any_of(info.begin(), info.end(),
                           [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
    };
    EXPECT_TRUE(has("vk device: "));
    EXPECT_TRUE(has("vk driver: "));
    EXPECT_TRUE(has("vk validation: on")) << "validation_env.cpp should have turned it on";
    EXPECT_GE(multiviewLimit(), 2);
}

TEST(VkBackend, MultiviewBatchesPastTheDeviceLimit) {
    MVR_SKIP_WITHOUT_VK();
    const int limit = multiviewLimit();
    ASSERT_GE(limit, 1);
    const int views = limit + 2;  // lavapipe: 8 views = 6 + 2
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, views, 1, float(kW) / kH);
    auto mv = backend().render(scene, rig, small(), "multiview");
    ASSERT_TRUE(mv) << mv.status().message();
    const auto stats = backend().lastStats();
    ASSERT_TRUE(stats);
    EXPECT_EQ(stats->passes, 2);
    EXPECT_EQ(stats->method, "multiview");
    auto mp = backend().render(scene, rig, small(), "multipass");
    ASSERT_TRUE(mp) << mp.status().message();
    ASSERT_EQ(mv->color.size(), std::size_t(views));
    ASSERT_EQ(mv->depth.size(), std::size_t(views));
    for (int v = 0; v < views; ++v) {
        // The bound of tolerances.h's vk:multiview row (its reason says why it is not exact).
        EXPECT_LE(offShare(mv->color[v], mp->color[v], 2), 0.03) << "view " << v;
    }
}

TEST(VkBackend, EveryMethodAndShadingMatchesSoftMultipass) {
    MVR_SKIP_WITHOUT_VK();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 3, 1, float(kW) / kH);
    for (Shading sh : {Shading::Flat, Shading::Vertex, Shading::Pixel}) {
        auto ref = (*soft)->render(scene, rig, small(sh), "multipass");
        ASSERT_TRUE(ref) << ref.status().message();
        for (const char* m : {"multipass", "multiview", "instanced-layer", "auto"}) {
            SCOPED_TRACE(fmt::format("vk:{} {}", m, shadingName(sh)));
            if (Status s = backend().supports(m); !s) {
                ASSERT_EQ(s.code(), ErrorCode::Unsupported) << s.message();
                continue;
            }
            auto out = backend().render(scene, rig, small(sh), m);
            ASSERT_TRUE(out) << out.status().message();
            for (int v = 0; v < 3; ++v) {
                const double bound = std::string(m) == "multiview" || std::string(m) == "auto"
                                         ? 0.03
                                         : 0.01;
                EXPECT_LE(offShare(out->color[v], ref->color[v], 2), bound) << "view " << v;
            }
        }
    }
}

TEST(VkBackend, DepthFalseSkipsTheDepthImages) {
    MVR_SKIP_WITHOUT_VK();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1, float(kW) / kH);
    RenderSettings s = small();
    auto with = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(with) << with.status().message();
    ASSERT_EQ(with->depth.size(), 2u);
    // Window depth in [0, 1], 1 where nothing was drawn; something was drawn.
    const auto [lo, hi] = std::minmax_element(with->depth[0].depth.begin(),
                                              with->depth[0].depth.end());
    EXPECT_GE(*lo, 0.0f);
    EXPECT_LT(*lo, 1.0f);
    EXPECT_EQ(*hi, 1.0f);
    s.depth = false;
    auto without = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(without) << without.status().message();
    EXPECT_TRUE(without->depth.empty());
    EXPECT_EQ(without->color[1].rgba, with->color[1].rgba);
}

TEST(VkBackend, CullingKeepsTheFrontFaces) {
    MVR_SKIP_WITHOUT_VK();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1, float(kW) / kH);
    RenderSettings s = small();
    s.cullBackFaces = true;
    auto ref = (*soft)->render(scene, rig, s, "multipass");
    auto out = backend().render(scene, rig, s, "multipass");
    ASSERT_TRUE(ref && out);
    EXPECT_LE(offShare(out->color[0], ref->color[0], 2), 0.01);
}

TEST(VkBackend, ShadowsAndTexturesAreUnsupportedSayingSo) {
    MVR_SKIP_WITHOUT_VK();
    const Scene& scene = defaultScene();
    const Rig rig = rigFor(scene, 2, 1, float(kW) / kH);
    RenderSettings s = small();
    s.shadows = true;
    auto r = backend().render(scene, rig, s, "multiview");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), ErrorCode::Unsupported);
    EXPECT_NE(r.status().message().find("shadows"), std::string::npos) << r.status().message();
    auto tr = backend().render(makeTexturedScene(), rig, small(), "multipass");
    ASSERT_FALSE(tr);
    EXPECT_EQ(tr.status().code(), ErrorCode::Unsupported);
    EXPECT_NE(tr.status().message().find("textured"), std::string::npos);
}

}  // namespace
}  // namespace mvr::vk::test
