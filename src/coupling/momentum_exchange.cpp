#include "coupling/momentum_exchange.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <utility>

#include "coupling/lattice_view.hpp"
#include "parallel/lattice_steps.hpp"

namespace settle::coupling {
namespace {

// What a refill needs of a neighbour cell: solid (1) or not, density, non-equilibrium part.
constexpr std::size_t kNeighbourHeader = 2;

/// The mean of the non-equilibrium parts (`f_neq`, sized) of the candidates whose direction lies
/// at least `threshold` along the normal; zero when none does.
void mean_of_closest(const std::vector<std::pair<double, const double*>>& candidates, double threshold,
                     std::vector<double>& f_neq) {
  std::fill(f_neq.begin(), f_neq.end(), 0.0);
  int donors = 0;
  for (const auto& [along, neq] : candidates) {
    if (along < threshold) continue;
    for (std::size_t i = 0; i < f_neq.size(); ++i) f_neq[i] += neq[i];
    ++donors;
  }
  for (double& v : f_neq) v /= std::max(donors, 1);
}

}  // namespace

namespace {

// The body's box in lattice units and the body frame.
struct BoxFrame {
  const body::Shape& shape;
  double dx_si;
  const CellBox& box;
  const LatticePose& pose;
  const body::DistanceTable* inside_table = nullptr;
  Eigen::Matrix3d to_body = pose.body_to_inertial.transpose();
  // Cells farther from the centre than the bounding radius are outside without asking.
  double reach = shape.bounding_radius() / dx_si;

