// tests/fuzz/png_fuzz.cpp — mvr::readPng() (libpng's simplified API, any bit depth and color
// type to RGBA8) on one file; an image that comes back must be as large as it says.
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/core/image.h"
#include "mvr/io/png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("input.png", data, size);
    mvr::Result<mvr::Image> image = mvr::readPng(path);
    if (image && (image->empty() ||
                  image->rgba.size() != std::size_t(image->width) * std::size_t(image->height) * 4))
        std::abort();
    return 0;
}
