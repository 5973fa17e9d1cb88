// Scene framing in the library (mvr/core/framing.h): a library user who frames a scene with
// frameScene() and renders it gets exactly the images `mvr render` writes, and the framing's
// geometry is what its documentation says (computed here independently).
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "mvr/backends.h"
#include "mvr/core/framing.h"
#include "mvr/io/mesh_io.h"
#include "mvr/io/png.h"
#include "mvr_test_support.h"

namespace mvr {
namespace {

namespace fs = std::filesystem;

fs::path mvrBinary() {
    return ::mvr::test::mvrBinary();
}

fs::path sharedModel(const char* name) {
    const char* dir = std::getenv("MVR_SHARED_DIR");
    return fs::path(dir ? dir : MVR_TEST_SHARED_DIR) / "models" / name;
}

/// Runs `mvr render ARGS -o DIR -q` and returns its exit code.
int mvrRender(const std::string& args, const fs::path& dir) {
    const std::string cmd = fmt::format("'{}' render {} -q -o '{}' </dev/null",
                                        mvrBinary().string(), args, dir.string());
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

class Framing : public ::testing::Test {
protected:
    void SetUp() override {
        mDir = fs::temp_directory_path() /
               fmt::format("mvr-framing-test-{}-{}", ::getpid(),
                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(mDir);
    }
    void TearDown() override { fs::remove_all(mDir); }
    fs::path mDir;
};

void expectSameAsCli(const Scene& scene, const FramingParams& params, RenderSettings settings,
                     const std::string& cliArgs, const fs::path& dir) {
    auto request = frameScene(scene, params, settings);
    ASSERT_TRUE(request) << request.status().message();
    auto soft = makeBackend("soft");
    ASSERT_TRUE(soft);
    auto out = (*soft)->render(scene, request->rig, request->settings, (*soft)->defaultMethod());
    ASSERT_TRUE(out) << out.status().message();
    ASSERT_EQ(mvrRender(cliArgs, dir), 0) << cliArgs;
    ASSERT_EQ(int(out->color.size()), request->rig.viewCount());
    for (int v = 0; v < request->rig.viewCount(); ++v) {
        auto cli = readPng(dir / fmt::format("view-{}.png", v));
        ASSERT_TRUE(cli) << cli.status().message();
        EXPECT_TRUE(*cli == out->color[std::size_t(v)])
            << "view " << v << " of `mvr render " << cliArgs << "` differs from the API's";
    }
}

TEST_F(Framing, TheApiRendersWhatTheCliWritesForTheDefaultScene) {
    expectSameAsCli(makeDefaultScene(), FramingParams{}, RenderSettings{.width = 96, .height = 72},
                    "--size 96x72", mDir);
}

TEST_F(Framing, TheApiRendersWhatTheCliWritesForAModelGridAndOptions) {
    auto mesh = loadMesh(sharedModel("suzanne.obj"));
    ASSERT_TRUE(mesh) << mesh.status().message();
    const Scene scene = makeGridScene({*mesh}, 3);
    FramingParams p;
    p.columns = 3;
    p.rows = 2;
    p.fovYDegrees = 50.0f;
    p.separation = 0.02f;
    expectSameAsCli(scene, p, RenderSettings{.width = 64, .height = 48, .shading = Shading::Pixel},
                    fmt::format("'{}' --grid 3 --view-grid 3x2 --fov 50 --separation 0.02 "
                                "--size 64x48 --shading pixel",
                                sharedModel("suzanne.obj").string()),
                    mDir);
}

TEST(FramingGeometry, FitsTheBoundingSphereFromPlusZ) {
    Mesh m;
    m.positions = {{-1, -1, -1}, {3, -1, -1}, {-1, 1, 1}};  // bounds centre (1, 0, 0)
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.indices = {0, 1, 2};
    Scene s;
    s.meshes = {m};
    s.instances = {Instance{}};
    const float fov = 40.0f, aspect = 0.5f;  // portrait: the horizontal fov is the narrower
    const Camera c = frameCamera(s, fov, aspect);
    const float r = std::sqrt(4.0f + 1.0f + 1.0f);  // half the box diagonal (4, 2, 2)
    const float halfX = std::atan(std::tan(fov * 3.14159265f / 360.0f) * aspect);
    const float d = 1.05f * r / std::sin(halfX);
    EXPECT_NEAR(c.target.x, 1.0f, 1e-5f);
    EXPECT_NEAR(c.position.x, 1.0f, 1e-5f);
    EXPECT_NEAR(c.position.z, d, 1e-3f);
    EXPECT_NEAR(c.near, std::max(d - 2.5f * r, 0.02f * d), 1e-3f);
    EXPECT_NEAR(c.far, d + 3.0f * r, 1e-3f);

    FramingParams params;
    params.fovYDegrees = fov;
    auto req = frameScene(s, params, RenderSettings{.width = 50, .height = 100});
    ASSERT_TRUE(req) << req.status().message();
    EXPECT_NEAR(req->rig.convergence, d, 1e-3f);         // the target's distance
    EXPECT_NEAR(req->rig.interaxial, d / 30.0f, 1e-4f);  // convergence / 30
    EXPECT_EQ(req->settings.clearColor, s.background);
}

// The Looking Glass camera (their Unity pipeline's LookingGlassUtil: angle of view i =
// -cone/2 + cone*i/(N-1), offset D*tan(angle) at the focal distance D): the outer eyes of a
// 48-view, 40 degree cone seen from the centre of the convergence plane make -20 and +20 degrees,
// computed here from the eye positions, and a projected point on that plane has one x in all views.
TEST(FramingGeometry, AViewConeSpreadsTheRowOverItsAngle) {
    const Scene s = makeDefaultScene();
    FramingParams params;
    params.columns = 48;
    params.viewConeDegrees = 40.0f;
    auto req = frameScene(s, params, RenderSettings{.width = 42, .height = 56});
    ASSERT_TRUE(req) << req.status().message();
    const Rig& rig = req->rig;
    ASSERT_EQ(rig.viewCount(), 48);
    const glm::vec3 fwd = glm::normalize(rig.camera.target - rig.camera.position);
    const glm::vec3 focal = rig.camera.position + fwd * rig.convergence;
    const glm::vec3 right = glm::normalize(glm::cross(fwd, rig.camera.up));
    auto angleOf = [&](int v) {
        const glm::vec3 d = rig.views[std::size_t(v)].eyeWorld - focal;
        return glm::degrees(std::atan2(glm::dot(d, right), -glm::dot(d, fwd)));
    };
    EXPECT_NEAR(angleOf(0), -20.0f, 1e-2f);
    EXPECT_NEAR(angleOf(47), 20.0f, 1e-2f);
    EXPECT_NEAR(angleOf(12), -20.0f + 40.0f * 12.0f / 47.0f, 1e-2f);
    const glm::vec3 onPlane = focal + right * 0.3f;
    float x0 = 0.0f;
    for (int v = 0; v < 48; ++v) {
        const glm::vec4 c = rig.views[std::size_t(v)].clipFromView *
                            rig.views[std::size_t(v)].viewFromWorld * glm::vec4(onPlane, 1.0f);
        if (v == 0) x0 = c.x / c.w;
        EXPECT_NEAR(c.x / c.w, x0, 1e-4f) << v;
    }
    params.interaxial = 0.1f;
    auto both = frameScene(s, params, RenderSettings{.width = 42, .height = 56});
    ASSERT_FALSE(both);
    EXPECT_NE(both.status().message().find("view cone"), std::string::npos);
}

namespace {

// A unit cube (12 triangles) centred at the origin: a scene 1 unit deep.
Scene cubeScene() {
    Mesh m;
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const float sign = face % 2 ? 1.0f : -1.0f;
        glm::vec3 n(0.0f), u(0.0f), v(0.0f);
        n[axis] = sign;
        u[(axis + 1) % 3] = 0.5f;
        v[(axis + 2) % 3] = 0.5f;
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1),
                                  glm::vec2(-1, 1)}) {
            m.positions.push_back(0.5f * n + c.x * u + c.y * v);
            m.normals.push_back(n);
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) m.indices.push_back(base + i);
    }
    Scene s;
    s.meshes = {m};
    s.instances = {Instance{}};
    return s;
}

// Distinct depth values among the drawn pixels of view 0 (soft:multipass).
std::size_t distinctDepths(const Scene& scene, const FramingParams& params, int w, int h) {
    auto req = frameScene(scene, params, RenderSettings{.width = w, .height = h});
    EXPECT_TRUE(req) << req.status().message();
    if (!req) return 0;
    auto backend = makeBackend("soft");
    auto out = (*backend)->render(scene, req->rig, req->settings, "multipass");
    EXPECT_TRUE(out) << out.status().message();
    if (!out) return 0;
    std::set<float> values;
    for (float d : out->depth[0].depth)
        if (d < 1.0f) values.insert(d);
    return values.size();
}

}  // namespace

