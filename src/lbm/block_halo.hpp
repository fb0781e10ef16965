#pragma once
// A block's halo links with the adjacent blocks of a split lattice (docs/parallel.md, "What crosses
// a block face"): what it sends each of them after its kernel (the copy lists evaluated as its own
// would be at that point of the step) and where what they send goes (the slots the copy lists
// would write if their cells were here). Which copy list applies follows the parity, as in
// waLBerla's CombinedInPlaceCpuPackInfo: the fill after an even kernel, the fold after an odd one.
#include <Eigen/Core>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "lbm/aa_populations.hpp"
#include "lbm/block_exchange.hpp"
#include "lbm/block_geometry.hpp"
#include "lbm/grid.hpp"

namespace settle::lbm {

template <Lattice L, class Real>
class BlockHalo {
 public:
  BlockHalo(std::vector<HaloLinks> links, const BlockGeometry& geometry) : links_(std::move(links)) {
    split_rows(geometry);
  }

  bool empty() const { return links_.empty(); }
  std::size_t size() const { return links_.size(); }
  /// The ranks of the adjacent blocks, ascending: the order of every HaloMessages.
  std::vector<int> ranks() const {
    std::vector<int> ranks;
    for (const HaloLinks& h : links_) ranks.push_back(h.rank);
    return ranks;
  }
  std::size_t index_of(int rank) const {
    for (std::size_t k = 0; k < links_.size(); ++k)
      if (links_[k].rank == rank) return k;
    throw std::logic_error("halo: rank " + std::to_string(rank) + " is not an adjacent block");
  }
  /// The length of each adjacent block's message in the coming step.
  std::vector<std::size_t> receive_counts(bool odd) const {
    std::vector<std::size_t> counts;
    for (const HaloLinks& h : links_) counts.push_back(odd ? h.fold_receive.size() : h.fill_receive.size());
    return counts;
  }
  /// A block's rows (y + ny z) near the faces it shares with other blocks, and the rest.
  const std::vector<int>& face_rows() const { return face_rows_; }
  const std::vector<int>& interior_rows() const { return interior_rows_; }

  /// Fills messages.send after the kernel of the current parity.
  void pack(const AaPopulations<L, Real>& f, const Eigen::Vector3d& inflow, HaloMessages& messages) const {
    messages.send.resize(links_.size());
    for (std::size_t k = 0; k < links_.size(); ++k) {
      const CopyLists& send = links_[k].send;
      if (f.odd_parity()) {
        pack<true>(f, inflow, send.fold, send.fold_shifted, messages.send[k]);
      } else {
        pack<false>(f, inflow, send.fill, send.fill_shifted, messages.send[k]);
      }
    }
  }
  /// Fills messages.send with the fill values whatever the parity: the ghosts' rebuild after a
  /// window shift at an odd parity.
  void pack_fill(const AaPopulations<L, Real>& f, const Eigen::Vector3d& inflow, HaloMessages& messages) const {
    messages.send.resize(links_.size());
    for (std::size_t k = 0; k < links_.size(); ++k)
      pack<false>(f, inflow, links_[k].send.fill, links_[k].send.fill_shifted, messages.send[k]);
  }

  /// Writes what the adjacent blocks sent into the slots of their links: the fold after an odd
  /// kernel, the fill after an even one.
  void write_received(AaPopulations<L, Real>& f, const HaloMessages& messages, bool fold, const char* who) const {
    Real* const data = f.data();
    for (std::size_t k = 0; k < links_.size(); ++k) {
      const std::vector<std::size_t>& slots = fold ? links_[k].fold_receive : links_[k].fill_receive;
      const std::vector<double>& values = messages.receive[k];
      if (values.size() != slots.size()) {
        throw std::invalid_argument(std::string(who) + ": a message of " + std::to_string(values.size()) +
                                    " values from rank " + std::to_string(links_[k].rank) + ", expected " +
                                    std::to_string(slots.size()));
      }
      for (std::size_t j = 0; j < slots.size(); ++j) data[slots[j]] = static_cast<Real>(values[j]);
    }
  }
  void check_message_count(const HaloMessages& messages, const char* who) const {
    if (messages.receive.size() != links_.size()) {
      throw std::invalid_argument(std::string(who) + ": " + std::to_string(messages.receive.size()) + " messages for " +
                                  std::to_string(links_.size()) + " adjacent blocks");
    }
  }

 private:
  /// The values of a block's send entries (HaloLinks), each as the copy lists would store it.
  template <bool Odd>
  static void pack(const AaPopulations<L, Real>& f, const Eigen::Vector3d& inflow, const std::vector<CopyEntry>& list,
                   const std::vector<ShiftedCopyEntry>& shifted, std::vector<double>& message) {
    const Real* const data = f.data();
    message.assign(list.size() + shifted.size(), 0.0);
    for (const CopyEntry& e : list) message[e.dst] = static_cast<double>(data[e.src]);
    for (const ShiftedCopyEntry& e : shifted)
      message[e.dst] = static_cast<double>(f.template shifted_value<Odd>(e, inflow));
  }

  /// The rows whose kernel results an adjacent block receives: those within kFaceRows of a face
  /// the block shares with another block along y or z (a link's source cell is next to the face,
  /// and an inlet's or outlet's value reads the moments of a cell one further in; a margin of
  /// three covers both). A block cut along x has a face cell in every row: all rows are face rows.
  void split_rows(const BlockGeometry& geometry) {
    constexpr int kFaceRows = 3;
    const int ny = geometry.extent()[1], nz = geometry.extent()[2];
    const auto shares = [&](std::size_t axis, int side) { return geometry.has_block_beyond(axis, side, true); };
    const bool all_faces = shares(0, 0) || shares(0, 1);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y) {
        const bool near = all_faces || (shares(1, 0) && y < kFaceRows) || (shares(1, 1) && y >= ny - kFaceRows) ||
                          (shares(2, 0) && z < kFaceRows) || (shares(2, 1) && z >= nz - kFaceRows);
        (near ? face_rows_ : interior_rows_).push_back(y + ny * z);
      }
  }

  std::vector<HaloLinks> links_;
  std::vector<int> face_rows_, interior_rows_;
};

}  // namespace settle::lbm
