#include "coupling/immersed_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "coupling/lattice_view.hpp"
#include "ibm/volume_fraction.hpp"

namespace settle::coupling {
namespace {

// Interior markers: a body-fixed cubic lattice of one-cell spacing centred on the centroid, kept
// where the point lies at least `depth_cells` below the surface. Each stands for one cell of volume.
void add_interior_markers(const body::Shape& shape, double dx_si, double depth_cells, BodyMarkers& markers) {
  const body::Aabb box = shape.bounding_box();
  const Eigen::Vector3d lo = box.lower / dx_si, hi = box.upper / dx_si;
  for (int k = static_cast<int>(std::ceil(lo.z())); k <= static_cast<int>(std::floor(hi.z())); ++k)
    for (int j = static_cast<int>(std::ceil(lo.y())); j <= static_cast<int>(std::floor(hi.y())); ++j)
      for (int i = static_cast<int>(std::ceil(lo.x())); i <= static_cast<int>(std::floor(hi.x())); ++i) {
        const Eigen::Vector3d p(i, j, k);
        if (shape.signed_distance(p * dx_si) > -depth_cells * dx_si) continue;
        markers.offset_b.push_back(p);
        markers.volume.push_back(1.0);
      }
}

// cell_state of each listed cell. Reading the list's bounding box a row at a time
// (Solver::box_states) costs a fraction of cell-by-cell reads per cell; it pays while the list
// fills at least a quarter of its box, as a body's cells do.
std::vector<lbm::CellState> states_through_box(const lbm::Solver& solver,
                                               const std::vector<std::array<int, 3>>& cells) {
  std::vector<lbm::CellState> states(cells.size());
  if (cells.empty()) return states;
  CellBox box{cells.front(), {1, 1, 1}};
  std::array<int, 3> upper = cells.front();
  for (const auto& c : cells)
    for (std::size_t a = 0; a < 3; ++a) {
      box.origin[a] = std::min(box.origin[a], c[a]);
      upper[a] = std::max(upper[a], c[a]);
    }
  for (std::size_t a = 0; a < 3; ++a) box.extent[a] = upper[a] - box.origin[a] + 1;
  if (box.cell_count() > 4 * cells.size()) {
    for (std::size_t n = 0; n < cells.size(); ++n) states[n] = solver.cell_state(cells[n][0], cells[n][1], cells[n][2]);
    return states;
  }
  std::vector<double> rho(box.cell_count());
  std::array<std::vector<double>, 3> u{rho, rho, rho};
  solver.box_states(box.origin, box.extent, rho.data(), {u[0].data(), u[1].data(), u[2].data()});
  for (std::size_t n = 0; n < cells.size(); ++n) {
    const std::size_t i = box.index_of(cells[n]);
    states[n] = {rho[i], Eigen::Vector3d(u[0][i], u[1][i], u[2][i])};
  }
  return states;
}

}  // namespace

BodyMarkers make_body_markers(const body::Shape& shape, double dx_si, double retraction_cells, bool interior) {
  const body::SurfaceMarkers surface = shape.surface_markers(dx_si);
  const double radius_cells = 0.5 * shape.equivalent_diameter() / dx_si;
  const double area_scale = std::pow(std::max(0.0, 1.0 - retraction_cells / radius_cells), 2);
  BodyMarkers markers;
  markers.offset_b.reserve(surface.size());
  markers.volume.reserve(surface.size());
  for (std::size_t l = 0; l < surface.size(); ++l) {
    markers.offset_b.push_back(surface.positions[l] / dx_si - retraction_cells * surface.normals[l]);
    // area in cells^2 times one cell width
    markers.volume.push_back(surface.areas[l] / (dx_si * dx_si) * area_scale);
  }
  if (interior) add_interior_markers(shape, dx_si, interior_lattice_depth_cells(retraction_cells), markers);
  return markers;
}

ibm::Markers place_markers(const BodyMarkers& markers, const Eigen::Vector3d& centre,
                           const Eigen::Matrix3d& body_to_inertial, const Eigen::Vector3d& velocity,
                           const Eigen::Vector3d& angular_velocity_n) {
  ibm::Markers placed;
  placed.position.reserve(markers.size());
  placed.target_velocity.reserve(markers.size());
  placed.volume = markers.volume;
  for (const Eigen::Vector3d& offset_b : markers.offset_b) {
    const Eigen::Vector3d arm = body_to_inertial * offset_b;
    placed.position.push_back(centre + arm);
    placed.target_velocity.push_back(velocity + angular_velocity_n.cross(arm));
  }
  return placed;
}

std::vector<std::array<int, 3>> cells_of(const CellBox& box) {
  std::vector<std::array<int, 3>> cells;
  cells.reserve(box.cell_count());
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i)
        cells.push_back({box.origin[0] + i, box.origin[1] + j, box.origin[2] + k});
  return cells;
}

