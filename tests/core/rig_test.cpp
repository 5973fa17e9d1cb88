// Property tests of the rigs over seeded random cameras, rigs and points.
#include "mvr/core/rig.h"

#include <random>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace mvr {
namespace {

struct RandomRig {
    Camera camera;
    RigParams params;
};

RandomRig randomRig(std::mt19937& rng, RigKind kind, int columns, int rows = 1) {
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    RandomRig r;
    r.camera.position = glm::vec3(u(rng), u(rng), u(rng)) * 5.0f;
    r.camera.target =
        r.camera.position + glm::normalize(glm::vec3(u(rng), u(rng) * 0.5f, -1.0f)) * 4.0f;
    r.camera.fovYDegrees = 30.0f + 40.0f * (u(rng) * 0.5f + 0.5f);
    r.camera.aspect = 1.0f + 0.8f * (u(rng) * 0.5f + 0.5f);
    r.camera.near = 0.2f + 0.3f * (u(rng) * 0.5f + 0.5f);
    r.camera.far = 50.0f + 50.0f * (u(rng) * 0.5f + 0.5f);
    r.params.kind = kind;
    r.params.columns = columns;
    r.params.rows = rows;
    r.params.convergence = 2.0f + 8.0f * (u(rng) * 0.5f + 0.5f);
    r.params.interaxial = r.params.convergence / (20.0f + 20.0f * (u(rng) * 0.5f + 0.5f));
    return r;
}

/// A random point inside the mono camera's frustum, at eye-space distance in [near·1.5, far/2].
glm::vec3 randomPointInView(std::mt19937& rng, const Camera& c) {
    std::uniform_real_distribution<float> u(-0.9f, 0.9f);
    std::uniform_real_distribution<float> dist(c.near * 1.5f, c.far * 0.5f);
    const glm::mat4 worldFromClip = glm::inverse(c.clipFromView() * c.viewFromWorld());
    const float w = dist(rng);
    // Clip position with that w: ndc z for distance w.
    const float n = c.near, f = c.far;
    const float ndcZ = ((f + n) - 2.0f * f * n / w) / (f - n);
    glm::vec4 p = worldFromClip * glm::vec4(u(rng), u(rng), ndcZ, 1.0f);
    return glm::vec3(p) / p.w;
}

float relTol(float v) { return 2e-4f * std::max(1.0f, std::abs(v)); }

TEST(Rig, OffAxisMatchesNvidiaClipSpaceForm) {
    std::mt19937 rng(1);
    for (int trial = 0; trial < 200; ++trial) {
        RandomRig rr = randomRig(rng, RigKind::OffAxis, 2);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig) << rig.status().message();
        const float separation = rig->separation();
        EXPECT_NEAR(
            separation,
            separationFromInteraxial(rr.camera, rr.params.interaxial, rr.params.convergence),
            1e-6f);
        EXPECT_NEAR(interaxialFromSeparation(rr.camera, separation, rr.params.convergence),
                    rr.params.interaxial, 1e-5f);
        const glm::mat4 mono = rr.camera.clipFromView() * rr.camera.viewFromWorld();
        for (int k = 0; k < 10; ++k) {
            const glm::vec3 p = randomPointInView(rng, rr.camera);
            const glm::vec4 monoClip = mono * glm::vec4(p, 1.0f);
            for (int eye = 0; eye < 2; ++eye) {
                const float eyeSign = eye == 0 ? -1.0f : 1.0f;
                const glm::vec4 expected =
                    applyClipSpaceStereo(monoClip, eyeSign, separation, rig->convergence);
                const glm::vec4 actual = rig->views[eye].clipFromWorld() * glm::vec4(p, 1.0f);
                for (int c = 0; c < 4; ++c) {
                    EXPECT_NEAR(actual[c], expected[c], relTol(expected.w))
                        << "trial " << trial << " eye " << eye << " c " << c;
                }
                // The stored clip shear gives the same position.
                ASSERT_TRUE(rig->views[eye].clipShear.has_value());
                EXPECT_NEAR(rig->views[eye].clipShear->x, eyeSign * separation, 1e-6f);
            }
        }
    }
}

