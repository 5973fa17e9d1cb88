// src/session/pending.cpp — outputs that appear whole or not at all (mvr/session/pending.h).
#include "mvr/session/pending.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>

#include <atomic>
#include <map>

#include <fmt/core.h>

namespace mvr::session {

namespace {

struct Entry {
    std::filesystem::path path;
    bool onlyIfEmpty;
};

struct Registry {
    std::recursive_mutex mutex;
    std::map<int, Entry> entries;  // by ticket: registration order
    int next = 0;
    std::string progress;
};

Registry& registry() {
    static Registry* r = new Registry;  // never destroyed: a signal may come at exit
    return *r;
}

void removeEntry(const Entry& e) {
    std::error_code ec;
    if (e.onlyIfEmpty) {
        if (std::filesystem::is_empty(e.path, ec) && !ec) std::filesystem::remove(e.path, ec);
        return;
    }
    // A writer thread may still create a file in a staging folder while it is removed.
    for (int tries = 0; tries < 4; ++tries) {
        std::filesystem::remove_all(e.path, ec);
        if (!std::filesystem::exists(std::filesystem::symlink_status(e.path, ec))) return;
    }
}

std::atomic<int> sStagingCount{0};

}  // namespace

std::recursive_mutex& pendingMutex() { return registry().mutex; }

int addPending(const std::filesystem::path& path, bool onlyIfEmpty) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    const int id = r.next++;
    r.entries.emplace(id, Entry{path, onlyIfEmpty});
    return id;
}

void releasePending(int id, bool remove) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    auto it = r.entries.find(id);
    if (it == r.entries.end()) return;
    if (remove) removeEntry(it->second);
    r.entries.erase(it);
}

int removePendingOutputs(std::unique_lock<std::recursive_mutex>* keepLocked) {
    Registry& r = registry();
    std::unique_lock lock(r.mutex);
    int removed = 0;
    // The newest first: a staging folder before the output folder made for it.
    for (auto it = r.entries.rbegin(); it != r.entries.rend(); ++it, ++removed)
        removeEntry(it->second);
    r.entries.clear();
    if (keepLocked) *keepLocked = std::move(lock);
    return removed;
}

void setOutputProgress(std::string note) {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    r.progress = std::move(note);
}

std::string outputProgress() {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    return r.progress;
}

// ---- MadeFolders -------------------------------------------------------------------------------

Result<MadeFolders> MadeFolders::make(const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> missing;  // innermost first
    std::error_code ec;
    for (std::filesystem::path p = dir; !p.empty() && !std::filesystem::exists(p, ec);
         p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    std::lock_guard lock(pendingMutex());  // made and registered at once
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
        for (const std::filesystem::path& p : missing) {  // what it made before it failed
            std::error_code rm;
            std::filesystem::remove(p, rm);
        }
        return outputError(fmt::format("cannot create output directory '{}': {}", dir.string(),
                                       ec ? ec.message() : "not a directory"));
    }
    MadeFolders made;
    for (auto it = missing.rbegin(); it != missing.rend(); ++it)
        made.mTickets.push_back(addPending(*it, true));
    return made;
}

MadeFolders& MadeFolders::operator=(MadeFolders&& o) noexcept {
    if (this != &o) {
        removeIfEmpty();
        mTickets = std::move(o.mTickets);
        o.mTickets.clear();
    }
    return *this;
}

void MadeFolders::keep() {
    for (int t : mTickets) releasePending(t, false);
    mTickets.clear();
}

void MadeFolders::removeIfEmpty() {
    for (auto it = mTickets.rbegin(); it != mTickets.rend(); ++it) releasePending(*it, true);
    mTickets.clear();
}

// ---- StagedFiles ---------------------------------------------------------------------------------

namespace {

/// Removes the staging folders that a process killed with SIGKILL (which nothing can clean up
/// after) left in `dir`: `.mvr-part-PID-…` of a PID that no longer runs.
void removeStaleStaging(const std::filesystem::path& dir) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(".mvr-part-", 0) != 0) continue;
        const long pid = std::strtol(name.c_str() + 10, nullptr, 10);
        if (pid <= 0 || pid == ::getpid()) continue;
        if (::kill(pid_t(pid), 0) != 0 && errno == ESRCH) {
            std::error_code rm;
            std::filesystem::remove_all(entry.path(), rm);
        }
    }
}

}  // namespace

