// tests/fuzz/jps_fuzz.cpp — composite::readViewFile() on a .jps file: the signature sniff (PNG,
// JPEG), the JPEG decode and splitJps() into {left, right}, as `mvr compose` reads it.
#include <cstdint>
#include <cstdlib>

#include "fuzz_util.h"
#include "mvr/composite/compose.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto path = mvr::fuzz::writeScratch("input.jps", data, size);
    auto views = mvr::composite::readViewFile(path);
    if (views && views->empty()) std::abort();
    return 0;
}
