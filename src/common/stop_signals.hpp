#pragma once
// The signals that stop a long run cleanly (docs/errors.md, "Promises": no signal ends a run
// without a message). `settle run` and `settle study run` catch each of them, finish the current
// step, write a checkpoint (a study: its cases do), say so and exit with 128 + the signal; SIGXFSZ
// (a file-size limit, ulimit -f) is ignored by every command, so that the write that crosses the
// limit fails with EFBIG and is reported like a full disk.
//  - SIGINT (Ctrl-C), SIGTERM (kill, batch systems at the time limit), SIGHUP (the terminal or ssh
//    connection went away), SIGXCPU (a CPU-time limit, ulimit -t, sent before SIGKILL), SIGUSR1
//    and SIGUSR2 (Slurm's --signal sends one before the time limit);
//  - SIGPIPE: the reader of settle's output went away. The run still checkpoints; its message has
//    nowhere to go.
// SIGKILL and SIGSTOP cannot be caught; SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT are crashes.
#include <array>
#include <csignal>
#include <string>

namespace settle {

/// In the order a run across processes reports them when its ranks saw different ones.
inline constexpr std::array<int, 7> kStopSignals{SIGINT, SIGTERM, SIGHUP, SIGXCPU, SIGUSR1, SIGUSR2, SIGPIPE};

/// "SIGINT", "SIGHUP", ...; "signal N" for others.
std::string signal_name(int signal_number);

/// Ignores SIGXFSZ for this process and the processes it starts (file comment). Once, at start-up.
void ignore_file_size_signal();

}  // namespace settle
