// tools/cli/stop_signals.h — a run stopped by SIGINT, SIGTERM or SIGHUP (Ctrl-C, `kill`, mpirun
// ending a job, a closed terminal) leaves its outputs whole or absent (issue 44).
#pragma once

#include <string>

namespace mvr::cli {

/// Called first thing in main(): blocks the stop signals in this thread and every thread made
/// after it (the backends', the writers', MPI's) and starts the one thread that waits for them.
/// When one comes, that thread removes what was not in place yet
/// (session::removePendingOutputs(), taken while no set is being moved into place), prints
/// "error: stopped by SIGTERM: <what the output holds>" and exits with 128 + the signal's
/// number, as a shell reports a process the signal killed. SIGXFSZ (a file over `ulimit -f`)
/// is ignored: the write fails with EFBIG and is an error like a full disk.
void handleStopSignals();

/// Why a stop signal may come here, said in its line: rank 0 under mpirun ("mpirun stopped
/// the run: a rank failed or was killed"). `quiet`: no line (a worker rank; rank 0 speaks).
void setStopContext(std::string why, bool quiet = false);

}  // namespace mvr::cli
