#include "coupling/momentum_exchange.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <unordered_set>
#include <utility>

namespace settle::coupling {
namespace {

/// Interior cell index with periodic axes wrapped, or nullopt outside a non-periodic axis.
std::optional<std::size_t> wrapped_index(const lbm::Solver& fluid, const std::array<int, 3>& c) {
  const std::array<int, 3> n{fluid.nx(), fluid.ny(), fluid.nz()};
  std::array<int, 3> w{};
  for (std::size_t a = 0; a < 3; ++a) {
    w[a] = c[a];
    if (w[a] >= 0 && w[a] < n[a]) continue;
    if (fluid.config().boundaries[a] != lbm::Boundary::periodic) return std::nullopt;
    w[a] = ((w[a] % n[a]) + n[a]) % n[a];
  }
  return fluid.linear_index(w[0], w[1], w[2]);
}

}  // namespace

BodyWalls body_walls(const body::Shape& shape, double dx_si, const CellBox& box, const LatticePose& pose,
                     std::span<const std::array<int, 3>> velocities, lbm::WallRule rule) {
  const Eigen::Matrix3d to_body = pose.body_to_inertial.transpose();
  const auto body_point = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    return to_body * ((x - pose.centre) * dx_si);
  };
  const auto cell_point = [&](int i, int j, int k) {
    return Eigen::Vector3d(box.origin[0] + i, box.origin[1] + j, box.origin[2] + k);
  };
  const auto at = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(box.extent[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(box.extent[1]) * static_cast<std::size_t>(k));
  };
  // Cells farther from the centre than the bounding radius are outside without asking.
  const double reach = shape.bounding_radius() / dx_si;
  std::vector<unsigned char> inside(box.cell_count(), 0);
  BodyWalls walls;
  walls.obstacle.rule = rule;
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i) {
        const Eigen::Vector3d x = cell_point(i, j, k);
        if ((x - pose.centre).norm() > reach || !shape.contains(body_point(x))) continue;
        inside[at(i, j, k)] = 1;
        walls.obstacle.solid_cells.push_back({box.origin[0] + i, box.origin[1] + j, box.origin[2] + k});
      }
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i) {
        const Eigen::Vector3d x = cell_point(i, j, k);
        if (inside[at(i, j, k)] || (x - pose.centre).norm() > reach + 2.0) continue;
        for (std::size_t dir = 1; dir < velocities.size(); ++dir) {
          const auto& c = velocities[dir];
          const int ni = i + c[0], nj = j + c[1], nk = k + c[2];
          if (ni < 0 || nj < 0 || nk < 0 || ni >= box.extent[0] || nj >= box.extent[1] || nk >= box.extent[2]) continue;
          if (!inside[at(ni, nj, nk)]) continue;
          const Eigen::Vector3d d(c[0], c[1], c[2]);
          // The lattice takes q in (0, 1]: a link whose fluid end lies on the surface (round-off) gets 1e-6.
          const double q = std::clamp(shape.surface_crossing(body_point(x), body_point(x + d)), 1e-6, 1.0);
          const Eigen::Vector3d wall = x + q * d;
          walls.obstacle.links.push_back({{box.origin[0] + i, box.origin[1] + j, box.origin[2] + k},
                                          static_cast<int>(dir),
                                          q,
                                          pose.velocity_at(wall)});
          walls.crossing.push_back(wall);
        }
      }
  return walls;
}

MomentumExchangeCoupling::MomentumExchangeCoupling(std::shared_ptr<const body::Shape> shape, double dx_si,
                                                   const CouplingOptions& options)
    : shape_(std::move(shape)), dx_si_(dx_si), options_(options) {}

CellBox momentum_exchange_box(const body::Shape& shape, double dx_si, const Eigen::Vector3d& centre,
                              const Eigen::Matrix3d& body_to_inertial) {
  // Every cell whose centre can lie inside the body, and one layer around them: the fluid ends
  // of the links and the cells a refill reads.
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d axis_b = body_to_inertial.row(a).transpose();
    const int first = static_cast<int>(std::ceil(centre[a] - shape.support(-axis_b) / dx_si)) - 1;
    const int last = static_cast<int>(std::floor(centre[a] + shape.support(axis_b) / dx_si)) + 1;
    box.origin[static_cast<std::size_t>(a)] = first;
    box.extent[static_cast<std::size_t>(a)] = last - first + 1;
  }
  return box;
}

