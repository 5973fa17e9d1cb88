// tools/cli/stop_signals.cpp — see stop_signals.h.
#include "stop_signals.h"

#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <thread>

#include <fmt/core.h>

#include "mvr/session/pending.h"

namespace mvr::cli {

namespace {

std::mutex sContextMutex;
std::string sContext;
bool sQuiet = false;

[[noreturn]] void stopRun(int sig) {
    // Holds the outputs' lock until the exit: no set is moved into place after this.
    std::unique_lock<std::recursive_mutex> outputs;
    session::removePendingOutputs(&outputs);
    std::string why, progress = session::outputProgress();
    bool quiet = false;
    {
        std::lock_guard lock(sContextMutex);
        why = sContext;
        quiet = sQuiet;
    }
    if (!quiet) {
        const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
        const std::string line = fmt::format(
            "{}error: stopped by {}{}{}: {}\n", ::isatty(STDERR_FILENO) ? "\r\033[K" : "", name,
            why.empty() ? "" : " (", why.empty() ? "" : why + ")",
            progress.empty() ? "nothing was written" : progress);
        [[maybe_unused]] auto n = ::write(STDERR_FILENO, line.data(), line.size());
    }
    std::fflush(stdout);
    ::_exit(128 + sig);
}

}  // namespace

void handleStopSignals() {
    sigset_t set;
    sigemptyset(&set);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&set, sig);
    if (::pthread_sigmask(SIG_BLOCK, &set, nullptr) != 0) return;  // the default: killed
    std::signal(SIGXFSZ, SIG_IGN);
    std::thread([set] {
        int sig = 0;
        while (::sigwait(&set, &sig) != 0) {
        }
        stopRun(sig);
    }).detach();
}

void setStopContext(std::string why, bool quiet) {
    std::lock_guard lock(sContextMutex);
    sContext = std::move(why);
    sQuiet = quiet;
}

}  // namespace mvr::cli
