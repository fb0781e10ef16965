#pragma once
// The exchange protocol of a block of a split lattice (docs/parallel.md): the halves of a step and
// of a window shift around the messages to and from the adjacent blocks. parallel::step and
// parallel::shift drive it (parallel/lattice_steps.hpp); the rest of the code steps and shifts a
// block through them. Only the parallel module includes this header (src/CMakeLists.txt, the
// RESTRICTED_HEADERS of the module table): a change of the protocol touches lbm and parallel alone.
#include <cstddef>
#include <vector>

#include "lbm/solver.hpp"

namespace settle::lbm {

/// The messages of one exchange between a block and the blocks adjacent to it, one per
/// BlockExchange::halo_ranks() entry and in that order: `send` what this block sends each of them,
/// `receive` what each of them sent to this one.
struct HaloMessages {
  std::vector<std::vector<double>> send, receive;
};

/// A block's step comes in two halves around the exchange of HaloMessages with the adjacent blocks:
/// begin_step runs the kernel and the copies of the block's own faces and fills messages.send;
/// end_step writes messages.receive into the block and finishes the step. Solver::step() refuses
/// to run when the block has neighbours.
class BlockExchange {
 public:
  virtual ~BlockExchange() = default;

  /// The ranks of the adjacent blocks the block exchanges with (ascending; empty when unsplit).
  virtual std::vector<int> halo_ranks() const = 0;
  virtual void begin_step(HaloMessages& messages) = 0;
  virtual void end_step(const HaloMessages& messages) = 0;
  /// begin_step in two parts, so that the messages can travel while the interior is updated:
  /// begin_step_faces runs the kernel on the rows near the faces shared with other blocks and fills
  /// messages.send; step_interior runs it on the other rows and copies the block's own faces. The
  /// result is begin_step's, bit for bit.
  virtual void begin_step_faces(HaloMessages& messages) = 0;
  virtual void step_interior() = 0;
  /// The length of the message each halo_ranks() entry sends this block in the coming step.
  virtual std::vector<std::size_t> halo_receive_counts() const = 0;

  /// The quadratic wall rule's far values (see WallRule): when true (a split block whose obstacle
  /// uses the quadratic rule; the same on every block), the step takes two more exchanges with
  /// the halo_ranks(). Before begin_step_faces: far_requests fills send with what this block needs
  /// of each adjacent one, take_far_requests keeps what they need of it. After the kernel and the
  /// halo messages, before end_step: far_answers fills send with the values asked for,
  /// take_far_answers writes what came back where the links read it.
  virtual bool exchanges_far_values() const = 0;
  virtual void far_requests(HaloMessages& messages) const = 0;
  virtual void take_far_requests(const HaloMessages& messages) = 0;
  virtual void far_answers(HaloMessages& messages) const = 0;
  virtual void take_far_answers(const HaloMessages& messages) = 0;

  /// Solver::shift on a block of a split lattice, around its exchanges: begin_shift moves the
  /// block's content and fills messages.send (the leaving layer, for the adjacent block it enters);
  /// after the exchange end_shift writes the entering layer. At an odd parity the ghosts must then be
  /// rebuilt from the adjacent blocks' new faces: end_shift returns true and has filled
  /// messages.send again; after that exchange end_ghost_refresh finishes the shift. The mass is
  /// this block's share: the layer that left the lattice here, the rest fluid that entered here.
  virtual ShiftMass begin_shift(int axis, int sign, HaloMessages& messages) = 0;
  virtual bool end_shift(HaloMessages& messages) = 0;
  virtual void end_ghost_refresh(const HaloMessages& messages) = 0;
};

}  // namespace settle::lbm
