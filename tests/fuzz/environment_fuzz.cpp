// tests/fuzz/environment_fuzz.cpp — mvr::loadEnvironmentMap() (`mvr render --environment FILE`,
// scene_io.h: mvr's own Radiance RGBE decoder, OpenEXR, PNG, JPEG; a cube cross resampled) on
// one file. A map that comes back must be 2:1, as large as it says, with finite non-negative
// texels; a small one is built for lighting (buildEnvironment) and looked up.
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/core/environment.h"
#include "mvr/io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("environment", data, size);
    mvr::Result<mvr::RadianceMap> map = mvr::loadEnvironmentMap(path.string());
    if (!map) return 0;
    if (map->width != 2 * map->height || map->height < 1 ||
        map->texels.size() != std::size_t(map->width) * std::size_t(map->height))
        std::abort();
    for (const glm::vec3& c : map->texels) {
        if (!(c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f) || !std::isfinite(c.x + c.y + c.z))
            std::abort();
    }
    if (map->width > 256) return 0;  // building a large one only costs time
    const mvr::Environment env = mvr::buildEnvironment(*map);
    for (glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, -1),
                        glm::vec3(0.36f, -0.48f, 0.8f)}) {
        const glm::vec3 a = mvr::diffuseLight(env, d), b = mvr::prefiltered(env, d, 0.3f);
        if (!(a.x >= 0.0f) || !(b.x >= 0.0f)) std::abort();
    }
    return 0;
}
