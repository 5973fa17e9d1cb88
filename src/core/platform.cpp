#include "mvr/core/platform.h"

#include <fstream>

namespace mvr {

std::string cpuModelName() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            const auto start = colon == std::string::npos ? colon : line.find_first_not_of(' ', colon + 1);
            if (start != std::string::npos) return line.substr(start);
        }
    }
    return "unknown CPU";
}

}  // namespace mvr
