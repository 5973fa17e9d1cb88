// tests/fuzz/jpeg_fuzz.cpp — composite::decodeJpeg() (libjpeg-turbo, with mvr's error manager
// that turns libjpeg's longjmp errors and corrupt-data warnings into a Status) in memory.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "mvr/composite/jpeg.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    mvr::Result<mvr::Image> image = mvr::composite::decodeJpeg(std::span(data, size), "fuzz");
    if (image && (image->empty() ||
                  image->rgba.size() != std::size_t(image->width) * std::size_t(image->height) * 4))
        std::abort();
    return 0;
}