std::vector<lbm::CellState> cell_states(const lbm::Solver& solver, const std::vector<std::array<int, 3>>& cells,
                                        parallel::Communicator& ranks) {
  const LatticeView view(solver);
  if (!view.split()) return states_through_box(solver, cells);
  std::vector<lbm::CellState> states(cells.size());
  // Each rank sends its cells' four values in list order; the owner of each cell says whose
  // message holds it next. Exact copies: every rank holds the owner's bits.
  constexpr std::size_t kValues = 4;
  std::vector<int> owner(cells.size());
  std::vector<double> mine;
  for (std::size_t n = 0; n < cells.size(); ++n) {
    const auto wrapped = view.wrap(cells[n]);
    if (!wrapped) throw std::logic_error("cell_states: a cell lies beyond a face that is not periodic");
    owner[n] = view.owner(*wrapped);
    if (owner[n] != view.rank()) continue;
    const auto l = view.to_block(*wrapped);
    const lbm::CellState s = solver.cell_state(l[0], l[1], l[2]);
    mine.insert(mine.end(), {s.density, s.velocity.x(), s.velocity.y(), s.velocity.z()});
  }
  const std::vector<std::vector<double>> parts = ranks.gather_all(mine);
  std::vector<std::size_t> read(parts.size(), 0);
  for (std::size_t n = 0; n < cells.size(); ++n) {
    const std::vector<double>& part = parts.at(static_cast<std::size_t>(owner[n]));
    std::size_t& at = read[static_cast<std::size_t>(owner[n])];
    if (at + kValues > part.size()) throw std::logic_error("cell_states: a rank sent fewer cells than it owns");
    states[n].density = part[at];
    states[n].velocity = Eigen::Vector3d(part[at + 1], part[at + 2], part[at + 3]);
    at += kValues;
  }
  return states;
}

ibm::LocalGrid gather(const lbm::Solver& solver, const CellBox& box, parallel::Communicator& ranks) {
  ibm::LocalGrid grid(box.origin, box.extent);
  if (!LatticeView(solver).split()) {
    solver.box_states(box.origin, box.extent, grid.rho.data(),
                      {grid.velocity[0].data(), grid.velocity[1].data(), grid.velocity[2].data()});
    return grid;
  }
  const std::vector<lbm::CellState> states = cell_states(solver, cells_of(box), ranks);
  for (std::size_t c = 0; c < states.size(); ++c) {
    grid.rho[c] = states[c].density;
    for (std::size_t a = 0; a < 3; ++a) grid.velocity[a][c] = states[c].velocity[static_cast<Eigen::Index>(a)];
  }
  return grid;
}

void scatter_forces(lbm::Solver& solver, const ibm::LocalGrid& grid) {
  const LatticeView view(solver);
  const auto& o = grid.origin();
  const auto& e = grid.extent();
  for (int k = 0; k < e[2]; ++k)
    for (int j = 0; j < e[1]; ++j)
      for (int i = 0; i < e[0]; ++i) {
        const std::size_t c = grid.index(i, j, k);
        const Eigen::Vector3d f(grid.force[0][c], grid.force[1][c], grid.force[2][c]);
        if (f.isZero(0.0)) continue;
        if (!view.split()) {
          solver.set_force(o[0] + i, o[1] + j, o[2] + k, f);
          continue;
        }
        const auto wrapped = view.wrap({o[0] + i, o[1] + j, o[2] + k});
        if (!wrapped || view.owner(*wrapped) != view.rank()) continue;
        const auto l = view.to_block(*wrapped);
        solver.set_force(l[0], l[1], l[2], f);
      }
}

double SolidCells::volume() const {
  double v = 0.0;
  for (double a : alpha) v += a;
  return v;
}

namespace {

// solid_cells with the signed distance `distance(p_b, inside)` of a body-frame point (SI) whose
// exact inside test gave `inside`.
template <class Distance>
SolidCells solid_cells_with(const body::Shape& shape, Distance&& distance, double dx_si, const CellBox& box,
                            const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) {
  const Eigen::Matrix3d inertial_to_body = body_to_inertial.transpose();
  const std::array<int, 3> n{box.extent[0] + 1, box.extent[1] + 1, box.extent[2] + 1};
  const auto corner_index = [&](int i, int j, int k) {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
  };
  const auto corner_point_b = [&](int i, int j, int k) -> Eigen::Vector3d {
    const Eigen::Vector3d corner(box.origin[0] + i - 0.5, box.origin[1] + j - 0.5, box.origin[2] + k - 0.5);
    return inertial_to_body * ((corner - centre) * dx_si);
  };
  const auto corners_of = [&](int i, int j, int k, auto&& visit) {
    for (int m = 0; m < 8; ++m) visit(corner_index(i + (m & 1), j + ((m >> 1) & 1), k + ((m >> 2) & 1)));
  };

  // Pass 1: which corners are inside (the cheap exact inside test). Corners farther than the
  // bounding radius plus two cells from the centre are outside without asking: every cell
  // touching one lies wholly outside (its diagonal is sqrt(3) < 2 cells).
  const double cull_radius = shape.bounding_radius() + 2.0 * dx_si;
  std::vector<unsigned char> inside(corner_index(n[0] - 1, n[1] - 1, n[2] - 1) + 1, 0);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Eigen::Vector3d p = corner_point_b(i, j, k);
        inside[corner_index(i, j, k)] = p.norm() <= cull_radius && shape.contains(p) ? 1 : 0;
      }