TEST(Rig, OffAxisRowSharesClipYZW) {
    std::mt19937 rng(2);
    for (int trial = 0; trial < 100; ++trial) {
        RandomRig rr = randomRig(rng, RigKind::OffAxis, 2 + trial % 8);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig);
        for (int k = 0; k < 10; ++k) {
            const glm::vec3 p = randomPointInView(rng, rr.camera);
            const glm::vec4 ref = rig->views[0].clipFromWorld() * glm::vec4(p, 1.0f);
            for (int v = 1; v < rig->viewCount(); ++v) {
                const glm::vec4 c = rig->views[v].clipFromWorld() * glm::vec4(p, 1.0f);
                EXPECT_NEAR(c.y, ref.y, relTol(ref.w));
                EXPECT_NEAR(c.z, ref.z, relTol(ref.w));
                EXPECT_NEAR(c.w, ref.w, relTol(ref.w));
            }
        }
    }
}

TEST(Rig, ParallaxZeroAtConvergenceAndChangesSign) {
    std::mt19937 rng(3);
    for (int trial = 0; trial < 100; ++trial) {
        RandomRig rr = randomRig(rng, RigKind::OffAxis, 2);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig);
        const glm::mat4 worldFromView = glm::inverse(rr.camera.viewFromWorld());
        std::uniform_real_distribution<float> u(-0.5f, 0.5f);
        auto pointAt = [&](float w) {
            return glm::vec3(worldFromView *
                             glm::vec4(u(rng) * w * 0.3f, u(rng) * w * 0.3f, -w, 1.0f));
        };
        const float conv = rig->convergence;
        EXPECT_NEAR(parallax(*rig, pointAt(conv), 0, 1), 0.0f, 2e-5f);
        const float nearW = conv * 0.7f, farW = conv * 3.0f;
        const float pNear = parallax(*rig, pointAt(nearW), 0, 1);
        const float pFar = parallax(*rig, pointAt(farW), 0, 1);
        EXPECT_LT(pNear, 0.0f);  // in front of the screen
        EXPECT_GT(pFar, 0.0f);   // behind it
        const float sep = rig->separation();
        EXPECT_NEAR(pNear, sep * (1.0f - conv / nearW), 2e-5f);
        EXPECT_NEAR(pFar, sep * (1.0f - conv / farW), 2e-5f);
    }
}

TEST(Rig, OffAxisFrustumCornersLandOnNdcCorners) {
    std::mt19937 rng(4);
    for (int trial = 0; trial < 50; ++trial) {
        RandomRig rr = randomRig(rng, RigKind::OffAxis, 3, 2);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig);
        for (const View& v : rig->views) {
            // The corners of the eye's frustum in eye space, from the glFrustum bounds.
            const glm::mat4 viewFromClip = glm::inverse(v.clipFromView);
            for (int i = 0; i < 8; ++i) {
                const glm::vec4 ndc((i & 1) ? 1.f : -1.f, (i & 2) ? 1.f : -1.f,
                                    (i & 4) ? 1.f : -1.f, 1.f);
                const glm::vec4 eye = viewFromClip * ndc;
                const glm::vec4 back = v.clipFromView * eye;
                EXPECT_NEAR(back.x / back.w, ndc.x, 1e-4f);
                EXPECT_NEAR(back.y / back.w, ndc.y, 1e-4f);
                EXPECT_NEAR(back.z / back.w, ndc.z, 1e-3f);
                // near corners at distance near, far corners at far
                EXPECT_NEAR(-eye.z / eye.w, (i & 4) ? rr.camera.far : rr.camera.near,
                            1e-3f * rr.camera.far);
            }
            // All views share the window on the convergence plane: its corners project to NDC corners.
            const glm::mat4 worldFromView = glm::inverse(rr.camera.viewFromWorld());
            const float tanHalf = std::tan(glm::radians(rr.camera.fovYDegrees) * 0.5f);
            const float conv = rig->convergence;
            const glm::vec3 corner(worldFromView * glm::vec4(conv * tanHalf * rr.camera.aspect,
                                                             conv * tanHalf, -conv, 1.0f));
            const glm::vec4 c = v.clipFromWorld() * glm::vec4(corner, 1.0f);
            EXPECT_NEAR(c.x / c.w, 1.0f, 1e-4f);
            EXPECT_NEAR(c.y / c.w, 1.0f, 1e-4f);
        }
    }
}

