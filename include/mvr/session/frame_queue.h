// mvr/session/frame_queue.h — a sequence's writing beside its rendering (library mvr::session,
// issue 37): the writes of frames run in order on a thread of their own while the caller
// renders the next frame, through a bounded queue.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>

#include "mvr/core/status.h"

namespace mvr::session {

/// The default depth of a sequence's queues (MVR_WRITE_QUEUE overrides it): one frame written
/// while the next renders.
inline constexpr int kDefaultWriteQueue = 1;
/// The depth a sequence's queues take: MVR_WRITE_QUEUE (0..8; 0: no overlap, every frame
/// written on the rendering thread before the next renders, as before issue 37), else
/// kDefaultWriteQueue.
int writeQueueDepth();

/// Runs writes (one frame's files, one frame of a video) in the order pushed, on a thread of
/// its own, while the caller goes on. At most `depth` writes are queued or running at once:
/// push() waits for room, which bounds the memory the queued frames hold. The first write
/// that fails (or throws: ErrorCode::Internal) stops the queue: the writes queued after it are
/// dropped unrun, and push() and finish() return its error from then on.
class FrameQueue {
public:
    /// `depth` 0: no thread; push() runs each write on the caller's thread.
    explicit FrameQueue(int depth);
    /// Drops the writes not started, waits for the running one and joins the thread (an early
    /// return: call finish() first to have every queued write run).
    ~FrameQueue();
    FrameQueue(const FrameQueue&) = delete;
    FrameQueue& operator=(const FrameQueue&) = delete;

    /// Queues `write` behind the earlier ones, waiting while `depth` are queued or running.
    /// Returns the error of an earlier write that failed (then `write` is dropped), else ok.
    Status push(std::function<Status()> write);
    /// Waits until every queued write has run; the first failure, or ok.
    Status finish();

private:
    void loop();
    const int mDepth;
    std::mutex mMutex;
    std::condition_variable mChanged;
    std::deque<std::function<Status()>> mQueue;
    bool mRunning = false;  ///< a write is running (popped from mQueue)
    bool mStop = false;
    Status mFailed;
    std::thread mThread;  ///< started by the first push()
};

}  // namespace mvr::session
