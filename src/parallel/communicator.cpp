#include "parallel/communicator.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace settle::parallel {

void Communicator::start_exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                                  const std::vector<std::size_t>&) {
  if (pending_ranks_) throw std::logic_error("start_exchange: an exchange is already under way");
  pending_ranks_ = &ranks;
  pending_send_ = &send;
}

void Communicator::finish_exchange(std::vector<std::vector<double>>& receive) {
  if (!pending_ranks_) throw std::logic_error("finish_exchange: no exchange was started");
  const std::vector<int>& ranks = *pending_ranks_;
  const std::vector<std::vector<double>>& send = *pending_send_;
  pending_ranks_ = nullptr;
  pending_send_ = nullptr;
  exchange(ranks, send, receive);
}

namespace {

class SingleProcess final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>&,
                std::vector<std::vector<double>>&) override {
    if (!ranks.empty()) throw std::logic_error("exchange: a run of one process has no other rank");
  }
  std::vector<std::vector<double>> gather_all(const std::vector<double>& mine) override { return {mine}; }
  std::vector<std::vector<double>> gather_to_root(const std::vector<double>& mine) override { return {mine}; }
  [[noreturn]] void abort(int status) override { std::exit(status); }
};

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Counts one collective call into the traffic when it returns.
class Stopwatch {
 public:
  Stopwatch(Traffic& traffic, std::size_t values) : traffic_(traffic), start_(MPI_Wtime()) {
    traffic_.collective_bytes_sent += values * sizeof(double);
  }
  ~Stopwatch() { traffic_.collective_seconds += MPI_Wtime() - start_; }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  Traffic& traffic_;
  double start_;
};

class MpiWorld final : public Communicator {
 public:
  MpiWorld() {
    int provided = 0;
    // Only the thread that calls MPI communicates; OpenMP threads work between the calls.
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiWorld() override { MPI_Finalize(); }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  void exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                std::vector<std::vector<double>>& receive) override {
    if (send.size() != ranks.size()) throw std::invalid_argument("exchange: one message per rank");
    const double start = MPI_Wtime();
    std::vector<MPI_Request> sends(ranks.size());
    for (std::size_t k = 0; k < ranks.size(); ++k) {
      check(MPI_Isend(send[k].data(), static_cast<int>(send[k].size()), MPI_DOUBLE, ranks[k], kTag, MPI_COMM_WORLD,
                      &sends[k]),
            "MPI_Isend");
    }
    // A message's length is the receiver's count of halo links with that rank; it is probed rather
    // than passed in, so that the two sides cannot disagree silently (a mismatch fails end_step).
    receive.resize(ranks.size());
    for (std::size_t k = 0; k < ranks.size(); ++k) {
      MPI_Status status;
      check(MPI_Probe(ranks[k], kTag, MPI_COMM_WORLD, &status), "MPI_Probe");
      int count = 0;
      MPI_Get_count(&status, MPI_DOUBLE, &count);
      receive[k].resize(static_cast<std::size_t>(count));
      check(MPI_Recv(receive[k].data(), count, MPI_DOUBLE, ranks[k], kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
    }
    check(MPI_Waitall(static_cast<int>(sends.size()), sends.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
    for (const auto& message : send) traffic_.exchange_bytes_sent += message.size() * sizeof(double);
    traffic_.exchange_messages_sent += send.size();
    traffic_.exchange_seconds += MPI_Wtime() - start;
  }

  // Receives and sends posted at once (MPI_Irecv with the lengths the receiving block expects,
  // MPI_Isend), completed by finish_exchange: the transfer can proceed while the caller updates
  // its interior. A message longer than expected fails (MPI's truncation error), a shorter one is
  // caught by its count.
  void start_exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                      const std::vector<std::size_t>& receive_counts) override {
    if (send.size() != ranks.size() || receive_counts.size() != ranks.size())
      throw std::invalid_argument("start_exchange: one message and one count per rank");
    if (!requests_.empty()) throw std::logic_error("start_exchange: an exchange is already under way");
    const double start = MPI_Wtime();
    received_.assign(ranks.size(), {});
    requests_.resize(2 * ranks.size());
    for (std::size_t k = 0; k < ranks.size(); ++k) {
      received_[k].resize(receive_counts[k]);
      check(MPI_Irecv(received_[k].data(), static_cast<int>(receive_counts[k]), MPI_DOUBLE, ranks[k], kTag,
                      MPI_COMM_WORLD, &requests_[k]),
            "MPI_Irecv");
    }
    for (std::size_t k = 0; k < ranks.size(); ++k) {
      check(MPI_Isend(send[k].data(), static_cast<int>(send[k].size()), MPI_DOUBLE, ranks[k], kTag, MPI_COMM_WORLD,
                      &requests_[ranks.size() + k]),
            "MPI_Isend");
      traffic_.exchange_bytes_sent += send[k].size() * sizeof(double);
    }
    traffic_.exchange_messages_sent += send.size();
    traffic_.exchange_seconds += MPI_Wtime() - start;
  }

  void finish_exchange(std::vector<std::vector<double>>& receive) override {
    const double start = MPI_Wtime();
    const std::size_t count = requests_.size() / 2;
    std::vector<MPI_Status> statuses(requests_.size());
    check(MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), statuses.data()), "MPI_Waitall");
    requests_.clear();
    for (std::size_t k = 0; k < count; ++k) {
      int arrived = 0;
      MPI_Get_count(&statuses[k], MPI_DOUBLE, &arrived);
      if (static_cast<std::size_t>(arrived) != received_[k].size())
        throw std::runtime_error("finish_exchange: a message is shorter than its receiver's halo");
    }
    receive = std::move(received_);
    received_.clear();
    traffic_.exchange_seconds += MPI_Wtime() - start;
  }

  std::vector<std::vector<double>> gather_all(const std::vector<double>& mine) override {
    const Stopwatch watch(traffic_, mine.size());
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), starts(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    int total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) starts[r] = total, total += counts[r];
    std::vector<double> all(static_cast<std::size_t>(total));
    check(MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), starts.data(), MPI_DOUBLE,
                         MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<std::vector<double>> by_rank(counts.size());
    for (std::size_t r = 0; r < counts.size(); ++r) {
      by_rank[r].assign(all.begin() + starts[r], all.begin() + starts[r] + counts[r]);
    }
    return by_rank;
  }