  // Pass 2: cells whose corners are all inside are solid (alpha = 1), all outside are fluid;
  // only cells the surface cuts need the signed distances of their corners, each corner
  // evaluated once. Serial on purpose: the box is small, and OpenMP regions this short cost more
  // than they save when the machine is shared.
  std::vector<double> phi(inside.size(), 0.0);
  std::vector<unsigned char> needed(inside.size(), 0);
  std::vector<unsigned char> cell_kind(box.cell_count(), 0);  // 0 fluid, 1 solid, 2 cut
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i) {
        int count = 0;
        corners_of(i, j, k, [&](std::size_t c) { count += inside[c]; });
        const std::size_t cell =
            static_cast<std::size_t>(i) +
            static_cast<std::size_t>(box.extent[0]) *
                (static_cast<std::size_t>(j) + static_cast<std::size_t>(box.extent[1]) * static_cast<std::size_t>(k));
        cell_kind[cell] = count == 0 ? 0 : count == 8 ? 1 : 2;
        if (cell_kind[cell] == 2) corners_of(i, j, k, [&](std::size_t c) { needed[c] = 1; });
      }
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        if (needed[corner_index(i, j, k)])
          phi[corner_index(i, j, k)] = distance(corner_point_b(i, j, k), inside[corner_index(i, j, k)] != 0) / dx_si;

  SolidCells cells;
  std::size_t cell = 0;
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i, ++cell) {
        double alpha = cell_kind[cell] == 1 ? 1.0 : 0.0;
        if (cell_kind[cell] == 2) {
          std::array<double, 8> corner{};
          std::size_t m = 0;
          corners_of(i, j, k, [&](std::size_t c) { corner[m++] = phi[c]; });
          alpha = ibm::cell_volume_fraction(corner);
        }
        if (alpha > 0.0) {
          cells.cell.push_back({box.origin[0] + i, box.origin[1] + j, box.origin[2] + k});
          cells.alpha.push_back(alpha);
        }
      }
  return cells;
}

}  // namespace

SolidCells solid_cells(const body::Shape& shape, double dx_si, const CellBox& box, const Eigen::Vector3d& centre,
                       const Eigen::Matrix3d& body_to_inertial) {
  return solid_cells_with(
      shape, [&](const Eigen::Vector3d& p, bool) { return shape.signed_distance(p); }, dx_si, box, centre,
      body_to_inertial);
}

SolidCells solid_cells(const body::DistanceTable& table, double dx_si, const CellBox& box,
                       const Eigen::Vector3d& centre, const Eigen::Matrix3d& body_to_inertial) {
  // The sign as the exact inside test says: next to the surface the interpolation may cross zero,
  // and the cell's kind (solid, cut, fluid) and its corners must agree. Clamped to zero there, not
  // mirrored, so that the value stays at or above the exact distance, as the table's is.
  const auto distance = [&](const Eigen::Vector3d& p, bool inside) {
    const double phi = table.signed_distance(p);
    return inside ? std::min(phi, 0.0) : std::max(phi, 0.0);
  };
  return solid_cells_with(table.shape(), distance, dx_si, box, centre, body_to_inertial);
}

FluidMomentum internal_momentum(const lbm::Solver& solver, const SolidCells& cells, const Eigen::Vector3d& centre,
                                parallel::Communicator& ranks) {
  FluidMomentum p;
  const std::vector<lbm::CellState> states = cell_states(solver, cells.cell, ranks);
  for (std::size_t n = 0; n < cells.cell.size(); ++n) {
    const auto& c = cells.cell[n];
    const lbm::CellState& s = states[n];
    const Eigen::Vector3d momentum = cells.alpha[n] * s.density * s.velocity;
    p.linear += momentum;
    p.angular += (Eigen::Vector3d(c[0], c[1], c[2]) - centre).cross(momentum);
  }
  return p;
}

LatticeWrench marker_reaction(const ibm::Markers& markers, const std::vector<Eigen::Vector3d>& marker_force,
                              const Eigen::Vector3d& centre) {
  LatticeWrench w;
  for (std::size_t l = 0; l < markers.size(); ++l) {
    const Eigen::Vector3d on_fluid = marker_force[l] * markers.volume[l];
    w.force -= on_fluid;
    w.torque -= (markers.position[l] - centre).cross(on_fluid);
  }
  return w;
}

LatticeWrench hydrodynamic_wrench(const LatticeWrench& reaction, const FluidMomentum& before,
                                  const FluidMomentum& after) {
  return {reaction.force + (after.linear - before.linear), reaction.torque + (after.angular - before.angular)};
}

}  // namespace settle::coupling
