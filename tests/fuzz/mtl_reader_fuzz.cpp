// tests/fuzz/mtl_reader_fuzz.cpp — mvr's own MTL reader (mvr::parseMtl, mtl.h): the fuzz input
// as MTL text. Whatever it is, the reader returns materials or an error, never a crash, and
// every color and dissolve it returns lies in [0, 1].
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mvr/io/mtl.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    mvr::Result<std::vector<mvr::MtlMaterial>> materials = mvr::parseMtl(text, "fuzz.mtl");
    if (!materials) {
        if (materials.status().message().empty()) std::abort();
        return 0;
    }
    for (const mvr::MtlMaterial& m : *materials) {
        for (int c = 0; c < 3; ++c)
            if (!(m.diffuse[c] >= 0.0f && m.diffuse[c] <= 1.0f)) std::abort();
        if (!(m.dissolve >= 0.0f && m.dissolve <= 1.0f) || m.name.empty()) std::abort();
    }
    return 0;
}