TEST(Rig, EveryViewInsideCullingFrustum) {
    std::mt19937 rng(5);
    const RigKind kinds[] = {RigKind::OffAxis, RigKind::ToeIn, RigKind::Parallel};
    for (int trial = 0; trial < 90; ++trial) {
        RandomRig rr = randomRig(rng, kinds[trial % 3], 1 + trial % 5, 1 + trial % 3);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig);
        for (const View& v : rig->views) {
            for (const glm::vec3& corner : frustumCorners(v)) {
                EXPECT_TRUE(rig->cullingFrustum.contains(corner, 1e-3f * rr.camera.far))
                    << "trial " << trial;
            }
        }
        // And the culling frustum is not trivially everything: a point far behind the camera is out.
        const glm::vec3 behind =
            rr.camera.position + (rr.camera.position - rr.camera.target) * 10.0f;
        EXPECT_FALSE(rig->cullingFrustum.contains(behind));
        const glm::vec3 farOut =
            rr.camera.target + (rr.camera.target - rr.camera.position) * 1000.0f;
        EXPECT_FALSE(rig->cullingFrustum.contains(farOut));
    }
}

TEST(Rig, OneViewRigEqualsMonoCamera) {
    std::mt19937 rng(6);
    for (RigKind kind : {RigKind::OffAxis, RigKind::ToeIn, RigKind::Parallel}) {
        RandomRig rr = randomRig(rng, kind, 1);
        auto rig = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(rig);
        ASSERT_EQ(rig->viewCount(), 1);
        const glm::mat4 mono = rr.camera.clipFromView() * rr.camera.viewFromWorld();
        const glm::mat4 one = rig->views[0].clipFromWorld();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                EXPECT_NEAR(one[c][r], mono[c][r], 1e-5f * std::max(1.0f, std::abs(mono[c][r])));
    }
}

TEST(Rig, ToeInHasVerticalParallaxOffAxisHasNone) {
    std::mt19937 rng(7);
    float maxToeIn = 0.0f;
    for (int trial = 0; trial < 50; ++trial) {
        RandomRig rr = randomRig(rng, RigKind::OffAxis, 2);
        rr.params.interaxial = rr.params.convergence / 10.0f;
        auto offAxis = makeRig(rr.camera, rr.params);
        rr.params.kind = RigKind::ToeIn;
        auto toeIn = makeRig(rr.camera, rr.params);
        ASSERT_TRUE(offAxis && toeIn);
        // A point off the axis (near a corner of the view) away from the convergence plane.
        const glm::mat4 worldFromView = glm::inverse(rr.camera.viewFromWorld());
        const float w = rr.params.convergence * 2.0f;
        const float tanHalf = std::tan(glm::radians(rr.camera.fovYDegrees) * 0.5f);
        const glm::vec3 p(worldFromView * glm::vec4(0.7f * w * tanHalf * rr.camera.aspect,
                                                    0.7f * w * tanHalf, -w, 1.0f));
        auto ndcY = [&](const Rig& rig, int v) {
            const glm::vec4 c = rig.views[v].clipFromWorld() * glm::vec4(p, 1.0f);
            return c.y / c.w;
        };
        EXPECT_NEAR(ndcY(*offAxis, 0), ndcY(*offAxis, 1), 1e-5f);
        const float dy = std::abs(ndcY(*toeIn, 0) - ndcY(*toeIn, 1));
        EXPECT_GT(dy, 1e-4f);
        maxToeIn = std::max(maxToeIn, dy);
    }
    EXPECT_GT(maxToeIn, 1e-3f);
}

