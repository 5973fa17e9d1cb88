// src/core/parallel.h — mvr::core's one way to spread independent items over the machine's
// cores (the environment map's rows, the anti-aliasing passes' views): plain threads, started
// per call, each item written by one thread, so a result never depends on the thread count.
#pragma once

#include <algorithm>
#include <functional>
#include <system_error>
#include <thread>
#include <vector>

namespace mvr::detail {

/// Runs body(i) for i in [0, count): on this thread when `parallel` is false or count is 1,
/// else on up to one thread per core (at most 16), item i on thread i mod threads. A thread
/// that cannot start leaves its items to this one.
inline void parallelFor(int count, bool parallel, const std::function<void(int)>& body) {
    if (!parallel || count <= 1) {
        for (int i = 0; i < count; ++i) body(i);
        return;
    }
    const int threads =
        std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, std::min(count, 16)));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t) {
        try {
            pool.emplace_back([&, t] {
                for (int i = t; i < count; i += threads) body(i);
            });
        } catch (const std::system_error&) {
            for (int i = t; i < count; i += threads) body(i);
        }
    }
    for (std::thread& th : pool) th.join();
}

}  // namespace mvr::detail