// Khronos's 2CylinderEngine: a file camera with znear 0.05 and zfar 1e6 over a scene a few
// units deep left 208 distinct depth values for 139 589 pixels (z-fighting). The file's planes
// are limits: the same camera, seen through them, resolves the scene's depth as finely as the
// bounds' own near / far do (counted here, not computed from the code's planes).
TEST(FramingGeometry, AFileCameraWithFarPlanesKeepsTheDepthResolution) {
    Scene s = cubeScene();
    s.instances[0].worldFromModel = glm::rotate(glm::mat4(1.0f), 0.6f, glm::vec3(1, 1, 0));
    const Camera framed = frameCamera(s, 45.0f, 1.0f);
    SceneCamera file;
    file.worldFromCamera = glm::inverse(glm::lookAt(framed.position, framed.target, framed.up));
    file.yfovRadians = glm::radians(45.0f);
    file.aspect = 1.0f;
    file.znear = 0.05f;
    file.zfar = 1e6f;
    s.camera = file;
    FramingParams params;
    params.columns = 1;
    const std::size_t withFile = distinctDepths(s, params, 128, 128);
    params.useSceneCamera = false;
    const std::size_t withBounds = distinctDepths(s, params, 128, 128);
    EXPECT_GT(withBounds, 1000u);
    EXPECT_GE(withFile, withBounds);
    // The file's planes stay limits: a near plane beyond the scene's front is kept.
    file.znear = glm::length(framed.position) - 0.2f;
    s.camera = file;
    const Camera limited = cameraFromScene(file, s, std::nullopt, 1.0f);
    EXPECT_FLOAT_EQ(limited.near, file.znear);
}

