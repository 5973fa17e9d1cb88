// mvr/core/platform.h — facts about the machine, for benchmark and `mvr info` lines.
#pragma once

#include <string>

namespace mvr {

/// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
std::string cpuModelName();

}  // namespace mvr