  Eigen::Vector3d body_point(const Eigen::Vector3d& x) const { return to_body * ((x - pose.centre) * dx_si); }
  Eigen::Vector3d cell_point(int i, int j, int k) const {
    return {double(box.origin[0] + i), double(box.origin[1] + j), double(box.origin[2] + k)};
  }
  std::size_t at(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(box.extent[0]) *
               (static_cast<std::size_t>(j) + static_cast<std::size_t>(box.extent[1]) * static_cast<std::size_t>(k));
  }
};

// Whether a cell's centre lies inside the body. With a table: the table's side where it settles it,
// else the shape's own test seen from a face neighbour that the table settles (Shape::contains_from:
// a mesh counts the crossings between them), else the shape's own test. The shape's queries are
// const and thread-safe (body/shape.hpp).
bool cell_inside(const BoxFrame& f, int i, int j, int k) {
  const Eigen::Vector3d x = f.cell_point(i, j, k);
  if ((x - f.pose.centre).norm() > f.reach) return false;
  const Eigen::Vector3d p = f.body_point(x);
  if (!f.inside_table) return f.shape.contains(p);
  const int side = f.inside_table->certain_side(p);
  if (side != 0) return side < 0;
  constexpr std::array<std::array<int, 3>, 6> kFaces{
      {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
  for (const auto& c : kFaces) {
    const Eigen::Vector3d reference = f.body_point(x + Eigen::Vector3d(c[0], c[1], c[2]));
    const int reference_side = f.inside_table->certain_side(reference);
    if (reference_side != 0) return f.shape.contains_from(p, reference, reference_side < 0);
  }
  return f.shape.contains(p);
}

// 1 for the box's cells whose centres lie inside the body.
std::vector<unsigned char> inside_cells(const BoxFrame& f) {
  std::vector<unsigned char> inside(f.box.cell_count(), 0);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < f.box.extent[2]; ++k)
    for (int j = 0; j < f.box.extent[1]; ++j)
      for (int i = 0; i < f.box.extent[0]; ++i)
        if (cell_inside(f, i, j, k)) inside[f.at(i, j, k)] = 1;
  return inside;
}

// The links from the fluid cells of plane k into the body, with their crossings (all of a cell's
// links in one query: a mesh then walks its tree once per cell).
void plane_links(const BoxFrame& f, const std::vector<unsigned char>& inside,
                 std::span<const std::array<int, 3>> velocities, int k, BodyWalls& result) {
  const CellBox& box = f.box;
  // Filled here and moved out at the end: the planes' vectors lie side by side, and growing them in
  // place from two threads would share their cache lines.
  BodyWalls plane;
  std::vector<std::size_t> directions;
  std::vector<Eigen::Vector3d> ends;
  std::vector<double> fractions;
  for (int j = 0; j < box.extent[1]; ++j)
    for (int i = 0; i < box.extent[0]; ++i) {
      const Eigen::Vector3d x = f.cell_point(i, j, k);
      if (inside[f.at(i, j, k)] || (x - f.pose.centre).norm() > f.reach + 2.0) continue;
      directions.clear();
      ends.clear();
      for (std::size_t dir = 1; dir < velocities.size(); ++dir) {
        const auto& c = velocities[dir];
        const int ni = i + c[0], nj = j + c[1], nk = k + c[2];
        if (ni < 0 || nj < 0 || nk < 0 || ni >= box.extent[0] || nj >= box.extent[1] || nk >= box.extent[2]) continue;
        if (!inside[f.at(ni, nj, nk)]) continue;
        directions.push_back(dir);
        ends.push_back(f.body_point(x + Eigen::Vector3d(c[0], c[1], c[2])));
      }
      if (directions.empty()) continue;
      fractions.resize(directions.size());
      f.shape.surface_crossings(f.body_point(x), ends, fractions);
      for (std::size_t n = 0; n < directions.size(); ++n) {
        const auto& c = velocities[directions[n]];
        const Eigen::Vector3d d(c[0], c[1], c[2]);
        // The lattice takes q in (0, 1]: a link whose fluid end lies on the surface (round-off) gets 1e-6.
        const double q = std::clamp(fractions[n], 1e-6, 1.0);
        const Eigen::Vector3d wall = x + q * d;
        plane.obstacle.links.push_back({{box.origin[0] + i, box.origin[1] + j, box.origin[2] + k},
                                        static_cast<int>(directions[n]),
                                        q,
                                        f.pose.velocity_at(wall)});
        plane.crossing.push_back(wall);
      }
    }
  result = std::move(plane);
}

}  // namespace

BodyWalls body_walls(const body::Shape& shape, double dx_si, const CellBox& box, const LatticePose& pose,
                     std::span<const std::array<int, 3>> velocities, lbm::WallRule rule,
                     const body::DistanceTable* inside_table) {
  const BoxFrame frame{shape, dx_si, box, pose, inside_table};
  const std::vector<unsigned char> inside = inside_cells(frame);
  BodyWalls walls;
  walls.obstacle.rule = rule;
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i)
        if (inside[frame.at(i, j, k)])
          walls.obstacle.solid_cells.push_back({box.origin[0] + i, box.origin[1] + j, box.origin[2] + k});
  // Each plane's links are found by one thread and joined in plane order: any thread count gives
  // the same walls in the same order.
  std::vector<BodyWalls> planes(static_cast<std::size_t>(box.extent[2]));
#pragma omp parallel for schedule(dynamic)
  for (int k = 0; k < box.extent[2]; ++k)
    plane_links(frame, inside, velocities, k, planes[static_cast<std::size_t>(k)]);
  for (const BodyWalls& plane : planes) {
    walls.obstacle.links.insert(walls.obstacle.links.end(), plane.obstacle.links.begin(), plane.obstacle.links.end());
    walls.crossing.insert(walls.crossing.end(), plane.crossing.begin(), plane.crossing.end());
  }
  return walls;
}

std::shared_ptr<const body::DistanceTable> inside_table_for(std::shared_ptr<const body::Shape> shape, double dx_si) {
  if (shape->contains_is_closed_form()) return nullptr;
  // A quarter cell, as the immersed boundary's table: the cells it leaves to the shape lie within
  // sqrt(3) / 8 of a cell of the surface. A band of one cell is more than the 2 sqrt(3) spacings
  // certain_side needs; beyond the body's box (and a margin of two nodes) every point is outside.
  const double spacing = 0.25 * dx_si;
  return std::make_shared<const body::DistanceTable>(std::move(shape), spacing, 2.0 * spacing, dx_si);
}

MomentumExchangeCoupling::MomentumExchangeCoupling(std::shared_ptr<const body::Shape> shape, double dx_si,
                                                   const CouplingOptions& options, parallel::Communicator& communicator)
    : shape_(std::move(shape)),
      dx_si_(dx_si),
      inside_table_(inside_table_for(shape_, dx_si_)),
      options_(options),
      communicator_(communicator) {}

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
  first_impose_ = true;
  // The fluid starts at rest inside the body too; the first impose makes those cells solid.
  place(fluid, pose);
}

