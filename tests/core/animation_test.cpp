// The animation module: orbit, camera paths and glTF-style samplers on hand-made keys.
#include "mvr/core/animation.h"

#include <cmath>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

namespace mvr {
namespace {

constexpr float kEps = 1e-5f;

TEST(Animation, OrbitTurnsAboutTheCentreAndKeepsTheDistance) {
    Camera c;
    c.position = {0, 1, 5};
    c.target = {0, 1, 0};
    const Camera q = orbitCamera(c, {0, 1, 0}, 90.0);
    EXPECT_NEAR(q.position.x, 5.0f, kEps);  // counter-clockwise seen from +Y: +Z goes to +X
    EXPECT_NEAR(q.position.y, 1.0f, kEps);
    EXPECT_NEAR(q.position.z, 0.0f, kEps);
    EXPECT_NEAR(glm::length(q.target - glm::vec3(0, 1, 0)), 0.0f, kEps);
    const Camera full = orbitCamera(c, {0, 1, 0}, 360.0);
    EXPECT_NEAR(glm::length(full.position - c.position), 0.0f, 1e-4f);
    EXPECT_DOUBLE_EQ(orbitDegrees(360.0, 6, 24), 90.0);
    EXPECT_DOUBLE_EQ(orbitDegrees(360.0, 0, 24), 0.0);
}

TEST(Animation, RigMovesWithTheCamera) {
    Camera c;
    RigParams p;
    p.columns = 4;
    p.interaxial = 0.2f;
    auto rig = makeRig(c, p);
    ASSERT_TRUE(rig);
    const Camera turned = orbitCamera(c, c.target, 90.0);
    auto moved = rigAt(*rig, turned);
    ASSERT_TRUE(moved);
    ASSERT_EQ(moved->viewCount(), 4);
    // The eyes lie on the turned camera's right axis (now -Z) at the same spacing.
    EXPECT_NEAR(glm::length(moved->views[1].eyeWorld - moved->views[0].eyeWorld), 0.2f, 1e-5f);
    EXPECT_NEAR(moved->views[0].eyeWorld.x, turned.position.x, 1e-5f);
    EXPECT_NEAR(moved->views[3].eyeWorld.z - moved->views[0].eyeWorld.z, -0.6f, 1e-5f);
    EXPECT_EQ(moved->convergence, rig->convergence);
}

TEST(Animation, CameraPathInterpolatesLinearlyAndClamps) {
    CameraPath path;
    path.keys.push_back({0.0, {0, 0, 10}, {0, 0, 0}, 40.0f});
    path.keys.push_back({2.0, {10, 0, 0}, {0, 2, 0}, std::nullopt});
    ASSERT_TRUE(validateCameraPath(path));
    Camera base;
    base.fovYDegrees = 60.0f;
    const Camera mid = cameraAt(path, 1.0, base);
    EXPECT_NEAR(mid.position.x, 5.0f, kEps);
    EXPECT_NEAR(mid.position.z, 5.0f, kEps);
    EXPECT_NEAR(mid.target.y, 1.0f, kEps);
    EXPECT_NEAR(mid.fovYDegrees, 50.0f, kEps);  // 40 .. the base's 60
    EXPECT_NEAR(cameraAt(path, -1.0, base).position.z, 10.0f, kEps);
    EXPECT_NEAR(cameraAt(path, 5.0, base).position.x, 10.0f, kEps);
    EXPECT_NEAR(cameraAt(path, 5.0, base).fovYDegrees, 60.0f, kEps);
}

TEST(Animation, BadCameraPathsNameTheKey) {
    CameraPath empty;
    EXPECT_FALSE(validateCameraPath(empty));
    CameraPath back;
    back.keys.push_back({1.0, {0, 0, 5}, {0, 0, 0}, std::nullopt});
    back.keys.push_back({0.5, {0, 0, 6}, {0, 0, 0}, std::nullopt});
    const Status s = validateCameraPath(back);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("key 1"), std::string::npos) << s.message();
    CameraPath same;
    same.keys.push_back({0.0, {1, 1, 1}, {1, 1, 1}, std::nullopt});
    EXPECT_FALSE(validateCameraPath(same));
    CameraPath fov;
    fov.keys.push_back({0.0, {0, 0, 5}, {0, 0, 0}, 190.0f});
    EXPECT_FALSE(validateCameraPath(fov));
}

TEST(Animation, LinearAndStepSamplers) {
    Sampler s;
    s.input = {0.0f, 1.0f, 3.0f};
    s.output = {0, 0, 0, 2, 4, 6, 2, 4, 10};
    ASSERT_TRUE(validateSampler(s));
    glm::vec3 v = sampleVec3(s, 0.5);
    EXPECT_NEAR(v.x, 1.0f, kEps);
    EXPECT_NEAR(v.y, 2.0f, kEps);
    EXPECT_NEAR(v.z, 3.0f, kEps);
    EXPECT_NEAR(sampleVec3(s, 2.0).z, 8.0f, kEps);
    EXPECT_NEAR(sampleVec3(s, -1.0).z, 0.0f, kEps);
    EXPECT_NEAR(sampleVec3(s, 9.0).z, 10.0f, kEps);
    s.interpolation = Interpolation::Step;
    EXPECT_NEAR(sampleVec3(s, 0.99).x, 0.0f, kEps);
    EXPECT_NEAR(sampleVec3(s, 1.0).x, 2.0f, kEps);
    EXPECT_NEAR(sampleVec3(s, 2.9).z, 6.0f, kEps);
}

TEST(Animation, RotationSlerpsAlongTheShorterArc) {
    Sampler r;
    r.rotation = true;
    r.components = 4;
    r.input = {0.0f, 1.0f};
    const glm::quat a = glm::angleAxis(0.0f, glm::vec3(0, 1, 0));
    const glm::quat b = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
    // b given with the opposite sign: the same rotation, the long way round if not flipped.
    r.output = {a.x, a.y, a.z, a.w, -b.x, -b.y, -b.z, -b.w};
    ASSERT_TRUE(validateSampler(r));
    const glm::quat mid = sampleRotation(r, 0.5);
    EXPECT_NEAR(glm::degrees(glm::angle(mid)), 45.0f, 1e-3f);
    const glm::vec3 axis = glm::axis(mid);
    EXPECT_NEAR(std::abs(axis.y), 1.0f, 1e-4f);
    r.interpolation = Interpolation::Step;
    EXPECT_NEAR(glm::degrees(glm::angle(sampleRotation(r, 0.5))), 0.0f, 1e-3f);
}

TEST(Animation, CubicSplineSamplerIsGltfsHermite) {
    // Keys (0 s: value 1, out-tangent 2) and (2 s: in-tangent -1, value 3); per key the output
    // holds in-tangent, value, out-tangent.
    Sampler s;
    s.components = 1;
    s.interpolation = Interpolation::CubicSpline;
    s.input = {0.0f, 2.0f};
    s.output = {9.0f, 1.0f, 2.0f, -1.0f, 3.0f, 9.0f};
    ASSERT_TRUE(validateSampler(s));
    // At 0.5 s, u = 0.25: the Hermite basis by hand is h00 = 0.84375, h10 = 0.140625,
    // h01 = 0.15625, h11 = -0.046875, so p = 0.84375·1 + 0.140625·2·2 + 0.15625·3 +
    // (-0.046875)·2·(-1) = 1.96875.
    EXPECT_NEAR(sample(s, 0.5)[0], 1.96875f, kEps);
    EXPECT_NEAR(sample(s, 0.0)[0], 1.0f, kEps);   // the value, not the in-tangent
    EXPECT_NEAR(sample(s, 2.0)[0], 3.0f, kEps);
    EXPECT_NEAR(sample(s, 10.0)[0], 3.0f, kEps);  // past the end: the last value holds
    s.output.pop_back();
    EXPECT_FALSE(validateSampler(s));  // 3 values per key and component
}

TEST(Animation, BadSamplersAreRefused) {
    Sampler s;
    EXPECT_FALSE(validateSampler(s));
    s.input = {0.0f, 0.0f};
    s.output = {0, 0, 0, 1, 1, 1};
    EXPECT_FALSE(validateSampler(s));  // not increasing
    s.input = {0.0f, 1.0f};
    s.output = {0, 0, 0};
    EXPECT_FALSE(validateSampler(s));  // too few values
    s.output = {0, 0, 0, 1, 1, 1};
    s.rotation = true;
    EXPECT_FALSE(validateSampler(s));  // a rotation of 3 components
}

TEST(Animation, NodeMatrixIsTranslationRotationScale) {
    NodeAnimation n;
    Sampler t;
    t.input = {0.0f, 1.0f};
    t.output = {0, 0, 0, 2, 0, 0};
    n.translation = t;
    n.restScale = {2, 2, 2};
    const glm::mat4 m = nodeMatrixAt(n, 0.5);
    const glm::vec4 p = m * glm::vec4(1, 0, 0, 1);
    EXPECT_NEAR(p.x, 3.0f, kEps);  // scaled to 2, then moved by 1
}

}  // namespace
}  // namespace mvr
