// tests/fuzz/camera_path_fuzz.cpp — the keyframe file of `mvr render --camera-path FILE`
// (docs/animation.md) through mvr::cli::readCameraPath(), as `mvr` reads it, then cameraAt()
// before, at, between and after the keys. A path that comes back has passed
// validateCameraPath(): its cameras must be finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "camera_path.h"
#include "fuzz_util.h"

namespace {

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("path.json", data, size);
    mvr::Result<mvr::CameraPath> keys = mvr::cli::readCameraPath(path.string());
    if (!keys) return 0;
    if (keys->keys.empty() || !mvr::validateCameraPath(*keys)) std::abort();
    const mvr::Camera base;
    const double end = keys->duration();
    for (double t : {keys->keys.front().time - 1.0, keys->keys.front().time, end * 0.37, end,
                     end + 1.0}) {
        const mvr::Camera c = mvr::cameraAt(*keys, t, base);
        if (!finite(c.position) || !finite(c.target) || !std::isfinite(c.fovYDegrees)) std::abort();
    }
    return 0;
}