void MomentumExchangeCoupling::place(const lbm::Solver& fluid, const LatticePose& pose) {
  pose_ = pose;
  placed_since_impose_ = true;
  BodyWalls whole = body_walls(*shape_, dx_si_, box_at(pose.centre, pose.body_to_inertial), pose,
                               lbm::velocity_set(fluid.config().lattice), options_.wall_rule, inside_table_.get());
  const LatticeView view(fluid);
  whole_link_count_ = whole.obstacle.links.size();
  std::vector<std::pair<std::size_t, std::array<int, 3>>> solids;
  for (const auto& c : whole.obstacle.solid_cells)
    if (const auto w = view.wrap(c)) solids.emplace_back(view.index(*w), c);
  std::sort(solids.begin(), solids.end());
  whole_solids_.clear();
  whole_solid_cells_.clear();
  for (const auto& [n, c] : solids) {
    whole_solids_.push_back(n);
    if (options_.covered_cell_torque) whole_solid_cells_.push_back(c);
  }
  link_index_.clear();
  if (!view.split()) {
    walls_ = std::move(whole);
    return;
  }
  walls_ = BodyWalls{};
  walls_.obstacle.rule = whole.obstacle.rule;
  walls_.crossing = std::move(whole.crossing);
  for (const auto& c : whole.obstacle.solid_cells) {
    const auto w = view.wrap(c);
    if (!w) continue;
    if (const auto local = view.in_padded_block(*w, view.rank())) {
      walls_.obstacle.solid_cells.push_back(*local);
    } else if (walls_.obstacle.rule != lbm::WallRule::quadratic) {
      continue;
    } else if (const auto far = view.in_padded_block(*w, view.rank(), 2)) {
      walls_.obstacle.far_solid_cells.push_back(*far);
    }
  }
  for (std::size_t k = 0; k < whole.obstacle.links.size(); ++k) {
    const auto w = view.wrap(whole.obstacle.links[k].cell);
    if (!w || view.owner(*w) != view.rank()) continue;
    lbm::WallLink link = whole.obstacle.links[k];
    link.cell = view.to_block(*w);
    walls_.obstacle.links.push_back(link);
    link_index_.push_back(k);
  }
}

