#include "thread_pool.h"

#include <exception>
#include <utility>

#include <pthread.h>
#include <sched.h>

namespace mvr::raster::detail {

namespace {
std::vector<int> allowedCpus() {
    std::vector<int> cpus;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof(set), &set) == 0) {
        for (int c = 0; c < CPU_SETSIZE; ++c) {
            if (CPU_ISSET(c, &set)) cpus.push_back(c);
        }
    }
    return cpus;
}
}  // namespace

int availableCpus() {
    const auto cpus = allowedCpus();
    if (!cpus.empty()) return static_cast<int>(cpus.size());
    const unsigned n = std::thread::hardware_concurrency();
    return n > 0 ? static_cast<int>(n) : 1;
}

ThreadPool::ThreadPool(int threads) {
    const std::vector<int> cpus = allowedCpus();
    if (threads <= 0) threads = availableCpus();
    mPinned = !cpus.empty() && threads <= static_cast<int>(cpus.size());
    for (int i = 0; i < threads; ++i) {
        mWorkers.emplace_back([this, i] { workerLoop(i); });
        if (!cpus.empty()) {
            cpu_set_t set;
            CPU_ZERO(&set);
            CPU_SET(cpus[static_cast<std::size_t>(i) % cpus.size()], &set);
            if (pthread_setaffinity_np(mWorkers.back().native_handle(), sizeof(set), &set) != 0) {
                mPinned = false;
            }
        }
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_all();
    for (std::thread& t : mWorkers) t.join();
}

void ThreadPool::run(int taskCount, const std::function<void(int, int)>& fn) {
    if (taskCount <= 0) return;
    std::unique_lock lock(mMutex);
    mFn = &fn;
    mTaskCount = taskCount;
    mNext.store(0, std::memory_order_relaxed);
    mBusy = size();
    ++mGeneration;
    mWake.notify_all();
    mDone.wait(lock, [this] { return mBusy == 0; });
    mFn = nullptr;
    if (mError) std::rethrow_exception(std::exchange(mError, nullptr));
}

void ThreadPool::workerLoop(int worker) {
    std::uint64_t seen = 0;
    for (;;) {
        const std::function<void(int, int)>* fn;
        int count;
        {
            std::unique_lock lock(mMutex);
            mWake.wait(lock, [&] { return mStop || mGeneration != seen; });
            if (mStop) return;
            seen = mGeneration;
            fn = mFn;
            count = mTaskCount;
        }
        try {
            for (int task = mNext.fetch_add(1); task < count; task = mNext.fetch_add(1)) {
                (*fn)(task, worker);
            }
        } catch (...) {          // e.g. std::bad_alloc: rethrown by run() on the caller's thread
            mNext.store(count);  // the other workers claim nothing more
            std::lock_guard lock(mMutex);
            if (!mError) mError = std::current_exception();
        }
        std::lock_guard lock(mMutex);
        if (--mBusy == 0) mDone.notify_one();
    }
}

}  // namespace mvr::raster::detail