TEST(Rig, GridViewsNumberedLeftToRightTopToBottom) {
    Camera camera;
    RigParams p;
    p.columns = 3;
    p.rows = 2;
    p.interaxial = 0.2f;
    p.convergence = 5.0f;
    auto rig = makeRig(camera, p);
    ASSERT_TRUE(rig);
    ASSERT_EQ(rig->viewCount(), 6);
    EXPECT_LT(rig->views[0].eyeWorld.x, rig->views[1].eyeWorld.x);
    EXPECT_LT(rig->views[1].eyeWorld.x, rig->views[2].eyeWorld.x);
    EXPECT_GT(rig->views[0].eyeWorld.y, rig->views[3].eyeWorld.y);  // row 0 on top
    EXPECT_FLOAT_EQ(rig->views[0].eyeWorld.x, rig->views[3].eyeWorld.x);
}

TEST(Rig, RejectsBadParameters) {
    Camera camera;
    RigParams p;
    p.columns = 0;
    EXPECT_EQ(makeRig(camera, p).status().code(), ErrorCode::Usage);
    p.columns = kMaxViews + 1;
    EXPECT_NE(makeRig(camera, p).status().message().find("out of range"), std::string::npos);
    p.columns = 2;
    p.interaxial = std::nanf("");
    EXPECT_FALSE(makeRig(camera, p));
    p.interaxial = 0.1f;
    p.convergence = camera.near * 0.5f;
    EXPECT_FALSE(makeRig(camera, p));
    p.convergence = 5.0f;
    camera.fovYDegrees = 180.0f;
    EXPECT_FALSE(makeRig(camera, p));
    camera.fovYDegrees = 45.0f;
    camera.far = camera.near;
    EXPECT_FALSE(makeRig(camera, p));
    EXPECT_FALSE(parseRigKind("fisheye"));
    EXPECT_TRUE(parseRigKind("toein"));
}

TEST(Rig, ParallaxRangeComfort) {
    Camera camera;
    RigParams p;
    p.convergence = 4.0f;
    p.interaxial = 0.1f;
    auto rig = makeRig(camera, p);
    ASSERT_TRUE(rig);
    const ParallaxRange ok = parallaxRange(*rig, 3.0f, 10.0f);
    EXPECT_TRUE(ok.comfortable);
    EXPECT_LT(ok.minParallax, 0.0f);
    EXPECT_GT(ok.maxParallax, 0.0f);
    EXPECT_FALSE(parallaxRange(*rig, 1.0f, 10.0f).comfortable);   // closer than convergence/2
    EXPECT_FALSE(parallaxRange(*rig, 3.0f, 500.0f).comfortable);  // beyond 100 x convergence
    EXPECT_TRUE(ok.why.empty());
    EXPECT_EQ(parallaxRange(*rig, 1.0f, 10.0f).why, "scene reaches closer than convergence/2");
    // A separation of 5000 % of the screen width (--separation 50): the parallax at w = 3 is
    // 50 * (1 - 4/3) = -16.7 screen widths, computed here by hand.
    p.interaxial =
        50.0f * 2.0f * 4.0f * camera.aspect * std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    auto huge = makeRig(camera, p);
    ASSERT_TRUE(huge);
    const ParallaxRange bad = parallaxRange(*huge, 3.0f, 10.0f);
    EXPECT_NEAR(huge->separation(), 50.0f, 1e-3f);
    EXPECT_NEAR(bad.minParallax, 50.0f * (1.0f - 4.0f / 3.0f), 1e-2f);
    EXPECT_LT(bad.minParallax, -1.0f);
    EXPECT_FALSE(bad.comfortable);
    EXPECT_NE(bad.why.find("parallax beyond one screen width"), std::string::npos) << bad.why;
}

