// tests/gl/gl_test_util.h — shared fixtures of the GL tests: one backend per process (one EGL
// context), small scenes and rigs, image-difference helpers.
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

namespace mvr::gl::test {

inline mvr::Backend& backend() {
    static std::unique_ptr<mvr::Backend> b = makeGlBackend();
    return *b;
}

/// Skips the current test when no GL context can be made here.
#define MVR_SKIP_WITHOUT_GL()                                                          \
    do {                                                                               \
        const ::mvr::Status glStatus_ = ::mvr::gl::test::backend().supports("multipass"); \
        if (!glStatus_) GTEST_SKIP() << glStatus_.message();                           \
    } while (0)

inline std::filesystem::path sharedDir() {
    const char* d = std::getenv("MVR_SHARED_DIR");
    return d ? d : "../shared";
}

/// The procedural default scene (no files needed): spheres, torus, boxes, ground.
inline const Scene& defaultScene() {
    static const Scene s = makeDefaultScene();
    return s;
}

/// Suzanne from shared/models, or nullptr when the file is not there.
inline const Scene* suzanneScene() {
    static const std::unique_ptr<Scene> s = []() -> std::unique_ptr<Scene> {
        auto m = loadMesh(sharedDir() / "models" / "suzanne.obj");
        if (!m) return nullptr;
        std::vector<Mesh> meshes;
        meshes.push_back(std::move(m).value());
        return std::make_unique<Scene>(makeGridScene(std::move(meshes), 1));
    }();
    return s.get();
}

/// A camera framing `scene`, looking down −Z at its centre.
inline Camera cameraFor(const Scene& scene, float aspect) {
    const Bounds b = scene.bounds();
    Camera c;
    const float r = b.radius();
    c.target = b.center();
    c.position = b.center() + glm::vec3(0.0f, 0.25f * r, 2.6f * r);
    c.aspect = aspect;
    c.near = 0.05f * r;
    c.far = 10.0f * r;
    return c;
}

inline Rig rigFor(const Scene& scene, int columns, int rows, float aspect = 4.0f / 3.0f) {
    const Camera cam = cameraFor(scene, aspect);
    RigParams p;
    p.columns = columns;
    p.rows = rows;
    const float dist = glm::length(cam.position - cam.target);
    p.convergence = dist;
    p.interaxial = 0.06f * dist;  // exaggerated so that the eyes really differ
    p.interaxialY = 0.03f * dist;
    auto rig = makeRig(cam, p);
    EXPECT_TRUE(rig) << rig.status().message();
    return rig ? *rig : Rig{};
}

/// Fraction of depth pixels that differ by more than `eps`.
inline double depthMismatch(const DepthImage& a, const DepthImage& b, float eps, float* maxDiff) {
    if (a.width != b.width || a.height != b.height) return 1.0;
    long bad = 0;
    float worst = 0.0f;
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const float d = std::abs(a.depth[i] - b.depth[i]);
        worst = std::max(worst, d);
        if (d > eps) ++bad;
    }
    if (maxDiff) *maxDiff = worst;
    return static_cast<double>(bad) / static_cast<double>(a.depth.size());
}

}  // namespace mvr::gl::test