std::unordered_map<std::size_t, MomentumExchangeCoupling::NeighbourCell> MomentumExchangeCoupling::neighbour_cells(
    const lbm::Solver& fluid) const {
  std::unordered_map<std::size_t, NeighbourCell> cells;
  const LatticeView view(fluid);
  if (!view.split()) return cells;
  // The box of the body and two layers more: every cell next to a cell the body uncovers.
  CellBox box = box_at(pose_.centre, pose_.body_to_inertial);
  for (std::size_t a = 0; a < 3; ++a) box.origin[a] -= 2, box.extent[a] += 4;
  // The box's cells once each, wrapped, in one order on every rank.
  std::vector<std::array<int, 3>> box_cells;
  std::unordered_set<std::size_t> seen;
  for (int k = 0; k < box.extent[2]; ++k)
    for (int j = 0; j < box.extent[1]; ++j)
      for (int i = 0; i < box.extent[0]; ++i) {
        const auto w = view.wrap({box.origin[0] + i, box.origin[1] + j, box.origin[2] + k});
        if (w && seen.insert(view.index(*w)).second) box_cells.push_back(*w);
      }
  const std::vector<int> neighbours = parallel::neighbour_ranks(fluid);
  const std::size_t q = static_cast<std::size_t>(fluid.velocity_count());
  std::vector<std::vector<double>> send(neighbours.size()), receive;
  std::vector<double> f_neq(q);
  for (std::size_t n = 0; n < neighbours.size(); ++n) {
    for (const auto& c : box_cells) {
      if (view.owner(c) != view.rank() || !view.in_padded_block(c, neighbours[n])) continue;
      const auto l = view.to_block(c);
      const bool solid = fluid.is_solid(l[0], l[1], l[2]);
      std::fill(f_neq.begin(), f_neq.end(), 0.0);
      const double density = solid ? 1.0 : fluid.non_equilibrium(l[0], l[1], l[2], f_neq);
      send[n].push_back(solid ? 1.0 : 0.0);
      send[n].push_back(density);
      send[n].insert(send[n].end(), f_neq.begin(), f_neq.end());
    }
  }
  communicator_.exchange(neighbours, send, receive);
  for (std::size_t n = 0; n < neighbours.size(); ++n) {
    std::size_t at = 0;
    for (const auto& c : box_cells) {
      if (view.owner(c) != neighbours[n] || !view.in_padded_block(c, view.rank())) continue;
      if (at + kNeighbourHeader + q > receive[n].size()) {
        throw std::logic_error("momentum exchange: a block sent fewer neighbour cells than its box holds");
      }
      NeighbourCell cell;
      cell.solid = receive[n][at] != 0.0;
      cell.density = receive[n][at + 1];
      cell.non_equilibrium.assign(receive[n].begin() + static_cast<std::ptrdiff_t>(at + kNeighbourHeader),
                                  receive[n].begin() + static_cast<std::ptrdiff_t>(at + kNeighbourHeader + q));
      at += kNeighbourHeader + q;
      cells.emplace(view.index(c), std::move(cell));
    }
  }
  return cells;
}

void MomentumExchangeCoupling::refill_uncovered(lbm::Solver& fluid) const {
  const LatticeView view(fluid);
  const std::unordered_map<std::size_t, NeighbourCell> remote = neighbour_cells(fluid);
  const auto now_solid = [&](const std::array<int, 3>& wrapped) {
    return std::binary_search(whole_solids_.begin(), whole_solids_.end(), view.index(wrapped));
  };
  const auto velocities = lbm::velocity_set(fluid.config().lattice);
  const std::size_t q = velocities.size();
  const Eigen::Matrix3d to_body = pose_.body_to_inertial.transpose();
  std::vector<double> f_neq(q);
  // The local neighbours' non-equilibrium parts, one row of q per neighbour, reused cell to cell.
  std::vector<double> local_neq(q * q);
  for (const std::array<int, 3>& local : fluid.solid_cell_list()) {
    const std::array<int, 3> x = view.to_lattice(local);
    if (now_solid(x)) continue;
    // The cell where the body is: across a periodic wrap from its wrapped coordinates when the
    // body straddles the wrap (its lever arm and normal would otherwise span the lattice).
    const std::array<int, 3> at = view.image_near(x, {pose_.centre.x(), pose_.centre.y(), pose_.centre.z()});
    const Eigen::Vector3d x_body(at[0], at[1], at[2]);
    // Away from the body: the outward normal at the nearest surface point.
    const Eigen::Vector3d p_b = to_body * ((x_body - pose_.centre) * dx_si_);
    const Eigen::Vector3d normal = pose_.body_to_inertial * shape_->outward_normal(shape_->closest_surface_point(p_b));
    double density_sum = 0.0;
    int count = 0;
    // The donor of the non-equilibrium part: the fluid neighbour along the lattice direction
    // closest to the normal. Directions tied to round-off (a normal halfway between two, as on the
    // grid's mirror planes through the body) share the role equally: a first-found rule would give
    // mirrored cells unmirrored refills, and a body on those planes a lateral force.
    constexpr double kTie = 1e-12;
    double best = -2.0;
    std::vector<std::pair<double, const double*>> candidates;  // (along the normal, f_neq)
    for (std::size_t j = 1; j < q; ++j) {
      const auto y = view.wrap({x[0] + velocities[j][0], x[1] + velocities[j][1], x[2] + velocities[j][2]});
      if (!y || now_solid(*y)) continue;
      const double* neq = nullptr;
      if (view.owner(*y) == view.rank()) {
        const std::array<int, 3> yl = view.to_block(*y);
        if (fluid.is_solid(yl[0], yl[1], yl[2])) continue;
        density_sum += fluid.cell_density(yl[0], yl[1], yl[2]);
        const std::span<double> row(local_neq.data() + j * q, q);
        fluid.non_equilibrium(yl[0], yl[1], yl[2], row);
        neq = row.data();
      } else {
        const auto it = remote.find(view.index(*y));
        if (it == remote.end()) throw std::logic_error("momentum exchange: no data for a neighbour in another block");
        if (it->second.solid) continue;
        density_sum += it->second.density;
        neq = it->second.non_equilibrium.data();
      }
      ++count;
      const Eigen::Vector3d c(velocities[j][0], velocities[j][1], velocities[j][2]);
      const double along = c.normalized().dot(normal);
      best = std::max(best, along);
      candidates.emplace_back(along, neq);
    }
    mean_of_closest(candidates, best - kTie, f_neq);
    const Eigen::Vector3d u = pose_.velocity_at(x_body);
    fluid.refill_cell_with(local, count > 0 ? density_sum / count : 1.0, u, f_neq);
  }
}

