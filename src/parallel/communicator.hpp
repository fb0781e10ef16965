#pragma once
// The processes of one run and the messages between them (docs/parallel.md). A process started by
// mpirun (or srun) joins MPI's world; any other process is a run of one, rank 0 of 1, and never
// initialises MPI.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace settle::parallel {

/// What a process sent to the others and how long it spent in the calls that move messages (for
/// `settle bench`; docs/parallel.md, "Speed"). Counted by the MPI communicator; a run of one
/// process sends nothing.
struct Traffic {
  std::uint64_t exchange_bytes_sent = 0;  ///< neighbour messages (exchange): the ghost traffic
  std::uint64_t exchange_messages_sent = 0;
  double exchange_seconds = 0.0;            ///< in exchange(): posting, waiting for and receiving
  std::uint64_t collective_bytes_sent = 0;  ///< this rank's parts of gather_all / gather_to_root
  double collective_seconds = 0.0;
};

class Communicator {
 public:
  virtual ~Communicator() = default;
  /// This process's traffic since it started.
  const Traffic& traffic() const { return traffic_; }
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Sends send[k] to ranks[k] and receives receive[k] from ranks[k], for every k, and returns
  /// when every message has arrived. Each pair of ranks exchanges at most one message per call.
  virtual void exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                        std::vector<std::vector<double>>& receive) = 0;
  /// exchange() in two halves, so that the caller can work while the messages travel:
  /// start_exchange posts them (`send` must stay alive and unchanged until finish_exchange
  /// returns; `receive_counts[k]` is the length of the message ranks[k] sends), finish_exchange
  /// waits for them and fills `receive`. One exchange at a time. By default the whole exchange
  /// happens in finish_exchange.
  virtual void start_exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                              const std::vector<std::size_t>& receive_counts);
  virtual void finish_exchange(std::vector<std::vector<double>>& receive);
  /// Every rank's `mine`, in rank order, on every rank (the lengths may differ between ranks).
  virtual std::vector<std::vector<double>> gather_all(const std::vector<double>& mine) = 0;
  /// Every rank's `mine` in rank order on rank 0; nothing on the others (a field written by rank 0).
  virtual std::vector<std::vector<double>> gather_to_root(const std::vector<double>& mine) = 0;
  /// Ends every process of the run with `status` (after a failure on this one: the others may be
  /// waiting for its messages).
  [[noreturn]] virtual void abort(int status) = 0;

 protected:
  Traffic traffic_;

 private:
  // The exchange started by the default start_exchange.
  const std::vector<int>* pending_ranks_ = nullptr;
  const std::vector<std::vector<double>>* pending_send_ = nullptr;
};

/// The element-wise sum of every rank's `mine` (all of one length), added in rank order on every
/// rank: the same bits on every rank and in every run with this many ranks (an MPI_Allreduce may
/// add in any order).
std::vector<double> sum_in_rank_order(Communicator& communicator, const std::vector<double>& mine);

/// The first rank, in rank order, whose `failed` is true, the same on every rank (every rank calls
/// it); none when no rank failed. A step that can fail on one rank alone (writing its file) is
/// followed by this, so that all ranks go on or all stop together.
std::optional<int> first_failed_rank(Communicator& communicator, bool failed);

/// As first_failed_rank, with the reason: `mine` is this rank's failure message (none: it did
/// not fail). Every rank gets the first failed rank and its message (cut to 4096 bytes), so that
/// rank 0, which reports, can say why another rank failed.
struct RankFailure {
  int rank = 0;
  std::string message;
};
std::optional<RankFailure> first_failure(Communicator& communicator, const std::optional<std::string>& mine);

/// True when this process was started by an MPI launcher (the environment variables OpenMPI's
/// mpirun, Hydra and Slurm's PMI set for their processes).
bool launched_by_mpi();

/// A run of one process, rank 0 of 1, whether or not MPI runs (for work that is not split).
Communicator& single_process();

/// The communicator of this process: MPI's world when launched_by_mpi() (MPI initialised at the
/// first call, finalised at exit), otherwise a run of one.
Communicator& world();

/// "MPI (Open MPI v4.1.4)": the MPI library this build links, for `settle --version` (callable
/// before MPI starts).
std::string mpi_library_version();

}  // namespace settle::parallel
