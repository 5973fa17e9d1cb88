// src/raster/thread_pool.h — worker threads pinned to cores, for the soft backend's passes.
//
// Why pinned: on the VMs mvr is measured on, unpinned worker threads were seen packed onto one
// core; each worker is bound (pthread_setaffinity_np) to one CPU of the process's affinity set.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mvr::raster::detail {

class ThreadPool {
public:
    /// `threads` <= 0: one worker per CPU this process may run on.
    explicit ThreadPool(int threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    int size() const { return static_cast<int>(mWorkers.size()); }
    /// True when every worker was bound to its own CPU.
    bool pinned() const { return mPinned; }

    /// Runs fn(task, worker) for task = 0..taskCount-1 on the workers (tasks are claimed in
    /// increasing order, dynamically); returns when all have finished. Not reentrant. A task
    /// that throws (std::bad_alloc: a frame too large for this machine) stops the claiming of
    /// further tasks, and run() rethrows its exception on the caller's thread once every
    /// worker is idle.
    void run(int taskCount, const std::function<void(int task, int worker)>& fn);

private:
    void workerLoop(int worker);

    std::vector<std::thread> mWorkers;
    std::mutex mMutex;
    std::condition_variable mWake, mDone;
    const std::function<void(int, int)>* mFn = nullptr;
    int mTaskCount = 0;
    std::atomic<int> mNext{0};
    int mBusy = 0;
    std::uint64_t mGeneration = 0;
    bool mStop = false;
    bool mPinned = false;
    std::exception_ptr mError;  ///< the first exception a task of this run() threw
};

/// CPUs in this process's affinity set (at least 1).
int availableCpus();

}  // namespace mvr::raster::detail
