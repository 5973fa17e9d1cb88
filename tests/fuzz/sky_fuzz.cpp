// tests/fuzz/sky_fuzz.cpp — mvr::loadSky() (`mvr render --sky FILE`, scene_io.h: mvr's PNG and
// JPEG decoders; until this target found an out-of-bounds write in it, stb_image) on one
// file, then skyColor() in the six axis directions and a diagonal. A sky that comes back must be as large as it says,
// of the aspect its kind needs, and give finite colors.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("sky", data, size);
    mvr::Result<mvr::Sky> sky = mvr::loadSky(path.string());
    if (!sky) return 0;
    const mvr::Image& im = sky->image;
    if (im.empty() || im.rgba.size() != std::size_t(im.width) * std::size_t(im.height) * 4)
        std::abort();
    if (sky->kind == mvr::Sky::Kind::Equirect ? im.width != 2 * im.height
                                              : (sky->kind != mvr::Sky::Kind::CubeCross ||
                                                 im.width * 3 != im.height * 4))
        std::abort();
    for (glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0),
                        glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0, 0, -1),
                        glm::vec3(0.3f, -0.5f, 0.8f)}) {
        const glm::vec3 c = mvr::skyColor(*sky, d);
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) std::abort();
    }
    return 0;
}
