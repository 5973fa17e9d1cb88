// tools/viewer/render_worker.h — one thread that owns the rendering backends.
//
// Why a thread: the gl backend renders in its own EGL context, made current on the thread that
// calls it, while the window's GLX context is current on the main thread. With libglvnd a thread
// cannot have a GLX and an EGL context current at once (eglMakeCurrent fails with
// EGL_BAD_ACCESS), and switching them back and forth every frame is fragile. So every backend
// call — creation, supports(), render(), destruction — runs on this thread, synchronously.
#pragma once

#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>
#include <queue>
#include <thread>
#include <type_traits>

namespace mvr::viewer {

class RenderWorker {
public:
    RenderWorker();
    /// Runs the queued work, then stops the thread (destroy backends through call() first).
    ~RenderWorker();
    RenderWorker(const RenderWorker&) = delete;
    RenderWorker& operator=(const RenderWorker&) = delete;

    /// Runs `f` on the worker thread and returns its result (waits for it).
    template <class F>
    auto call(F f) -> std::invoke_result_t<F> {
        using R = std::invoke_result_t<F>;
        std::packaged_task<R()> task(std::move(f));
        std::future<R> result = task.get_future();
        post([&task] { task(); });
        return result.get();
    }

private:
    void post(std::function<void()> job);
    void loop();

    std::mutex mMutex;
    std::condition_variable mWake;
    std::queue<std::function<void()>> mJobs;
    bool mStop = false;
    std::thread mThread;
};

}  // namespace mvr::viewer
