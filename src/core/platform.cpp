#include "mvr/core/platform.h"

#include <fstream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace mvr {

std::string cpuModelName() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            const auto start =
                colon == std::string::npos ? colon : line.find_first_not_of(' ', colon + 1);
            if (start != std::string::npos) return line.substr(start);
        }
    }
    return "unknown CPU";
}

bool retainFreedMemory() {
#if defined(__GLIBC__)
    // Both settings are needed: without the trim threshold a freed block at the top of the heap
    // is returned to the kernel and faulted back in; without the mmap threshold glibc serves big
    // blocks with mmap and unmaps them on free. 32 MiB is the largest threshold glibc accepts.
    const bool trim = mallopt(M_TRIM_THRESHOLD, 1 << 30) == 1;
    const bool mmap = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1;
    return trim && mmap;
#else
    return false;
#endif
}

}  // namespace mvr
