// mvr/core/platform.h — facts about the machine, for benchmark and `mvr info` lines.
#pragma once

#include <string>

namespace mvr {

/// The CPU's model name from /proc/cpuinfo ("unknown CPU" where there is none).
std::string cpuModelName();

/// Process-wide allocator policy for rendering many frames: freed memory stays in the process
/// (glibc: no heap trimming; blocks up to the largest mmap threshold come from the heap), so
/// buffers that are allocated and freed every frame do not page-fault every frame. Measured on
/// Mesa llvmpipe, whose draw module allocates its vertex buffers per draw: the 625k-triangle
/// stereo pair drops from ~400 ms to ~110 ms. An application's policy, so the library never calls
/// it on its own: `mvr` calls it first thing in main(). Returns false where it has no effect
/// (another C library, or glibc refused the settings).
bool retainFreedMemory();

}  // namespace mvr
