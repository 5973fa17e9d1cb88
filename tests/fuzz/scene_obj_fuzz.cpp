// tests/fuzz/scene_obj_fuzz.cpp — mvr::loadScene() (scene_io.h) on an OBJ as a scene: the
// fuzz input as the OBJ, beside a fixed, valid material library (input.mtl: a textured
// material over tex.png, a plain one, a translucent one) that it may name with `mtllib
// input.mtl` and `usemtl`. The OBJ-with-materials path (one instance per material, texture
// coordinates, textures read through mvr's PNG decoder) is what the other targets do not
// reach: obj fuzzes loadMesh(), mtl_reader the MTL text. Every scene that comes back must
// pass validateScene().
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/core/image.h"
#include "mvr/io/mesh_io.h"
#include "mvr/io/png.h"
#include "mvr/io/scene_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool ready = [] {
        mvr::fuzz::writeScratch("input.mtl",
                                "newmtl red\nKd 1 0 0\nmap_Kd tex.png\n"
                                "newmtl blue\nKd 0 0 1\nNs 32\nKs 0.5 0.5 0.5\n"
                                "newmtl glass\nKd 0.8 0.9 1\nd 0.4\n");
        mvr::Image tex(4, 2, {200, 100, 50, 255});
        tex.set(1, 1, {0, 0, 0, 128});
        return bool(mvr::writePng(mvr::fuzz::scratchDir() / "tex.png", tex));
    }();
    if (!ready) std::abort();
    const auto path = mvr::fuzz::writeScratch("input.obj", data, size);
    mvr::Result<mvr::Scene> scene = mvr::loadScene(path);
    if (scene && !mvr::validateScene(*scene)) std::abort();
    return 0;
}
