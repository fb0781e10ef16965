#pragma once
// Ranks as threads of one process (tests only): a parallel::Communicator whose messages go through
// shared mailboxes, so that the blocks of a split run step together in one test program, each on
// its own thread, through the same code path that MPI processes take.
#include <condition_variable>
#include <cstdlib>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "parallel/communicator.hpp"

namespace settle::test {

class ThreadRanks {
 public:
  explicit ThreadRanks(int size) : size_(size), gathered_(static_cast<std::size_t>(size)) {
    ranks_.reserve(static_cast<std::size_t>(size));
    for (int r = 0; r < size; ++r) ranks_.emplace_back(*this, r);
  }

  /// Runs work(communicator) on `size` threads, one per rank, and waits for them all.
  void run(const std::function<void(parallel::Communicator&)>& work) {
    std::vector<std::thread> threads;
    for (Rank& rank : ranks_) threads.emplace_back([&work, &rank] { work(rank); });
    for (std::thread& t : threads) t.join();
  }

 private:
  class Rank final : public parallel::Communicator {
   public:
    Rank(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return all_.size_; }
    void exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
                  std::vector<std::vector<double>>& receive) override {
      std::unique_lock lock(all_.mutex_);
      for (std::size_t k = 0; k < ranks.size(); ++k) all_.mail_[{rank_, ranks[k]}].push_back(send[k]);
      all_.changed_.notify_all();
      receive.assign(ranks.size(), {});
      for (std::size_t k = 0; k < ranks.size(); ++k) {
        auto& box = all_.mail_[{ranks[k], rank_}];
        all_.changed_.wait(lock, [&box] { return !box.empty(); });
        receive[k] = std::move(box.front());
        box.erase(box.begin());
      }
    }
    std::vector<std::vector<double>> gather_all(const std::vector<double>& mine) override {
      std::unique_lock lock(all_.mutex_);
      // Two phases per round: everyone deposits, then everyone reads before the slots are reused.
      const long round = all_.round_;
      all_.gathered_[static_cast<std::size_t>(rank_)] = mine;
      if (++all_.arrived_ == all_.size_) {
        all_.arrived_ = 0, ++all_.round_;
        all_.changed_.notify_all();
      } else {
        all_.changed_.wait(lock, [&] { return all_.round_ != round; });
      }
      std::vector<std::vector<double>> all = all_.gathered_;
      if (++all_.read_ == all_.size_) {
        all_.read_ = 0, ++all_.read_round_;
        all_.changed_.notify_all();
      } else {
        const long read_round = all_.read_round_;
        all_.changed_.wait(lock, [&] { return all_.read_round_ != read_round; });
      }
      return all;
    }
    std::vector<std::vector<double>> gather_to_root(const std::vector<double>& mine) override {
      std::vector<std::vector<double>> all = gather_all(mine);
      if (rank_ != 0) all.clear();
      return all;
    }
    [[noreturn]] void abort(int) override { std::abort(); }

   private:
    ThreadRanks& all_;
    int rank_;
  };

  int size_;
  std::vector<Rank> ranks_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::pair<int, int>, std::vector<std::vector<double>>> mail_;  // (from, to) -> messages in order
  std::vector<std::vector<double>> gathered_;
  int arrived_ = 0, read_ = 0;
  long round_ = 0, read_round_ = 0;
};

}  // namespace settle::test
