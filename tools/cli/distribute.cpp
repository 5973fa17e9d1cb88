#include "distribute.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>

#include <fmt/core.h>

#include "options.h"
#include "stop_signals.h"
#include "mvr/session/pending.h"
#include "video.h"

#ifdef MVR_WITH_MPI
#include <mpi.h>
#endif

namespace mvr::cli {

namespace {

Status renderHere(const std::vector<int>& frames, int views, const RenderViewsFn& render,
                  const EmitFrameFn& emit) {
    for (int f : frames) {
        auto out = render(f, 0, views);
        if (!out) return out.status();
        if (Status s = emit(f, *out); !s) return s;
    }
    return {};
}

#ifdef MVR_WITH_MPI
int sRank = 0;

/// Under mpirun (Open MPI or another launcher's environment) with more than one process.
bool launchedWithRanks() {
    for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
        if (const char* v = std::getenv(var); v && std::atoi(v) > 1) return true;
    }
    return false;
}

enum Tag { kReady = 1, kHeader = 2, kPixels = 3, kError = 4, kDepth = 5, kItem = 10 };

struct Item {
    int frame, v0, v1;
};

void worker(const RenderViewsFn& render) {
    int ready = 0;
    Item item{};
    MPI_Send(&ready, 1, MPI_INT, 0, kReady, MPI_COMM_WORLD);
    MPI_Recv(&item, 3, MPI_INT, 0, kItem, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    for (;;) {
        if (item.frame < 0) return;
        // Asks for the next item before rendering this one: rank 0 answers between writing
        // frames, so the worker never waits for a write to finish.
        MPI_Send(&ready, 1, MPI_INT, 0, kReady, MPI_COMM_WORLD);
        auto out = render(item.frame, item.v0, item.v1);
        if (!out) {
            const std::string msg = out.status().message();
            MPI_Send(msg.data(), int(msg.size()), MPI_CHAR, 0, kError, MPI_COMM_WORLD);
            return;
        }
        // One message for the item's views (one per view costs a round trip each).
        const Image& first = out->color.at(0);
        const std::size_t bytes = first.rgba.size();
        std::vector<std::uint8_t> all;
        all.reserve(bytes * out->color.size());
        for (const Image& im : out->color) all.insert(all.end(), im.rgba.begin(), im.rgba.end());
        const bool depth = !out->depth.empty() && out->depth.size() == out->color.size();
        int header[6] = {item.frame, item.v0, item.v1, first.width, first.height, depth ? 1 : 0};
        MPI_Send(header, 6, MPI_INT, 0, kHeader, MPI_COMM_WORLD);
        MPI_Send(all.data(), int(all.size()), MPI_BYTE, 0, kPixels, MPI_COMM_WORLD);
        if (depth) {  // --depth: the views' depth images, one message
            std::vector<float> d;
            d.reserve(std::size_t(first.width) * std::size_t(first.height) * out->depth.size());
            for (const DepthImage& im : out->depth) d.insert(d.end(), im.depth.begin(), im.depth.end());
            MPI_Send(d.data(), int(d.size()), MPI_FLOAT, 0, kDepth, MPI_COMM_WORLD);
        }
        MPI_Recv(&item, 3, MPI_INT, 0, kItem, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }
}

Status coordinator(int workers, const std::vector<int>& frames, int views,
                   const EmitFrameFn& emit, bool gatherStats) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    double gatherSeconds = 0.0;  // receiving and unpacking views (after their header came)
    std::uint64_t gatherBytes = 0;
    // Whole frames while there are at least as many frames as workers; else shares of views.
    std::vector<Item> items;
    const int chunks =
        frames.size() >= std::size_t(workers)
            ? 1
            : std::min(views, (workers + int(frames.size()) - 1) / std::max(1, int(frames.size())));
    const int per = (views + chunks - 1) / chunks;
    for (int f : frames) {
        for (int v0 = 0; v0 < views; v0 += per) items.push_back({f, v0, std::min(views, v0 + per)});
    }
    struct Pending {
        RenderOutput out;
        int missing = 0;
    };
    std::map<int, Pending> pending;
    std::size_t next = 0, emitted = 0;
    int stopped = 0;
    while (stopped < workers || emitted < frames.size()) {
        MPI_Status st;
        // Polls with short sleeps: rank 0 does not render, and must not take a core from the
        // workers by spinning in MPI_Probe.
        for (int flag = 0; !flag;) {
            if (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) !=
                MPI_SUCCESS) {
                return internalError(
                    fmt::format("a rank stopped ({} of {} frames written): it failed or was killed",
                                emitted, frames.size()));
            }
            if (!flag) ::usleep(200);
        }
        const int src = st.MPI_SOURCE;
        if (st.MPI_TAG == kReady) {
            int dummy = 0;
            MPI_Recv(&dummy, 1, MPI_INT, src, kReady, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            Item item{-1, 0, 0};
            if (next < items.size()) {
                item = items[next++];
            } else {
                ++stopped;
            }
            MPI_Send(&item, 3, MPI_INT, src, kItem, MPI_COMM_WORLD);
        } else if (st.MPI_TAG == kError) {
            int n = 0;
            MPI_Get_count(&st, MPI_CHAR, &n);
            std::string msg(std::size_t(n), '\0');
            MPI_Recv(msg.data(), n, MPI_CHAR, src, kError, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            return Status(ErrorCode::Internal, fmt::format("rank {}: {}", src, msg));
        } else if (st.MPI_TAG == kHeader) {
            int h[6];
            MPI_Recv(h, 6, MPI_INT, src, kHeader, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            const Clock::time_point gather = Clock::now();
            const std::size_t pixels = std::size_t(h[3]) * std::size_t(h[4]);
            const std::size_t bytes = pixels * 4;
            std::vector<std::uint8_t> all(bytes * std::size_t(h[2] - h[1]));
            std::vector<float> depth(h[5] ? pixels * std::size_t(h[2] - h[1]) : 0);
            if (MPI_Recv(all.data(), int(all.size()), MPI_BYTE, src, kPixels, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE) != MPI_SUCCESS ||
                (h[5] && MPI_Recv(depth.data(), int(depth.size()), MPI_FLOAT, src, kDepth,
                                  MPI_COMM_WORLD, MPI_STATUS_IGNORE) != MPI_SUCCESS)) {
                return internalError(fmt::format(
                    "rank {} stopped while sending frame {}: it failed or was killed", src, h[0]));
            }
            auto [it, fresh] = pending.try_emplace(h[0]);
            if (fresh) {
                it->second.out.color.resize(std::size_t(views));
                it->second.missing = views;
            }
            if (h[5]) it->second.out.depth.resize(std::size_t(views));
            for (int v = h[1]; v < h[2]; ++v) {
                Image im(h[3], h[4]);
                std::copy_n(all.begin() + long(bytes) * (v - h[1]), bytes, im.rgba.begin());
                it->second.out.color.at(std::size_t(v)) = std::move(im);
                if (h[5]) {
                    DepthImage d(h[3], h[4]);
                    std::copy_n(depth.begin() + long(pixels) * (v - h[1]), pixels, d.depth.begin());
                    it->second.out.depth.at(std::size_t(v)) = std::move(d);
                }
                --it->second.missing;
            }
            gatherSeconds += std::chrono::duration<double>(Clock::now() - gather).count();
            gatherBytes += all.size() + depth.size() * sizeof(float);
            // Emit the frames in order as they complete.
            while (emitted < frames.size()) {
                auto ready = pending.find(frames[emitted]);
                if (ready == pending.end() || ready->second.missing > 0) break;
                if (Status s = emit(ready->first, ready->second.out); !s) return s;
                pending.erase(ready);
                ++emitted;
            }
        } else {
            return internalError(fmt::format("rank {} sent an unknown message", src));
        }
    }
    if (emitted != frames.size()) {
        return internalError(fmt::format("{} of {} frames came back", emitted, frames.size()));
    }
    if (gatherStats && !frames.empty()) {
        const double total = std::chrono::duration<double>(Clock::now() - start).count();
        const double n = double(frames.size());
        fmt::print(stderr,
                   "gather: {} frames of {} views, {:.1f} MiB received; rank 0 receiving and "
                   "unpacking views {:.2f} ms per frame ({:.1f}% of the run's {:.2f} ms per "
                   "frame)\n",
                   frames.size(), views, double(gatherBytes) / (1 << 20), gatherSeconds * 1e3 / n,
                   total > 0 ? 100.0 * gatherSeconds / total : 0.0, total * 1e3 / n);
    }
    return {};
}
#endif

}  // namespace

bool mpiAvailable() {
#ifdef MVR_WITH_MPI
    return true;
#else
    return false;
#endif
}

bool isRankZero() {
#ifdef MVR_WITH_MPI
    return sRank == 0;
#else
    return true;
#endif
}

Status distributeFrames(const std::vector<int>& frames, int views, const RenderViewsFn& render,
                        const EmitFrameFn& emit, bool gatherStats,
                        const std::function<void()>& settle) {
#ifdef MVR_WITH_MPI
    if (launchedWithRanks()) {
        // A rank killed while rank 0 copies a frame straight out of its memory (Open MPI's
        // shared-memory single copy, CMA: "Read -1, expected …, errno = 3") makes Open MPI abort
        // rank 0 from inside MPI_Recv, before it can say that a rank stopped (cli.mpi caught it
        // now and then). Frames then go through the shared-memory buffers instead: one more copy
        // of a few MB a frame, small next to rendering it. A user's own setting wins.
        ::setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 0);
        MPI_Init(nullptr, nullptr);
        int size = 1;
        MPI_Comm_rank(MPI_COMM_WORLD, &sRank);
        MPI_Comm_size(MPI_COMM_WORLD, &size);
        if (size > 1) {
            if (sRank != 0) {
                setStopContext({}, true);  // rank 0 says why the job stopped
                worker(render);
                MPI_Finalize();
                return {};
            }
            MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
            // mpirun ends every rank with SIGTERM when one fails or is killed: rank 0's line
            // (stop_signals.h) says so, what was not in place being removed.
            setStopContext("mpirun stopped the run: a rank failed or was killed, see mpirun's "
                           "lines");
            Status s = coordinator(size - 1, frames, views, emit, gatherStats);
            if (!s) {
                // The workers wait for items or send views: end them all, with rank 0's line
                // and what the output holds (MPI_Abort does not return).
                if (settle) settle();
                session::removePendingOutputs();
                fail(Status(s.code(), fmt::format("{}; {}", s.message(), session::outputProgress())));
                MPI_Abort(MPI_COMM_WORLD, exitCode(s.code()) ? exitCode(s.code()) : 1);
            }
            MPI_Finalize();
            return s;
        }
        MPI_Finalize();
    }
#endif
    return renderHere(frames, views, render, emit);
}

}  // namespace mvr::cli
