// mvr/session/pending.h — outputs that appear whole or not at all (issue 44; library
// mvr::session).
//
// A still's files (a sequence's frame) are written under temporary names and moved into place
// when the set is complete. What is not in place yet is registered here, process-wide, so that
// whatever ends the run — an error, a full disk, a signal (the `mvr` tool's handler calls
// removePendingOutputs()) — removes it and leaves the output directory as it was.
#pragma once

#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include "mvr/core/status.h"

namespace mvr::session {

/// Registers `path` (a temporary file or folder, removed with what it holds; or, with
/// `onlyIfEmpty`, a folder this run made) to be removed should the run stop before it is
/// released. Returns its ticket for releasePending().
int addPending(const std::filesystem::path& path, bool onlyIfEmpty = false);
/// Forgets ticket `id` (its path is in place, or gone); with `remove`, removes the path first.
void releasePending(int id, bool remove);
/// Removes every registered path (temporary ones first, then the folders made for them, when
/// empty), and forgets them. Thread-safe; returns how many were removed. While the returned
/// lock is held, nothing is committed: the signal handler keeps it until the process exits.
int removePendingOutputs(std::unique_lock<std::recursive_mutex>* keepLocked = nullptr);
/// The lock commits take (moving a set into place is not interrupted half-way).
std::recursive_mutex& pendingMutex();

/// What the output holds so far, said when the run stops (a sequence: "3 of 24 frames are
/// complete in out/; `--frame-range 3:` renders the rest"); empty for a still.
void setOutputProgress(std::string note);
std::string outputProgress();

/// Folders made for an output (`-o out/a/b` makes the missing ones), removed again — the
/// innermost first, each only when empty — unless kept: a failed run leaves no folder behind.
class MadeFolders {
public:
    /// Makes `dir` and the folders above it that are missing; ErrorCode::Output naming `dir`
    /// when it cannot (and nothing made is left).
    static Result<MadeFolders> make(const std::filesystem::path& dir);
    MadeFolders() = default;
    MadeFolders(MadeFolders&& o) noexcept : mTickets(std::move(o.mTickets)) { o.mTickets.clear(); }
    MadeFolders& operator=(MadeFolders&& o) noexcept;
    MadeFolders(const MadeFolders&) = delete;
    ~MadeFolders() { removeIfEmpty(); }
    /// They stay (something was put in place in them).
    void keep();
    /// Removes those that are empty now, innermost first, and forgets them all.
    void removeIfEmpty();

private:
    std::vector<int> mTickets;  // outermost first
};

/// The files of one set: the folder's files in a hidden staging folder inside it
/// (`.mvr-part-PID-N/`), files elsewhere (the comfort report) in a hidden folder of their own beside
/// their place. commit() moves them into place; destroyed uncommitted, it removes what it
/// staged, and the folder when it made it and nothing else is in it.
class StagedFiles {
public:
    /// Makes `dir` (when missing) and its staging folder; ErrorCode::Output naming `dir` when
    /// it cannot.
    static Result<StagedFiles> inFolder(const std::filesystem::path& dir);
    /// A set of files elsewhere only (stage() each): no folder.
    static StagedFiles elsewhere();
    StagedFiles(StagedFiles&&) noexcept;
    StagedFiles& operator=(StagedFiles&&) = delete;
    StagedFiles(const StagedFiles&) = delete;
    ~StagedFiles();

    /// Where the folder's files are written.
    const std::filesystem::path& folder() const { return mStaging; }
    /// The temporary name to write `path` (outside the folder) under, in a hidden folder
    /// beside it (`.mvr-part-PID-N/<its name>`; its own folder made when missing); moved with
    /// the set.
    Result<std::filesystem::path> stage(const std::filesystem::path& path);
    /// Moves every staged file into place (the folder's: those under folder() now), after
    /// checking that none would replace a directory. `paths` (files under folder() and staged
    /// names) become their final names.
    Status commit(std::vector<std::string>& paths);
    /// `error` with the staged names in its message put back to their final ones.
    Status withFinalNames(const Status& error) const;
    /// Removes what was staged (idempotent; the destructor's).
    void discard();

private:
    StagedFiles() = default;
    std::filesystem::path mDir, mStaging;
    struct Elsewhere {
        std::filesystem::path temp, final;
        int ticket;
    };
    std::vector<Elsewhere> mElsewhere;
    MadeFolders mMade;
    std::vector<MadeFolders> mMadeElsewhere;  // the folders of staged files, made for them
    int mStagingTicket = -1;
    bool mDone = false;
};

}  // namespace mvr::session
