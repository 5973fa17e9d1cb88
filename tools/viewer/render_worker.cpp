#include "render_worker.h"

namespace mvr::viewer {

RenderWorker::RenderWorker() : mThread([this] { loop(); }) {}

RenderWorker::~RenderWorker() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
    }
    mWake.notify_one();
    mThread.join();
}

void RenderWorker::post(std::function<void()> job) {
    {
        std::lock_guard lock(mMutex);
        mJobs.push(std::move(job));
    }
    mWake.notify_one();
}

void RenderWorker::loop() {
    for (;;) {
        std::function<void()> job;
        {
            std::unique_lock lock(mMutex);
            mWake.wait(lock, [this] { return mStop || !mJobs.empty(); });
            if (mJobs.empty()) return;  // stopping, nothing left
            job = std::move(mJobs.front());
            mJobs.pop();
        }
        job();
    }
}

}  // namespace mvr::viewer
