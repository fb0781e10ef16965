#pragma once
// A block of a split lattice (lbm/decomposition.hpp) stepped and shifted with its messages sent
// through a communicator (docs/parallel.md): the exchanges between the halves of
// lbm::Solver::begin_step / end_step and begin_shift / end_shift / end_ghost_refresh.
#include "lbm/solver.hpp"
#include "parallel/communicator.hpp"

namespace settle::parallel {

/// One collide-and-stream step of this rank's block: the rows near its shared faces first, their
/// messages posted, then the interior while they travel (Solver::begin_step_faces); with the
/// quadratic wall rule the far values' requests before and answers after the kernel
/// (Solver::exchanges_far_values).
void step(lbm::Solver& block, Communicator& communicator);

/// The moving window across every rank's block; the mass that left and entered the whole lattice,
/// summed in rank order (the same on every rank).
lbm::ShiftMass shift(lbm::Solver& block, int axis, int sign, Communicator& communicator);

}  // namespace settle::parallel