CellBox MomentumExchangeCoupling::box_at(const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) const {
  return momentum_exchange_box(*shape_, dx_si_, centre, body_to_inertial);
}

void MomentumExchangeCoupling::start(lbm::Solver& fluid, const LatticePose& pose) {
  previous_links_ = LatticeWrench{};
  // The fluid starts at rest inside the body too; the first impose makes those cells solid.
  place(fluid, pose);
}

void MomentumExchangeCoupling::place(const lbm::Solver& fluid, const LatticePose& pose) {
  pose_ = pose;
  walls_ = body_walls(*shape_, dx_si_, box_at(pose.centre, pose.body_to_inertial), pose,
                      lbm::velocity_set(fluid.config().lattice), options_.wall_rule);
}

void MomentumExchangeCoupling::refill_uncovered(lbm::Solver& fluid) const {
  std::unordered_set<std::size_t> now_solid;
  for (const auto& c : walls_.obstacle.solid_cells)
    if (const auto n = wrapped_index(fluid, c)) now_solid.insert(*n);
  const auto fluid_before_and_after = [&](const std::array<int, 3>& c) {
    const auto n = wrapped_index(fluid, c);
    return n && !now_solid.count(*n) && !fluid.is_solid(c[0], c[1], c[2]);
  };
  const auto velocities = lbm::velocity_set(fluid.config().lattice);
  const Eigen::Matrix3d to_body = pose_.body_to_inertial.transpose();
  for (const std::array<int, 3>& x : fluid.solid_cell_list()) {
    if (now_solid.count(fluid.linear_index(x[0], x[1], x[2]))) continue;
    // Away from the body: the outward normal at the nearest surface point.
    const Eigen::Vector3d p_b = to_body * ((Eigen::Vector3d(x[0], x[1], x[2]) - pose_.centre) * dx_si_);
    const Eigen::Vector3d normal = pose_.body_to_inertial * shape_->outward_normal(shape_->closest_surface_point(p_b));
    double density_sum = 0.0;
    int count = 0;
    std::optional<std::array<int, 3>> donor;
    double best = -2.0;
    for (std::size_t j = 1; j < velocities.size(); ++j) {
      const std::array<int, 3> y{x[0] + velocities[j][0], x[1] + velocities[j][1], x[2] + velocities[j][2]};
      if (!fluid_before_and_after(y)) continue;
      density_sum += fluid.cell_density(y[0], y[1], y[2]);
      ++count;
      const Eigen::Vector3d c(velocities[j][0], velocities[j][1], velocities[j][2]);
      const double along = c.normalized().dot(normal);
      if (along > best) best = along, donor = y;
    }
    const Eigen::Vector3d u = pose_.velocity_at(Eigen::Vector3d(x[0], x[1], x[2]));
    fluid.refill_cell(x, count > 0 ? density_sum / count : 1.0, u, donor);
  }
}

void MomentumExchangeCoupling::impose(lbm::Solver& fluid) {
  refill_uncovered(fluid);
  fluid.set_obstacle(walls_.obstacle);
}

CouplingForces MomentumExchangeCoupling::measure(const lbm::Solver& fluid) {
  LatticeWrench links;
  const auto& momentum = fluid.wall_momentum();
  for (std::size_t k = 0; k < momentum.size(); ++k) {
    links.force += momentum[k];
    links.torque += (walls_.crossing[k] - pose_.centre).cross(momentum[k]);
  }
  CouplingForces f;
  f.surface.force = 0.5 * (links.force + previous_links_.force);
  f.surface.torque = 0.5 * (links.torque + previous_links_.torque);
  previous_links_ = links;
  // A body force on the fluid stands for a mean pressure gradient, which pushes on the body's
  // volume too; inside an immersed boundary the enclosed fluid passes it on, here the solid
  // cells take it directly.
  f.total = f.surface;
  f.total.force += fluid.config().body_force * static_cast<double>(fluid.solid_cell_count());
  return f;
}

std::array<double, 6> MomentumExchangeCoupling::carried_state() const {
  const auto& f = previous_links_.force;
  const auto& t = previous_links_.torque;
  return {f.x(), f.y(), f.z(), t.x(), t.y(), t.z()};
}

void MomentumExchangeCoupling::restore_carried_state(const std::array<double, 6>& state) {
  previous_links_.force = Eigen::Vector3d(state[0], state[1], state[2]);
  previous_links_.torque = Eigen::Vector3d(state[3], state[4], state[5]);
}

}  // namespace settle::coupling
