// tests/fuzz/mpo_fuzz.cpp — an MPO (CIPA DC-007) in memory: composite::mpoImageRanges() (the MP
// Index IFD: byte order, entry counts and offsets) and composite::decodeMpo() (every image).
#include <cstdint>
#include <cstdlib>
#include <span>

#include "mvr/composite/jpeg.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    auto ranges = mvr::composite::mpoImageRanges(bytes, "fuzz");
    if (ranges) {
        for (const auto& r : *ranges)
            if (r.offset > size || r.size > size - r.offset) std::abort();  // inside the file
    }
    auto views = mvr::composite::decodeMpo(bytes, "fuzz");
    if (views && views->empty()) std::abort();
    return 0;
}
