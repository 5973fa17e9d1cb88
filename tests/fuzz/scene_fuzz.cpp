// tests/fuzz/scene_fuzz.cpp — mvr::loadScene() (scene_io.h) on one glTF / GLB file: the node
// hierarchy, materials, embedded (data-URI, GLB) images through the PNG and JPEG decoders,
// camera and lights. Built once per extension (MVR_FUZZ_EXTENSION). Every scene that comes
// back must pass validateScene().
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/io/scene_io.h"

#ifndef MVR_FUZZ_EXTENSION
#error "MVR_FUZZ_EXTENSION (e.g. \".gltf\") must be defined"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("input" MVR_FUZZ_EXTENSION, data, size);
    mvr::Result<mvr::Scene> scene = mvr::loadScene(path);
    if (scene && !mvr::validateScene(*scene)) std::abort();  // the loader's promise
    return 0;
}
