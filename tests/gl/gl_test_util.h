// tests/gl/gl_test_util.h — shared fixtures of the GL tests: one backend per process (one EGL
// context); small scenes, rigs and image-difference helpers from the conformance suite's
// tests/support/test_scenes.h.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/scene.h"
#include "mvr/gl/gl_backend.h"
#include "../conformance/gl_requirements.h"
#include "test_scenes.h"
#include "mvr_test_support.h"

namespace mvr::gl::test {

inline mvr::Backend& backend() {
    static std::unique_ptr<mvr::Backend> b = makeGlBackend();
    return *b;
}

/// Skips the current test when no GL context can be made here.
/// Fails instead under MVR_REQUIRE_GL=1 (CI), and when MVR_REQUIRE_GL_DRIVER names another
/// driver than the one running (tests/conformance/gl_requirements.h).
#define MVR_SKIP_WITHOUT_GL()                                                                     \
    do {                                                                                          \
        const ::mvr::Status glStatus_ = ::mvr::gl::test::backend().supports("multipass");         \
        if (!glStatus_ && ::mvr::test::requireGl())                                               \
            FAIL() << "MVR_REQUIRE_GL=1: " << glStatus_.message();                                \
        if (!glStatus_) MVR_SKIP(NoGlContext) << glStatus_.message();                                      \
        const std::string wrong_ = ::mvr::test::wrongGlDriver(::mvr::gl::test::backend().info()); \
        if (!wrong_.empty()) FAIL() << wrong_;                                                    \
    } while (0)

// The scenes, rigs and measures the cross-backend tests share (tests/support/test_scenes.h).
using ::mvr::test::cameraFor;
using ::mvr::test::defaultScene;
using ::mvr::test::depthMismatch;
/// A unit quad in the XY plane facing +Z, texture coordinates (0, 0) at its top left.
inline Mesh quadMesh() {
    Mesh m;
    m.name = "quad";
    m.positions = {{-1, 1, 0}, {1, 1, 0}, {1, -1, 0}, {-1, -1, 0}};
    m.normals.assign(4, glm::vec3(0, 0, 1));
    m.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.indices = {0, 3, 2, 0, 2, 1};
    return m;
}

/// One view from (0, 0, 2) looking at the origin, 60° high, of a 160 × 120 image's aspect
/// (the textured, surface-map and environment tests' size).
inline Rig monoRig() {
    Camera cam;
    cam.position = {0, 0, 2.0f};
    cam.target = {0, 0, 0};
    cam.fovYDegrees = 60.0f;
    cam.aspect = 160.0f / 120.0f;
    RigParams p;
    p.columns = 1;
    p.rows = 1;
    p.convergence = 2.0f;
    p.interaxial = 0.0f;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

/// The backend's methods that draw every view exactly (not auto, gs-mrt, gs-depthmap).
inline std::vector<std::string> exactMethods() {
    std::vector<std::string> out;
    for (const std::string& m : backend().methods()) {
        if (m != "auto" && m != "gs-mrt" && m != "gs-depthmap") out.push_back(m);
    }
    return out;
}

using ::mvr::test::rigFor;
using ::mvr::test::sharedDir;
using ::mvr::test::suzanneScene;

}  // namespace mvr::gl::test