Eigen::Vector3d MomentumExchangeCoupling::covered_cell_torque(const lbm::Solver& fluid) const {
  const LatticeView view(fluid);
  std::vector<double> mine;  // (whole-lattice index, torque) of each covered cell of this block
  for (std::size_t k = 0; k < whole_solids_.size(); ++k) {
    const std::array<int, 3>& c = whole_solid_cells_[k];
    const std::array<int, 3> w = *view.wrap(c);
    if (view.owner(w) != view.rank()) continue;
    const std::array<int, 3> l = view.to_block(w);
    if (fluid.is_solid(l[0], l[1], l[2])) continue;
    const lbm::CellState s = fluid.cell_state(l[0], l[1], l[2]);
    const Eigen::Vector3d x(c[0], c[1], c[2]);
    const Eigen::Vector3d lag = s.density * (s.velocity - pose_.velocity_at(x));
    const Eigen::Vector3d t = (x - pose_.centre).cross(lag);
    mine.insert(mine.end(), {static_cast<double>(whole_solids_[k]), t.x(), t.y(), t.z()});
  }
  std::vector<std::pair<double, Eigen::Vector3d>> cells;
  const auto add_part = [&cells](const std::vector<double>& part) {
    for (std::size_t at = 0; at + 3 < part.size(); at += 4)
      cells.emplace_back(part[at], Eigen::Vector3d(part[at + 1], part[at + 2], part[at + 3]));
  };
  if (view.split()) {
    for (const std::vector<double>& part : communicator_.gather_all(mine)) add_part(part);
  } else {
    add_part(mine);
  }
  std::sort(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& cell : cells) sum += cell.second;
  return sum;
}

bool MomentumExchangeCoupling::lattice_has_solid_cells(const lbm::Solver& fluid) const {
  const double mine = static_cast<double>(fluid.solid_cell_count());
  if (!LatticeView(fluid).split()) return mine > 0.0;
  for (const std::vector<double>& part : communicator_.gather_all({mine}))
    if (!part.empty() && part[0] > 0.0) return true;
  return false;
}

