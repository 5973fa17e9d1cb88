// tests/gl/gl_test_util.h — shared fixtures of the GL tests: one backend per process (one EGL
// context); small scenes, rigs and image-difference helpers from the conformance suite's
// tests/support/test_scenes.h.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

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
using ::mvr::test::rigFor;
using ::mvr::test::sharedDir;
using ::mvr::test::suzanneScene;

}  // namespace mvr::gl::test