  std::vector<std::vector<double>> gather_to_root(const std::vector<double>& mine) override {
    const Stopwatch watch(traffic_, mine.size());
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), starts(static_cast<std::size_t>(size_));
    check(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    int total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) starts[r] = total, total += counts[r];
    std::vector<double> all(rank_ == 0 ? static_cast<std::size_t>(total) : 0);
    check(MPI_Gatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), starts.data(), MPI_DOUBLE, 0,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    std::vector<std::vector<double>> by_rank;
    if (rank_ != 0) return by_rank;
    by_rank.resize(counts.size());
    for (std::size_t r = 0; r < counts.size(); ++r) {
      by_rank[r].assign(all.begin() + starts[r], all.begin() + starts[r] + counts[r]);
    }
    return by_rank;
  }

  [[noreturn]] void abort(int status) override {
    MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
  }

 private:
  static constexpr int kTag = 17;
  int rank_ = 0, size_ = 1;
  std::vector<MPI_Request> requests_;  ///< the receives, then the sends, of an exchange under way
  std::vector<std::vector<double>> received_;
};

}  // namespace

std::optional<int> first_failed_rank(Communicator& communicator, bool failed) {
  const std::vector<std::vector<double>> flags = communicator.gather_all({failed ? 1.0 : 0.0});
  for (std::size_t r = 0; r < flags.size(); ++r)
    if (flags[r].at(0) > 0.0) return static_cast<int>(r);
  return std::nullopt;
}

std::optional<RankFailure> first_failure(Communicator& communicator, const std::optional<std::string>& mine) {
  // The messages travel as doubles, one byte each (exact): a flag, then the bytes.
  constexpr std::size_t kMaxMessageBytes = 4096;
  std::vector<double> packed{mine ? 1.0 : 0.0};
  if (mine)
    for (std::size_t i = 0; i < std::min(mine->size(), kMaxMessageBytes); ++i)
      packed.push_back(static_cast<double>(static_cast<unsigned char>((*mine)[i])));
  const std::vector<std::vector<double>> all = communicator.gather_all(packed);
  for (std::size_t r = 0; r < all.size(); ++r) {
    if (!(all[r].at(0) > 0.0)) continue;
    RankFailure failure{static_cast<int>(r), {}};
    for (std::size_t i = 1; i < all[r].size(); ++i)
      failure.message.push_back(static_cast<char>(static_cast<unsigned char>(all[r][i])));
    return failure;
  }
  return std::nullopt;
}

std::vector<double> sum_in_rank_order(Communicator& communicator, const std::vector<double>& mine) {
  const std::vector<std::vector<double>> all = communicator.gather_all(mine);
  std::vector<double> sum(mine.size(), 0.0);
  for (const std::vector<double>& part : all) {
    if (part.size() != mine.size()) throw std::logic_error("sum_in_rank_order: ranks sum vectors of different lengths");
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += part[k];
  }
  return sum;
}

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

Communicator& single_process() {
  static SingleProcess one;
  return one;
}

Communicator& world() {
  if (launched_by_mpi()) {
    static MpiWorld mpi;
    return mpi;
  }
  return single_process();
}

std::string mpi_library_version() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string version(text, static_cast<std::size_t>(length));
  const auto end = version.find_first_of(",\n");
  return "MPI (" + version.substr(0, end) + ")";
}

}  // namespace settle::parallel
