#pragma once
// A block of a split lattice (lbm/decomposition.hpp) stepped and shifted with its messages sent
// through a communicator (docs/parallel.md): the exchanges between the halves of the block's
// protocol (lbm/block_exchange.hpp, which no module but this one and lbm includes), begin_step /
// end_step and begin_shift / end_shift / end_ghost_refresh.
#include <vector>

#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"

namespace settle::parallel {

/// One collide-and-stream step of this rank's block: the rows near its shared faces first, their
/// messages posted, then the interior while they travel (BlockExchange::begin_step_faces); with the
/// quadratic wall rule the far values' requests before and answers after the kernel
/// (BlockExchange::exchanges_far_values).
void step(lbm::Solver& block, Communicator& communicator);

/// The moving window across every rank's block; the mass that left and entered the whole lattice,
/// summed in rank order (the same on every rank).
lbm::ShiftMass shift(lbm::Solver& block, int axis, int sign, Communicator& communicator);

/// The ranks of the blocks adjacent to this rank's block that it exchanges with (ascending; empty
/// when the lattice is not split): the neighbours of a coupling's own exchanges.
std::vector<int> neighbour_ranks(const lbm::Solver& block);

}  // namespace settle::parallel
