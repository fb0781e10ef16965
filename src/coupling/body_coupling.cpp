#include "coupling/body_coupling.hpp"

#include <fmt/format.h>

#include "common/error.hpp"
#include "coupling/immersed_boundary_coupling.hpp"
#include "coupling/momentum_exchange.hpp"

namespace settle::coupling {

std::string to_string(CouplingKind kind) {
  return kind == CouplingKind::momentum_exchange ? "momentum_exchange" : "immersed_boundary";
}

CouplingKind parse_coupling(const std::string& name, const std::string& what) {
  if (name == "immersed_boundary") return CouplingKind::immersed_boundary;
  if (name == "momentum_exchange") return CouplingKind::momentum_exchange;
  throw InputError(fmt::format("{}: must be immersed_boundary or momentum_exchange, got '{}'", what, name));
}

double coupling_reach_cells(const CouplingOptions& options) {
  if (options.kind == CouplingKind::momentum_exchange) return kMomentumExchangeReachCells;
  return ibm::support_half_width(options.kernel);
}

CellBox coupling_box(const CouplingOptions& options, const body::Shape& shape, double dx_si,
                     const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) {
  if (options.kind == CouplingKind::momentum_exchange)
    return momentum_exchange_box(shape, dx_si, centre, body_to_inertial);
  return immersed_boundary_box(shape, dx_si, options.kernel, centre, body_to_inertial);
}

std::unique_ptr<BodyCoupling> make_coupling(std::shared_ptr<const body::Shape> shape, double dx_si,
                                            const CouplingOptions& options, parallel::Communicator& communicator) {
  if (options.kind == CouplingKind::momentum_exchange)
    return std::make_unique<MomentumExchangeCoupling>(std::move(shape), dx_si, options, communicator);
  return std::make_unique<ImmersedBoundaryCoupling>(std::move(shape), dx_si, options, communicator);
}

}  // namespace settle::coupling
