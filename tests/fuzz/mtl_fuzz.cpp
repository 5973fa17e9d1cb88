// tests/fuzz/mtl_fuzz.cpp — an OBJ's material library: a fixed, valid OBJ that names
// input.mtl, and the fuzz input as that MTL file, through mvr::loadMesh() (assimp's MTL parser
// runs while the OBJ loads; mvr draws no materials, but a bad MTL must not crash the load).
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/core/mesh.h"
#include "mvr/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const auto obj = mvr::fuzz::writeScratch(
        "input.obj",
        "mtllib input.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
        "usemtl red\nf 1/1 2/2 3/3\nusemtl blue\nf 3/3 2/2 1/1\n");
    mvr::fuzz::writeScratch("input.mtl", data, size);
    mvr::Result<mvr::Mesh> mesh = mvr::loadMesh(obj);
    if (mesh && !mvr::validateMesh(*mesh, "fuzz")) std::abort();
    return 0;
}
