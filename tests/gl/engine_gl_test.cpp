// A file shaped like Khronos's 2CylinderEngine sample (engine_fixture.h: 40 nodes, meshes and
// materials, 16-bit indices), read by mvr::loadScene as `mvr render` reads it, on every gl
// method against soft:multipass within the conformance table's gl bound (kGlVsSoft: the same
// one every exact gl method is held to on the procedural scenes).
#include <unistd.h>

#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../conformance/tolerances.h"
#include "engine_fixture.h"
#include "gl_test_util.h"
#include "mvr/core/framing.h"
#include "mvr/io/scene_io.h"
#include "mvr/raster/soft_backend.h"

namespace mvr::gl::test {
namespace {

TEST(GlEngine, ManyMeshFileRendersOnEveryMethodWithinTheBoundOfSoft) {
    MVR_SKIP_WITHOUT_GL();
    const auto dir =
        std::filesystem::temp_directory_path() / fmt::format("mvr-engine-{}", ::getpid());
    std::filesystem::create_directories(dir);
    auto scene = loadScene(writeEngineGlb(dir / "engine.glb"));
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(scene->meshes.size(), 40u);
    ASSERT_EQ(scene->instances.size(), 40u);
    if (scene->lights.empty()) scene->lights = defaultLights();
    const Rig rig = rigFor(*scene, 2, 1);
    RenderSettings s;
    s.width = 160;
    s.height = 120;
    s.clearColor = {0.1f, 0.15f, 0.2f};
    auto ref = raster::makeSoftBackend()->render(*scene, rig, s, "multipass");
    ASSERT_TRUE(ref) << ref.status().message();
    const conformance::Bound& b = conformance::kGlVsSoft;
    for (const std::string& m : backend().methods()) {
        if (!backend().supports(m)) continue;
        // Twice: the second render finds the meshes on the GPU from the first.
        for (int run = 0; run < 2; ++run) {
            auto out = backend().render(*scene, rig, s, m);
            ASSERT_TRUE(out) << m << ": " << out.status().message();
            if (!backend().lastStats() || m == "gs-mrt" || m == "gs-depthmap") continue;
            for (std::size_t v = 0; v < ref->color.size(); ++v) {
                const ImageDiff d = compareImages(ref->color[v], out->color[v], b.channel);
                const double share = double(d.differingPixels) / (s.width * s.height);
                EXPECT_TRUE(b.shareFor(int(v)).holds(share))
                    << m << " view " << v << ": " << 100 * share << " % off, max " << d.maxDelta;
            }
        }
    }
}

}  // namespace
}  // namespace mvr::gl::test
