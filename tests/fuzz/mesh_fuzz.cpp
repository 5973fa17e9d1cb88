// tests/fuzz/mesh_fuzz.cpp — mvr::loadMesh() on one model file: OBJ, PLY (mvr's own reader),
// glTF, GLB (assimp). Built once per format with MVR_FUZZ_EXTENSION set to the extension the
// input is saved under, since that is how the loader and assimp pick the reader. Every mesh
// that comes back must hold what mesh.h promises.
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/core/mesh.h"
#include "mvr/io/mesh_io.h"

#ifndef MVR_FUZZ_EXTENSION
#error "MVR_FUZZ_EXTENSION (e.g. \".obj\") must be defined"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("input" MVR_FUZZ_EXTENSION, data, size);
    mvr::Result<mvr::Mesh> mesh = mvr::loadMesh(path);
    if (mesh && !mvr::validateMesh(*mesh, "fuzz")) std::abort();  // the loader's promise
    return 0;
}