// View-cone rig (issue 13): view 0 leftmost, zero parallax on the focal plane, outer views at
// ±cone/2 to the focal-plane centre (computed here from the eye positions, not the rig code).
TEST(Rig, ViewConeSpreadsViewsEvenlyInAngle) {
    Camera camera;
    camera.position = glm::vec3(0.0f, 0.0f, 10.0f);
    camera.aspect = 0.75f;
    RigParams p;
    p.columns = 48;
    p.convergence = 10.0f;
    p.viewConeDegrees = 40.0f;
    Result<Rig> rig = makeRig(camera, p);
    ASSERT_TRUE(rig);
    ASSERT_EQ(rig->viewCount(), 48);
    const glm::vec3 focal(0.0f);
    for (int i = 0; i < 48; ++i) {
        const glm::vec3 e = rig->views[i].eyeWorld;
        const float angle = glm::degrees(std::atan2(e.x, e.z - focal.z));
        EXPECT_NEAR(angle, -20.0f + 40.0f * i / 47.0f, 1e-3f) << i;
        if (i > 0) {
            EXPECT_LT(rig->views[i - 1].eyeWorld.x, e.x);
        }
        for (const glm::vec3 q : {glm::vec3(1.0f, 0.5f, 0.0f), glm::vec3(-2.0f, -1.0f, 0.0f)})
            EXPECT_NEAR(parallax(*rig, q, 0, i), 0.0f, 1e-5f);
    }
    EXPECT_LT(parallax(*rig, glm::vec3(0.0f, 0.0f, -5.0f), 0, 47), 0.0f + 1.0f);
    EXPECT_GT(parallax(*rig, glm::vec3(0.0f, 0.0f, -5.0f), 0, 47), 0.0f);
    p.viewConeDegrees = 200.0f;
    EXPECT_FALSE(makeRig(camera, p));
}

// --depthiness (RigParams::coneSpread): the eyes' offsets C·tan(θ_i) scaled, every parallax with
// them (the off-axis parallax s·(1 − C/w) is linear in the spacing); 0: identical views.
TEST(Rig, ConeSpreadScalesTheEyesAndTheParallax) {
    Camera camera;
    camera.position = glm::vec3(0.0f, 0.0f, 10.0f);
    camera.aspect = 0.75f;
    RigParams p;
    p.columns = 9;
    p.convergence = 10.0f;
    p.viewConeDegrees = 40.0f;
    const Rig whole = *makeRig(camera, p);
    p.coneSpread = 0.5f;
    const Rig half = *makeRig(camera, p);
    const glm::vec3 far(0.3f, 0.2f, -6.0f);
    for (int i = 0; i < 9; ++i) {
        const float t = std::tan(glm::radians(-20.0f + 40.0f * float(i) / 8.0f));
        EXPECT_NEAR(whole.views[i].eyeWorld.x, 10.0f * t, 1e-4f) << i;
        EXPECT_NEAR(half.views[i].eyeWorld.x, 0.5f * 10.0f * t, 1e-4f) << i;
        EXPECT_NEAR(parallax(half, far, 0, i), 0.5f * parallax(whole, far, 0, i), 1e-5f) << i;
    }
    EXPECT_NEAR(half.interaxial, 0.5f * whole.interaxial, 1e-6f);
    p.coneSpread = 0.0f;
    const Rig flat = *makeRig(camera, p);
    for (int i = 1; i < 9; ++i) {
        EXPECT_EQ(flat.views[i].clipFromView, flat.views[0].clipFromView) << i;
        EXPECT_EQ(flat.views[i].viewFromWorld, flat.views[0].viewFromWorld) << i;
    }
    p.coneSpread = 2.5f;
    EXPECT_FALSE(makeRig(camera, p));
}

}  // namespace
}  // namespace mvr