// A square file camera (yfov 18 degrees) seen in a Portrait view (aspect 0.75) kept its yfov
// and cropped the sides; the file's horizontal field of view is kept instead, as a sensor fit
// does; a wider output keeps the yfov.
TEST(FramingGeometry, AFileCameraKeepsItsWholeFrameAtAnyAspect) {
    Scene s = cubeScene();
    SceneCamera file;
    file.worldFromCamera = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 10));
    file.yfovRadians = glm::radians(18.0f);
    file.aspect = 1.0f;
    s.camera = file;
    const float halfX = std::atan(std::tan(glm::radians(9.0f)) * 1.0f);  // the file's, aspect 1
    const Camera portrait = cameraFromScene(file, s, std::nullopt, 0.75f);
    const float portraitHalfX =
        std::atan(std::tan(glm::radians(portrait.fovYDegrees) * 0.5f) * 0.75f);
    EXPECT_NEAR(portraitHalfX, halfX, 1e-5f);
    EXPECT_NEAR(portrait.fovYDegrees, 2.0f * glm::degrees(std::atan(std::tan(glm::radians(9.0f)) / 0.75f)), 1e-3f);
    EXPECT_FLOAT_EQ(cameraFromScene(file, s, std::nullopt, 16.0f / 9.0f).fovYDegrees, 18.0f);
    file.aspect = 0.0f;  // not given: yfov as given
    EXPECT_FLOAT_EQ(cameraFromScene(file, s, std::nullopt, 0.75f).fovYDegrees, 18.0f);
    file.aspect = 1.0f;  // --fov wins
    EXPECT_FLOAT_EQ(cameraFromScene(file, s, 30.0f, 0.75f).fovYDegrees, 30.0f);
}

TEST(FramingGeometry, TheSceneViewpointWins) {
    const Scene s = makeDefaultScene();
    ASSERT_TRUE(s.viewpoint);
    const Camera c = frameCamera(s, 45.0f, 4.0f / 3.0f);
    EXPECT_EQ(c.position, s.viewpoint->position);
    EXPECT_EQ(c.target, s.viewpoint->target);
}

TEST(FramingGeometry, BadParametersAreUsageErrorsNamingThem) {
    const Scene s = makeDefaultScene();
    auto expectBad = [&](FramingParams p, const char* name) {
        auto r = frameScene(s, p);
        ASSERT_FALSE(r) << name;
        EXPECT_EQ(r.status().code(), ErrorCode::Usage) << name;
        EXPECT_NE(r.status().message().find(name), std::string::npos) << r.status().message();
    };
    auto with = [](auto set) {
        FramingParams p;
        set(p);
        return p;
    };
    expectBad(with([](FramingParams& p) { p.fovYDegrees = 180.0f; }), "fov");
    expectBad(with([](FramingParams& p) { p.fovYDegrees = std::nanf(""); }), "fov");
    expectBad(with([](FramingParams& p) { p.interaxial = -1.0f; }), "interaxial");
    expectBad(with([](FramingParams& p) { p.separation = INFINITY; }), "separation");
    expectBad(with([](FramingParams& p) { p.convergence = 0.0f; }), "convergence");
    expectBad(with([](FramingParams& p) { p.convergence = 1e6f; }), "beyond the far plane");
    expectBad(with([](FramingParams& p) { p.interaxial = 0.1f, p.separation = 0.02f; }),
              "separation");
    expectBad(with([](FramingParams& p) { p.columns = 13, p.rows = 10; }), "views");
    EXPECT_FALSE(frameScene(Scene{}, FramingParams{}));
}

}  // namespace
}  // namespace mvr
