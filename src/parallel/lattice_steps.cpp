#include "parallel/lattice_steps.hpp"

#include <vector>

#include "lbm/block_exchange.hpp"

namespace settle::parallel {

void step(lbm::Solver& solver, Communicator& communicator) {
  lbm::BlockExchange& block = solver.block_exchange();
  lbm::HaloMessages messages, far;
  const std::vector<int> neighbours = block.halo_ranks();
  const bool far_values = block.exchanges_far_values();
  if (far_values) {
    block.far_requests(far);
    communicator.exchange(neighbours, far.send, far.receive);
    block.take_far_requests(far);
  }
  block.begin_step_faces(messages);
  communicator.start_exchange(neighbours, messages.send, block.halo_receive_counts());
  block.step_interior();
  communicator.finish_exchange(messages.receive);
  if (far_values) {
    block.far_answers(far);
    communicator.exchange(neighbours, far.send, far.receive);
    block.take_far_answers(far);
  }
  block.end_step(messages);
}

lbm::ShiftMass shift(lbm::Solver& solver, int axis, int sign, Communicator& communicator) {
  lbm::BlockExchange& block = solver.block_exchange();
  lbm::HaloMessages messages;
  const std::vector<int> neighbours = block.halo_ranks();
  const lbm::ShiftMass mine = block.begin_shift(axis, sign, messages);
  communicator.exchange(neighbours, messages.send, messages.receive);
  if (block.end_shift(messages)) {
    communicator.exchange(neighbours, messages.send, messages.receive);
    block.end_ghost_refresh(messages);
  }
  const std::vector<double> total = sum_in_rank_order(communicator, {mine.left, mine.entered});
  return {total[0], total[1]};
}

std::vector<int> neighbour_ranks(const lbm::Solver& block) { return block.block_exchange().halo_ranks(); }

}  // namespace settle::parallel