Result<StagedFiles> StagedFiles::inFolder(const std::filesystem::path& dir) {
    auto made = MadeFolders::make(dir);
    if (!made) return made.status();
    removeStaleStaging(dir);
    StagedFiles s;
    s.mDir = dir;
    s.mMade = std::move(made).value();
    s.mStaging = dir / fmt::format(".mvr-part-{}-{}", ::getpid(), sStagingCount++);
    std::lock_guard lock(pendingMutex());  // registered and made at once
    s.mStagingTicket = addPending(s.mStaging);
    std::error_code ec;
    std::filesystem::create_directory(s.mStaging, ec);
    if (ec) {
        const std::string why = ec.message();
        s.discard();
        return outputError(
            fmt::format("cannot write into output directory '{}': {}", dir.string(), why));
    }
    return s;
}

StagedFiles StagedFiles::elsewhere() { return StagedFiles(); }

StagedFiles::StagedFiles(StagedFiles&& o) noexcept
    : mDir(std::move(o.mDir)),
      mStaging(std::move(o.mStaging)),
      mElsewhere(std::move(o.mElsewhere)),
      mMade(std::move(o.mMade)),
      mMadeElsewhere(std::move(o.mMadeElsewhere)),
      mStagingTicket(o.mStagingTicket),
      mDone(o.mDone) {
    o.mDone = true;
    o.mElsewhere.clear();
}

StagedFiles::~StagedFiles() { discard(); }

Result<std::filesystem::path> StagedFiles::stage(const std::filesystem::path& path) {
    // In a hidden folder of its own beside its place, under its own name: a writer still
    // running when a stop signal removed the folder cannot leave a file behind.
    const std::filesystem::path parent = path.has_parent_path() ? path.parent_path() : ".";
    auto made = MadeFolders::make(parent);  // kept with the set, else removed when empty
    if (!made) return made.status();
    mMadeElsewhere.push_back(std::move(made).value());
    const std::filesystem::path folder =
        parent / fmt::format(".mvr-part-{}-{}", ::getpid(), sStagingCount++);
    std::lock_guard lock(pendingMutex());  // registered and made at once
    const int ticket = addPending(folder);
    std::error_code ec;
    std::filesystem::create_directory(folder, ec);
    if (ec) {
        releasePending(ticket, true);
        return outputError(fmt::format("cannot write '{}': {}", path.string(), ec.message()));
    }
    mElsewhere.push_back({folder / path.filename(), path, ticket});
    return mElsewhere.back().temp;
}

Status StagedFiles::withFinalNames(const Status& error) const {
    std::string m = error.message();
    auto replace = [&m](const std::string& from, const std::string& to) {
        for (std::size_t at = m.find(from); !from.empty() && at != std::string::npos;
             at = m.find(from, at + to.size()))
            m.replace(at, from.size(), to);
    };
    for (const Elsewhere& e : mElsewhere) replace(e.temp.string(), e.final.string());
    if (!mStaging.empty()) replace(mStaging.string(), mDir.string());
    return Status(error.code(), std::move(m));
}

void StagedFiles::discard() {
    if (mDone) return;
    mDone = true;
    std::lock_guard lock(pendingMutex());
    for (const Elsewhere& e : mElsewhere) releasePending(e.ticket, true);
    releasePending(mStagingTicket, true);
    for (MadeFolders& m : mMadeElsewhere) m.removeIfEmpty();
    mMade.removeIfEmpty();
}

Status StagedFiles::commit(std::vector<std::string>& paths) {
    if (mDone) return internalError("StagedFiles::commit: the set was already committed");
    std::lock_guard lock(pendingMutex());
    // Where each file goes; nothing moves when one of them would replace a directory.
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> moves;
    for (std::string& path : paths) {
        const std::filesystem::path from(path);
        std::filesystem::path to;
        for (const Elsewhere& e : mElsewhere)
            if (e.temp == from) to = e.final;
        if (to.empty() && !mStaging.empty() && from.parent_path() == mStaging)
            to = mDir / from.filename();
        if (to.empty()) continue;  // not staged (written in place by the caller)
        std::error_code ec;
        if (std::filesystem::is_directory(std::filesystem::symlink_status(to, ec))) {
            return outputError(
                fmt::format("cannot write '{}': a directory is in the way", to.string()));
        }
        moves.emplace_back(from, to);
        path = to.string();
    }
    for (const auto& [from, to] : moves) {
        std::error_code ec;
        std::filesystem::rename(from, to, ec);
        if (ec) {
            return outputError(fmt::format("cannot move '{}' into place as '{}': {}",
                                           from.string(), to.string(), ec.message()));
        }
    }
    mDone = true;
    for (const Elsewhere& e : mElsewhere) releasePending(e.ticket, true);  // its empty folder
    releasePending(mStagingTicket, true);  // empty now, or what was staged but not listed
    for (MadeFolders& m : mMadeElsewhere) m.keep();
    mMade.keep();
    return {};
}

}  // namespace mvr::session
