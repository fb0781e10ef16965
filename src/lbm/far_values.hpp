#pragma once
// The quadratic wall rule's far values (docs/parallel.md, "The moving window and bodies"): a link
// whose x - c_i is a ghost reads its third value, f*_i(x - 2 c_i) (q < 1/2) or f*_opp(i)(x - c_i)
// (q >= 1/2), from a cell beyond the padded block. After a periodic wrap of one block that cell is
// the block's own and is read in place; on a split lattice it belongs to an adjacent block, which
// answers a request (cell in its coordinates and population, four values each) after its kernel.
// The exchange around the step is parallel::step's (lbm/block_exchange.hpp).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/lattice.hpp"

namespace settle::lbm {

class FarValues {
 public:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  /// No far values (no links need them).
  void clear() { *this = {}; }
  /// Forgets every value; `halo_count` adjacent blocks (BlockHalo order) may be asked.
  void reset(std::size_t halo_count) {
    clear();
    requests_.resize(halo_count);
    answers_to_.resize(halo_count);
  }
  /// A far value read here: f*_j of this block's padded cell `cell`. Returns its entry.
  std::size_t add_local(std::size_t cell, int j) {
    local_.push_back({values_.size(), cell, j});
    values_.push_back(0.0);
    return values_.size() - 1;
  }
  /// A far value asked of the block at `halo` (its cell y in its coordinates, population j).
  std::size_t add_request(std::size_t halo, const std::array<int, 3>& y, int j) {
    requests_[halo].insert(requests_[halo].end(), {static_cast<double>(y[0]), static_cast<double>(y[1]),
                                                   static_cast<double>(y[2]), static_cast<double>(j)});
    answers_to_[halo].push_back(values_.size());
    values_.push_back(0.0);
    return values_.size() - 1;
  }
  double value(std::size_t entry) const { return values_[entry]; }

  /// After the kernel of the given parity: the values this block holds itself.
  template <bool Odd, Lattice L, class Real>
  void read_local(const AaPopulations<L, Real>& f) {
    for (const Local& e : local_) values_[e.value] = f.template post_collision<Odd>(e.population, e.cell);
  }

  /// Fills send with what this block asks of each of `halo_count` adjacent blocks.
  void requests(HaloMessages& messages, std::size_t halo_count) const {
    messages.send.assign(halo_count, {});
    for (std::size_t k = 0; k < requests_.size(); ++k) messages.send[k] = requests_[k];
  }
  /// Keeps what the adjacent blocks ask of this one, after checking each request against the
  /// block's extent and the lattice's populations.
  void take_requests(const HaloMessages& messages, const std::array<int, 3>& extent, int q) {
    for (const std::vector<double>& asked : messages.receive) {
      if (asked.size() % 4 != 0) throw std::invalid_argument("take_far_requests: a request holds four values");
      for (std::size_t n = 0; n < asked.size(); n += 4) {
        for (std::size_t a = 0; a < 3; ++a) {
          if (!(asked[n + a] >= 0.0 && asked[n + a] < extent[a])) {
            throw std::invalid_argument("take_far_requests: a requested cell lies outside the block");
          }
        }
        if (!(asked[n + 3] >= 0.0 && asked[n + 3] < q)) {
          throw std::invalid_argument("take_far_requests: a requested population is out of range");
        }
      }
    }
    asked_ = messages.receive;
  }
  /// Fills send with the post-collision values asked of this block, after its kernel.
  template <Lattice L, class Real>
  void answers(HaloMessages& messages, std::size_t halo_count, const AaPopulations<L, Real>& f) const {
    messages.send.assign(halo_count, {});
    for (std::size_t k = 0; k < asked_.size(); ++k) {
      const std::vector<double>& asked = asked_[k];
      for (std::size_t n = 0; n < asked.size(); n += 4) {
        const auto at = [&](std::size_t m) { return static_cast<int>(asked[n + m]); };
        const std::size_t cell = f.layout().index(at(0), at(1), at(2));
        messages.send[k].push_back(f.odd_parity() ? f.template post_collision<true>(at(3), cell)
                                                  : f.template post_collision<false>(at(3), cell));
      }
    }
  }
  /// Writes the answers where the links read them; `ranks` names the adjacent blocks in messages.
  void take_answers(const HaloMessages& messages, const std::vector<int>& ranks) {
    for (std::size_t k = 0; k < ranks.size(); ++k) {
      const std::vector<std::size_t> none;
      const std::vector<std::size_t>& to = k < answers_to_.size() ? answers_to_[k] : none;
      if (messages.receive[k].size() != to.size()) {
        throw std::invalid_argument("take_far_answers: " + std::to_string(messages.receive[k].size()) +
                                    " values from rank " + std::to_string(ranks[k]) + ", expected " +
                                    std::to_string(to.size()));
      }
      for (std::size_t n = 0; n < to.size(); ++n) values_[to[n]] = messages.receive[k][n];
    }
  }

 private:
  struct Local {
    std::size_t value = 0, cell = 0;  ///< entry of values_; the interior cell y (padded index)
    int population = 0;               ///< j of f*_j(y)
  };
  std::vector<double> values_;
  std::vector<Local> local_;  ///< those this block holds (across a periodic wrap)
  /// Per adjacent block: what this block asks of it (four values each), the entry of values_ each
  /// answer fills, and what it asked of this block.
  std::vector<std::vector<double>> requests_;
  std::vector<std::vector<std::size_t>> answers_to_;
  std::vector<std::vector<double>> asked_;
};

}  // namespace settle::lbm
