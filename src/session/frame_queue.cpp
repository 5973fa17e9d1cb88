// src/session/frame_queue.cpp — a sequence's writes beside its rendering
// (mvr/session/frame_queue.h).
#include "mvr/session/frame_queue.h"

#include <cstdlib>
#include <exception>
#include <string>

#include <fmt/core.h>

namespace mvr::session {

int writeQueueDepth() {
    if (const char* v = std::getenv("MVR_WRITE_QUEUE"); v && *v) {
        char* end = nullptr;
        const long n = std::strtol(v, &end, 10);
        if (end && *end == '\0' && n >= 0 && n <= 8) return int(n);
    }
    return kDefaultWriteQueue;
}

FrameQueue::FrameQueue(int depth) : mDepth(depth < 0 ? 0 : depth) {}

FrameQueue::~FrameQueue() {
    {
        std::lock_guard lock(mMutex);
        mStop = true;
        mQueue.clear();
    }
    mChanged.notify_all();
    if (mThread.joinable()) mThread.join();
}

namespace {
Status runWrite(const std::function<Status()>& write) {
    try {
        return write();
    } catch (const std::exception& e) {
        return internalError(fmt::format("writing a frame: {}", e.what()));
    } catch (...) {
        return internalError("writing a frame: unknown exception");
    }
}
}  // namespace

Status FrameQueue::push(std::function<Status()> write) {
    if (mDepth == 0) {
        if (!mFailed) return mFailed;
        mFailed = runWrite(write);
        return mFailed;
    }
    std::unique_lock lock(mMutex);
    if (!mThread.joinable()) mThread = std::thread([this] { loop(); });
    mChanged.wait(lock, [&] {
        return !mFailed || int(mQueue.size()) + (mRunning ? 1 : 0) < mDepth;
    });
    if (!mFailed) return mFailed;
    mQueue.push_back(std::move(write));
    mChanged.notify_all();
    return {};
}

Status FrameQueue::finish() {
    if (mDepth == 0) return mFailed;
    std::unique_lock lock(mMutex);
    mChanged.wait(lock, [&] { return mQueue.empty() && !mRunning; });
    return mFailed;
}

void FrameQueue::loop() {
    std::unique_lock lock(mMutex);
    for (;;) {
        mChanged.wait(lock, [&] { return mStop || !mQueue.empty(); });
        if (mQueue.empty()) return;  // stopped
        std::function<Status()> write = std::move(mQueue.front());
        mQueue.pop_front();
        mRunning = true;
        lock.unlock();
        Status s = runWrite(write);
        write = nullptr;  // what it held (a frame's images) is freed before room is made
        lock.lock();
        mRunning = false;
        if (!s && mFailed) {
            mFailed = s;
            mQueue.clear();
        }
        mChanged.notify_all();
    }
}

}  // namespace mvr::session