void MomentumExchangeCoupling::impose(lbm::Solver& fluid) {
  // Walls held over a second lattice step (lattice_steps_per_body_step = 2) are in the fluid
  // already, and the cells covered when they were placed keep their torque for the pair.
  if (!placed_since_impose_) return;
  placed_since_impose_ = false;
  // A fresh start's first impose turns the body's own cells solid: nothing is covered then. A
  // restored run's fluid already holds them, and its first impose covers cells as any other does.
  bool count = options_.covered_cell_torque;
  if (count && first_impose_) count = lattice_has_solid_cells(fluid);
  first_impose_ = false;
  covered_torque_ = count ? covered_cell_torque(fluid) : Eigen::Vector3d::Zero();
  refill_uncovered(fluid);
  fluid.set_obstacle(walls_.obstacle);
}

LatticeWrench MomentumExchangeCoupling::link_sum(const lbm::Solver& fluid) const {
  const std::vector<Eigen::Vector3d>& momentum = fluid.wall_momentum();
  // One loop adds the links for one process and for a split alike: two loops of the same sum may
  // be compiled apart, and where the compiler fuses a multiply and an add (-march=native with
  // FMA) they then round the torque's cross products differently, so a split run left the
  // one-process run in the last bit (tests/coupling/test_split_simulation.cpp).
  const bool split = LatticeView(fluid).split();
  const std::vector<Eigen::Vector3d> gathered =
      split ? gathered_link_momenta(momentum) : std::vector<Eigen::Vector3d>{};
  const std::vector<Eigen::Vector3d>& ordered = split ? gathered : momentum;
  LatticeWrench links;
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    links.force += ordered[k];
    links.torque += (walls_.crossing[k] - pose_.centre).cross(ordered[k]);
  }
  return links;
}

std::vector<Eigen::Vector3d> MomentumExchangeCoupling::gathered_link_momenta(
    const std::vector<Eigen::Vector3d>& momentum) const {
  // Every block's links in the whole lattice's link order, so that the sum is the one process's
  // bit for bit (at the cost of every rank receiving every link's momentum).
  std::vector<double> mine;
  mine.reserve(4 * momentum.size());
  for (std::size_t k = 0; k < momentum.size(); ++k) {
    mine.insert(mine.end(), {static_cast<double>(link_index_[k]), momentum[k].x(), momentum[k].y(), momentum[k].z()});
  }
  std::vector<Eigen::Vector3d> ordered(whole_link_count_, Eigen::Vector3d::Zero());
  std::vector<char> have(whole_link_count_, 0);
  for (const std::vector<double>& part : communicator_.gather_all(mine)) {
    for (std::size_t at = 0; at + 3 < part.size(); at += 4) {
      const auto k = static_cast<std::size_t>(part[at]);
      ordered.at(k) = Eigen::Vector3d(part[at + 1], part[at + 2], part[at + 3]);
      have[k] = 1;
    }
  }
  if (std::count(have.begin(), have.end(), 1) != static_cast<std::ptrdiff_t>(whole_link_count_)) {
    throw std::logic_error("momentum exchange: the blocks' links do not add up to the body's");
  }
  return ordered;
}

CouplingForces MomentumExchangeCoupling::measure(const lbm::Solver& fluid) {
  const LatticeWrench links = link_sum(fluid);
  CouplingForces f;
  f.surface.force = 0.5 * (links.force + previous_links_.force);
  // The covered cells' angular momentum is an impulse of the placement, spread over the lattice
  // steps the placement lasts.
  f.surface.torque = 0.5 * (links.torque + previous_links_.torque) +
                     covered_torque_ / static_cast<double>(options_.lattice_steps_per_body_step);
  previous_links_ = links;
  // A body force on the fluid stands for a mean pressure gradient, which pushes on the body's
  // volume too; inside an immersed boundary the enclosed fluid passes it on, here the solid
  // cells take it directly.
  f.total = f.surface;
  f.total.force += fluid.config().body_force * static_cast<double>(whole_solids_.size());
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
