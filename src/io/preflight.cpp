#include "io/preflight.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/core.h>

#include "common/error.hpp"
#include "common/require.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/runner.hpp"
#include "io/window_advice.hpp"
#include "lbm/config.hpp"
#include "lbm/grid.hpp"
#include "lbm/lattice.hpp"

namespace settle::io {
namespace {

namespace fs = std::filesystem;

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
constexpr double kMiB = 1024.0 * 1024.0;
constexpr std::size_t kPageBytes = 4096;
constexpr char kAxis[] = "xyz";

std::string bytes_text(double bytes) {
  if (bytes >= kGiB) return fmt::format("{:.3g} GiB", bytes / kGiB);
  if (bytes >= kMiB) return fmt::format("{:.3g} MiB", bytes / kMiB);
  return fmt::format("{:.3g} KiB", bytes / 1024.0);
}

double page_rounded(double bytes) { return std::ceil(bytes / kPageBytes) * kPageBytes; }

// ---- 1. numbers -------------------------------------------------------------------------

void require_finite(double value, std::string_view key) {
  if (!std::isfinite(value)) throw InputError(fmt::format("{}: must be finite, got {}", key, value));
}
void require_finite(const Eigen::Vector3d& value, std::string_view key) {
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(value[a]))
      throw InputError(
          fmt::format("{}: every component must be finite, got [{}, {}, {}]", key, value[0], value[1], value[2]));
}

// The kinematic viscosity nu = mu / rho_f sets tau and dt: a quotient that leaves double precision
// (fluid.density = 1e308 gives 1e-311, subnormal) made the resolution check ask for "at least inf"
// cells per diameter.
void check_kinematic_viscosity(const coupling::SimulationSetup& s) {
  const double nu = s.dynamic_viscosity_si / s.fluid_density_si;
  if (std::isfinite(nu) && nu >= std::numeric_limits<double>::min()) return;
  throw InputError(
      fmt::format("fluid.dynamic_viscosity, fluid.density: the kinematic viscosity {} Pa s / {} kg/m^3 = {:.4g} m^2/s "
                  "is not representable in double precision; check fluid.density and fluid.dynamic_viscosity",
                  s.dynamic_viscosity_si, s.fluid_density_si, nu));
}

// The rigid body needs a mass and principal moments of inertia that are normal doubles: a density
// such as 1e-320 kg/m^3 is positive, but the mass underflows to 0 and the body cannot be built.
void check_mass_representable(const coupling::SimulationSetup& s) {
  const body::MassProperties m = s.shape->mass_properties(s.particle_density_si);
  const Eigen::Vector3d& moments = m.principal.moments;
  const auto representable = [](double x) { return std::isfinite(x) && x >= std::numeric_limits<double>::min(); };
  if (representable(m.mass) && representable(moments.minCoeff()) && std::isfinite(moments.maxCoeff())) return;
  throw InputError(fmt::format(
      "particle.density: {} kg/m^3 gives the particle (volume {:.4g} m^3) a mass of {:.4g} kg and moments of "
      "inertia from {:.4g} to {:.4g} kg m^2, which double precision cannot represent (it needs finite numbers "
      "above {:.3g}); check particle.density and the particle's size",
      s.particle_density_si, m.volume, m.mass, moments.minCoeff(), moments.maxCoeff(),
      std::numeric_limits<double>::min()));
}

void check_numbers(const coupling::SimulationSetup& s) {
  if (!s.shape) throw std::invalid_argument("preflight: the set-up has no shape");
  require_positive(s.particle_density_si, "particle.density");
  require_positive(s.fluid_density_si, "fluid.density");
  require_positive(s.dynamic_viscosity_si, "fluid.dynamic_viscosity");
  check_kinematic_viscosity(s);
  require_finite(s.gravity_si, "fluid.gravity");
  require_finite(s.body_force_si, "fluid.body_force");
  for (int a = 0; a < 3; ++a) require_positive(s.domain_size_si[a], "domain.size");
  require_finite(s.initial.position_si, "particle.position");
  require_finite(s.initial.velocity_si, "particle.velocity");
  require_finite(s.initial.angular_velocity_b_si, "particle.angular_velocity");
  require_positive(s.cells_per_diameter, "numerics.cells_per_diameter");
  require_finite(s.marker_retraction_cells, "numerics.marker_retraction");
  require_positive(s.max_lattice_velocity, "numerics.max_lattice_velocity");
  require_positive(s.max_tau, "numerics.max_tau");
  if (s.tau) require_positive(*s.tau, "numerics.tau");
  require_positive(s.end_time_si, "run.end_time");
  require_finite(s.output_interval_si, "run.output_interval");
  require_positive(s.shape->equivalent_diameter(), "particle (its volume-equivalent diameter)");
  check_mass_representable(s);
  lbm::check_collision_lattice(s.collision, s.lattice);
  lbm::check_collision_subgrid(s.collision, s.subgrid_model);
}

// ---- 2. units -----------------------------------------------------------------------------

// When the viscous bound (tau at numerics.max_tau) sets dt, a dt too small to count comes from the
// fluid's viscosity, not from run.end_time.
bool viscosity_sets_dt(const coupling::SimulationSetup& s, const coupling::CasePlan& plan) {
  return !s.tau && plan.units.tau() >= s.max_tau * (1.0 - 1e-9);
}

// The case's plan (coupling/case_plan.hpp, the same the Simulation is built on): it refuses what
// the set-up and the converter refuse. A second look at the time step guards against a change
// there that would let an unsafe dt through (and against NaN from extreme inputs).
coupling::CasePlan checked_plan(const coupling::SimulationSetup& s) {
  const coupling::CasePlan plan = coupling::plan_case(s);
  require_positive(plan.units.dt_si(),
                   "the time step dt (from numerics.max_tau, numerics.max_lattice_velocity, numerics.tau)");
  if (plan.units.dt_si() < std::numeric_limits<double>::min())
    throw InputError(fmt::format(
        "fluid.dynamic_viscosity, fluid.density: the time step dt = {:.4g} s (kinematic viscosity {:.4g} m^2/s) is "
        "below the smallest normal double; check fluid.dynamic_viscosity and fluid.density",
        plan.units.dt_si(), plan.units.kinematic_viscosity_si()));
  const double u = plan.units.velocity(plan.expected_speed_si);
  if (!(u <= s.max_lattice_velocity * (1.0 + 1e-12)))
    throw InputError(
        fmt::format("numerics.max_lattice_velocity: the expected speed {:.4g} m/s is {:.4g} in lattice "
                    "units (Mach {:.3g}) with dt = {:.4g} s, above the bound {}",
                    plan.expected_speed_si, u, coupling::mach_number(u), plan.units.dt_si(), s.max_lattice_velocity));
  return plan;
}

// ---- 4. grid and memory ---------------------------------------------------------------------

void check_grid_size(const GridExtent& grid, double dx_si, const Eigen::Vector3d& domain_size_si,
                     double estimate_bytes) {
  for (int a = 0; a < 3; ++a) {
    const double n = grid.cells[static_cast<std::size_t>(a)];
    if (n < 4.0)
      throw InputError(
          fmt::format("domain.size: {:.4g} m along {} is {} cells of dx = {:.4g} m; at least 4 are needed "
                      "(raise domain.size or numerics.cells_per_diameter)",
                      domain_size_si[a], kAxis[a], n, dx_si));
  }
  if (grid.total() > coupling::kMaxGridCells)
    throw InputError(fmt::format(
        "numerics.cells_per_diameter: the grid would be {:.4g} x {:.4g} x {:.4g} = {:.3g} cells of dx = {:.4g} m "
        "(about "
        "{} of memory), more than the {:.0e} cells settle allocates; lower numerics.cells_per_diameter or domain.size",
        grid.cells[0], grid.cells[1], grid.cells[2], grid.total(), dx_si, bytes_text(estimate_bytes),
        coupling::kMaxGridCells));
}

// Bytes of the lattice parts for a grid too large to lay out: Q + 3 values per cell.
double rough_grid_bytes(const GridExtent& grid, const coupling::SimulationSetup& s) {
  const double q = s.lattice == lbm::LatticeKind::D3Q27 ? 27.0 : 19.0;
  const double real = s.precision == lbm::Precision::float32 ? 4.0 : 8.0;
  return grid.total() * ((q + 3.0) * real + 1.0);
}

template <class L>
double links_of(const std::array<int, 3>& n) {
  const double total = static_cast<double>(n[0]) * n[1] * n[2];
  double links = 0.0;
  for (int i = 1; i < L::Q; ++i) {
    double inside = 1.0;
    for (int a = 0; a < 3; ++a)
      inside *= std::max(0, n[static_cast<std::size_t>(a)] - std::abs(L::set.c[i][static_cast<std::size_t>(a)]));
    links += total - inside;
  }
  return links;
}

// ---- 5. the particle in the domain ------------------------------------------------------------

void check_centre_inside(const Eigen::Vector3d& p, const std::array<double, 3>& extent_si) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < 0.0 || p[a] > extent_si[static_cast<std::size_t>(a)])
      throw InputError(
          fmt::format("particle.position: the centre's {} = {:.4g} m lies outside the domain [0, {:.4g}] m", kAxis[a],
                      p[a], extent_si[static_cast<std::size_t>(a)]));
}

void check_width(const FaceClearance& c, const std::array<double, 3>& extent_si, double dx_si,
                 const coupling::SimulationSetup& s) {
  for (std::size_t a = 0; a < 3; ++a) {
    if (c.width_si[a] < extent_si[a]) continue;
    const bool periodic = s.boundaries[a] == lbm::Boundary::periodic;
    throw InputError(
        fmt::format("domain.size: the particle is {:.4g} m wide along {} at its initial attitude (particle.euler) but "
                    "the domain is "
                    "only {:.4g} m ({:.0f} cells of dx = {:.4g} m){}; enlarge domain.size along {}",
                    c.width_si[a], kAxis[a], extent_si[a], extent_si[a] / dx_si, dx_si,
                    periodic ? ", and periodic: the particle would overlap its own image" : "", kAxis[a]));
  }
}

void check_walls_clear(const FaceClearance& c, const std::array<double, 3>& extent_si,
                       const coupling::SimulationSetup& s) {
  for (std::size_t a = 0; a < 3; ++a) {
    if (s.boundaries[a] == lbm::Boundary::periodic) continue;
    const double lowest = c.lower_si[a], highest = extent_si[a] - c.upper_si[a];
    if (c.lower_si[a] < 0.0)
      throw InputError(
          fmt::format("particle.position: the particle overlaps the wall at {} = 0: at its initial attitude "
                      "it reaches down to {} = {:.4g} m; move it at least {:.4g} m further in",
                      kAxis[a], kAxis[a], lowest, -c.lower_si[a]));
    if (c.upper_si[a] < 0.0)
      throw InputError(
          fmt::format("particle.position: the particle overlaps the wall at {} = {:.4g} m: at its initial "
                      "attitude it reaches up to {} = {:.4g} m; move it at least {:.4g} m further in",
                      kAxis[a], extent_si[a], kAxis[a], highest, -c.upper_si[a]));
  }
}

// ---- 6. surface elements and steps -----------------------------------------------------------

// Interior markers (numerics.interior_markers) fill the body from interior_lattice_depth_cells below
// the surface, one per cell of volume. Their count is estimated without building them: the inner body's
// volume as V (1 - depth A / (3 V))^3, exact for a sphere (A / 3V = 1 / R) and an approximation for
// other shapes, which is all a memory estimate needs.
double estimated_interior_markers(const coupling::SimulationSetup& s, double dx_si) {
  if (!s.interior_markers) return 0.0;
  const double volume = s.shape->volume(),
               depth_si = coupling::interior_lattice_depth_cells(s.marker_retraction_cells) * dx_si;
  const double shrink = std::max(0.0, 1.0 - depth_si * s.shape->surface_area() / (3.0 * volume));
  return volume * shrink * shrink * shrink / (dx_si * dx_si * dx_si);
}

// The immersed boundary's markers: the surface ones, at about one per cell^2 of area (whose
// construction body::validate_marker_spacing bounds), and the interior lattice's, if any.
double estimated_markers(const coupling::SimulationSetup& s, double dx_si) {
  const double surface = s.shape->surface_area() / (dx_si * dx_si);
  if (surface > kMaxMarkers)
    throw InputError(
        fmt::format("numerics.cells_per_diameter: about {:.3g} surface markers at dx = {:.4g} m, more than the {:.0e} "
                    "settle builds "
                    "(their construction alone would need over a gigabyte); lower numerics.cells_per_diameter",
                    surface, dx_si, kMaxMarkers));
  return surface + estimated_interior_markers(s, dx_si);
}

double checked_steps(const coupling::SimulationSetup& s, const coupling::CasePlan& plan) {
  if (plan.steps <= kMaxSteps) return std::max(1.0, plan.steps);
  // Not even a second fits in 2^53 steps of this dt (1.1e-16 s): that is the fluid's doing.
  if (viscosity_sets_dt(s, plan) && plan.units.dt_si() * kMaxSteps < 1.0)
    throw InputError(fmt::format(
        "fluid.dynamic_viscosity, fluid.density: the kinematic viscosity {:.4g} m^2/s sets dt = {:.4g} s (tau at "
        "numerics.max_tau = {}), and run.end_time = {} s is then {:.3g} steps, more than the 2^53 a run can count; "
        "check fluid.dynamic_viscosity and fluid.density, or lower run.end_time",
        plan.units.kinematic_viscosity_si(), plan.units.dt_si(), s.max_tau, s.end_time_si, plan.steps));
  throw InputError(
      fmt::format("run.end_time: {} s is {:.3g} steps of dt = {:.4g} s, more than the 2^53 a run can "
                  "count; lower run.end_time",
                  s.end_time_si, plan.steps, plan.units.dt_si()));
}

// Rows kept in RunResult::samples: one at t = 0, one per output time, and the final state.
double sample_count(const coupling::SimulationSetup& s, double steps) {
  const double per_interval = s.output_interval_si > 0.0 ? std::floor(s.end_time_si / s.output_interval_si) : steps;
  return std::min(steps, per_interval) + 2.0;
}

// Below this tau a velocity inlet under TRT was found to diverge (docs/lbm.md, "Inlets and
// outlets"): with magic 3/16 at 0.512 within 2000 steps (a channel; stable at 0.55), with magic 1/12
// at 0.508 after 1536 steps and at 0.512 after 27 072 (a fixed sphere), with magic 3/16 at 0.5276
// after 6739 (a sphere held in a stream with a sideways part, periodic sides); BGK and the
// recursive regularised operator held. The threshold is the lowest tau seen to hold. An advisory,
// not an error: the threshold is measured, not derived.
constexpr double kTrtInletStableTau = 0.55;

// Above this cell Reynolds number U dx / nu a sphere's drag at 16 cells per diameter was 5-8% off
// its reference and moved by 2-5% with the collision model, numerics.trt_magic, the wall rule or the
// grid (docs/validation.md: the fixed and the towed sphere at Re = 300, cell Reynolds number 19;
// Mordant and Pinton's bead, 25), where below it (Uhlmann and Dusek's case A, 11.6) the settling
// speed was within 0.5% of the reference. An advisory: the threshold is measured on spheres, not
// derived.
constexpr double kResolvedCellReynolds = 15.0;

// How far a settling sphere's mean fall speed was from the standard drag curve under the default
// numerics (TRT, numerics.subgrid_model = "auto"), by grid: density ratio 2.5, Ga 120 to 600,
// released from rest, in percent (docs/lbm.md, "The default subgrid model", where the runs are).
// Measured, not a bound: a grid between two rows is given the coarser row's range.
struct MeasuredSettlingDeviation {
  double cells_per_diameter;
  const char* galileo_range;
  double lowest_percent, highest_percent;
};
// At 16 cells Ga 120 was not run (its cell Reynolds number, 9, keeps TRT alone).
constexpr std::array<MeasuredSettlingDeviation, 3> kDefaultNumericsDeviation{
    {{8.0, "120-600", -10.2, 0.5}, {12.0, "120-600", -7.1, 0.9}, {16.0, "250-600", -2.8, -0.7}}};

std::string measured_deviation_text(const coupling::SimulationSetup& s) {
  if (s.collision != lbm::CollisionKind::trt || s.subgrid_model != lbm::SubgridModel::automatic) return "";
  const MeasuredSettlingDeviation* row = nullptr;
  for (const auto& r : kDefaultNumericsDeviation)
    if (r.cells_per_diameter <= s.cells_per_diameter) row = &r;
  if (row == nullptr) return "";
  return fmt::format(
      "; with these numerics settling spheres at Ga {} fell {:+.1f}% to {:+.1f}% from the standard drag curve at "
      "{:g} cells per diameter (docs/lbm.md, \"The default subgrid model\")",
      row->galileo_range, row->lowest_percent, row->highest_percent, row->cells_per_diameter);
}

std::optional<std::string> cell_reynolds_advice(const coupling::SimulationSetup& s, const coupling::CasePlan& plan) {
  const double cell_reynolds = plan.cell_reynolds;
  if (!(cell_reynolds > kResolvedCellReynolds)) return std::nullopt;
  return fmt::format(
      "numerics.cells_per_diameter: the cell Reynolds number U dx / nu at the expected speed is {:.1f} (Re {:.0f} over "
      "{:.3g} cells per d_eq), above about {}, where a sphere's drag moved by 2-5% with numerics.collision, "
      "numerics.trt_magic, numerics.wall_rule or the grid (docs/validation.md){}; for figures to publish, compare with "
      "a run at {} or more cells per d_eq",
      cell_reynolds, plan.reynolds, s.cells_per_diameter, kResolvedCellReynolds, measured_deviation_text(s),
      std::ceil(plan.reynolds / kResolvedCellReynolds));
}

// The covered cells' torque holds a free sphere's spin in check with the momentum exchange on
// D3Q19 (Uhlmann and Dusek's cases A and B); on D3Q27 case C's sphere spun up to omega d / u_g =
// 0.21 and drifted 14 degrees from the vertical where D3Q19 gave 0.05 and 5.8, at 16 cells too
// (docs/coupling.md, Known limits). An advisory: the spin's lift drives it, the cause of the spin
// is not found.
std::optional<std::string> free_body_lattice_advice(const coupling::SimulationSetup& s) {
  if (s.motion != body::MotionKind::free || s.coupling != coupling::CouplingKind::momentum_exchange ||
      s.lattice != lbm::LatticeKind::D3Q27)
    return std::nullopt;
  return std::string(
      "numerics.lattice: \"D3Q27\" with a free body and the momentum exchange: the covered cells' torque that "
      "keeps a free body's spin in check was validated on D3Q19 only, and on D3Q27 a free sphere's spin ran away "
      "(Uhlmann and Dusek's case C: 14 degrees from the vertical instead of 5.8; docs/coupling.md, Known limits); "
      "use numerics.lattice = \"D3Q19\" for figures to publish");
}

std::vector<std::string> advisories(const coupling::SimulationSetup& s, const coupling::CasePlan& plan) {
  const double dx_si = plan.units.dx_si(), dt_si = plan.units.dt_si(), tau = plan.units.tau();
  std::vector<std::string> out;
  if (s.inflow && s.collision == lbm::CollisionKind::trt && tau < kTrtInletStableTau)
    out.push_back(
        fmt::format("numerics.collision: \"trt\" with an inlet (domain.inflow) at tau = {:.4f}, below about {}, "
                    "where this inlet was found to diverge whatever numerics.trt_magic (docs/lbm.md, Inlets and "
                    "outlets); use numerics.collision = \"recursive_regularized\", or raise tau",
                    tau, kTrtInletStableTau));
  const body::Aabb box = s.shape->bounding_box();
  const double thinnest_cells = (box.upper - box.lower).minCoeff() / dx_si;
  if (thinnest_cells < 2.0)
    out.push_back(
        fmt::format("numerics.cells_per_diameter: the particle is {:.2g} cells thick along its thinnest body "
                    "axis; below 2 cells the immersed boundary smears it out (raise "
                    "numerics.cells_per_diameter)",
                    thinnest_cells));
  if (auto cells = cell_reynolds_advice(s, plan)) out.push_back(*cells);
  if (auto lattice = free_body_lattice_advice(s)) out.push_back(*lattice);
  if (auto window = window_advice(s, plan.equivalent_diameter_si, plan.reynolds)) out.push_back(*window);
  if (s.end_time_si < dt_si)
    out.push_back(
        fmt::format("run.end_time: {} s is shorter than one time step (dt = {:.4g} s); the run makes one step",
                    s.end_time_si, dt_si));
  if (s.output_interval_si > 0.0 && s.output_interval_si < dt_si)
    out.push_back(
        fmt::format("run.output_interval: {} s is shorter than one time step (dt = {:.4g} s); a row is "
                    "written every step",
                    s.output_interval_si, dt_si));
  return out;
}

// Empty when the process may create entries in `dir`, else the reason (root passes permission
// bits, but not a read-only file system).
std::string write_refusal(const fs::path& dir) {
  if (::access(dir.c_str(), W_OK | X_OK) == 0) return "";
  return std::strerror(errno);
}

}  // namespace

double MemoryEstimate::total_bytes() const {
  return populations_bytes + force_bytes + flag_bytes + boundary_links_bytes + body_bytes + output_bytes;
}

double boundary_link_count(const std::array<int, 3>& cells, lbm::LatticeKind lattice) {
  return lattice == lbm::LatticeKind::D3Q27 ? links_of<lbm::D3Q27>(cells) : links_of<lbm::D3Q19>(cells);
}

MemoryEstimate estimate_memory(const MemoryInputs& in) {
  const int q = in.lattice == lbm::LatticeKind::D3Q27 ? lbm::D3Q27::Q : lbm::D3Q19::Q;
  const std::size_t real = in.precision == lbm::Precision::float32 ? 4 : 8;
  const double cells = static_cast<double>(in.cells[0]) * in.cells[1] * in.cells[2];
  const lbm::GridLayout layout = lbm::make_layout(in.cells[0], in.cells[1], in.cells[2], real, q);
  MemoryEstimate m;
  // lbm::AaSolver: one page-aligned array of Q x pop_stride values, three of one value per cell.
  m.populations_bytes = page_rounded(static_cast<double>(layout.pop_stride) * q * static_cast<double>(real));
  m.force_bytes = 3.0 * page_rounded(cells * static_cast<double>(real));
  m.flag_bytes = cells;
  m.boundary_links_bytes = 2.0 * sizeof(lbm::CopyEntry) * boundary_link_count(in.cells, in.lattice);
  // Approximation: per cell of the body's box, the local grid (7 doubles), the solid-cell list
  // (cell, fraction, kind) and the forced-cell index, about 100 bytes; per surface element about
  // 1200 bytes: an immersed-boundary marker's ~20 clustering patches of 56 bytes, which its
  // construction holds (body/shape.cpp), or a momentum-exchange boundary cell's wall links, some
  // 220 bytes each (the link and its crossing, 72, its momentum, 24, the solver's prepared link,
  // 128; lbm/block_obstacle.hpp) and 5.7 per cell of area on D3Q19 (2592 links for 452 cells^2 of
  // glass_bead_2mm's sphere at 12 cells per diameter).
  m.body_bytes = 100.0 * in.body_box_cells + 1200.0 * in.surface_elements;
  m.output_bytes = in.samples * static_cast<double>(sizeof(coupling::Sample)) +
                   (in.velocity_field_per_sample ? 3.0 * sizeof(double) * cells : 0.0);
  return m;
}

std::optional<double> parse_mem_available(std::string_view text) {
  std::istringstream in{std::string(text)};
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("MemAvailable:", 0) != 0) continue;
    std::istringstream fields(line.substr(13));
    double value = 0.0;
    std::string unit;
    if (!(fields >> value) || value < 0.0) return std::nullopt;
    fields >> unit;
    if (unit == "kB" || unit == "KB" || unit == "kb") return value * 1024.0;  // /proc uses kB for KiB
    if (unit.empty()) return value;
    return std::nullopt;
  }
  return std::nullopt;
}

std::optional<double> available_memory_bytes() {
  std::ifstream file("/proc/meminfo");
  if (!file) return std::nullopt;
  std::stringstream text;
  text << file.rdbuf();
  return parse_mem_available(text.str());
}

void check_memory(const MemoryEstimate& m, double budget_bytes, std::string_view budget_source) {
  const double total = m.total_bytes();
  if (total <= budget_bytes) return;
  // Name the key whose change helps most: the kept samples when they dominate, else the grid.
  const bool samples_dominate = m.output_bytes > 0.5 * total;
  throw InputError(
      fmt::format("{}: the run needs about {} of memory (fluid {}, outputs {}) but the budget is {} ({}); {}, or raise "
                  "the budget with settle run --max-memory GIB",
                  samples_dominate ? "run.output_interval" : "numerics.cells_per_diameter", bytes_text(total),
                  bytes_text(m.populations_bytes + m.force_bytes + m.flag_bytes + m.boundary_links_bytes),
                  bytes_text(m.output_bytes), bytes_text(budget_bytes), budget_source,
                  samples_dominate ? "raise run.output_interval (fewer rows kept)"
                                   : "lower numerics.cells_per_diameter or domain.size"));
}

FaceClearance face_clearance(const body::Shape& shape, const Eigen::Vector3d& position_si,
                             const Eigen::Matrix3d& body_to_inertial, const Eigen::Vector3d& extent_si) {
  FaceClearance c;
  for (int a = 0; a < 3; ++a) {
    // The support function of the body along the inertial axis, evaluated in the body frame.
    const Eigen::Vector3d axis_b = body_to_inertial.transpose().col(a);
    const double up = shape.support(axis_b), down = shape.support(-axis_b);
    const auto i = static_cast<std::size_t>(a);
    c.lower_si[i] = position_si[a] - down;
    c.upper_si[i] = extent_si[a] - (position_si[a] + up);
    c.width_si[i] = up + down;
  }
  return c;
}

void check_particle_in_domain(const coupling::SimulationSetup& s, double dx_si, const std::array<double, 3>& cells) {
  const std::array<double, 3> extent_si{cells[0] * dx_si, cells[1] * dx_si, cells[2] * dx_si};
  const FaceClearance clearance = face_clearance(*s.shape, s.initial.position_si, s.initial.attitude.body_to_inertial(),
                                                 Eigen::Vector3d(extent_si[0], extent_si[1], extent_si[2]));
  check_centre_inside(s.initial.position_si, extent_si);
  check_width(clearance, extent_si, dx_si, s);
  check_walls_clear(clearance, extent_si, s);
  // The grid fits in int: check_grid_size came first.
  coupling::check_body_box_in_grid(
      s, dx_si, {static_cast<int>(cells[0]), static_cast<int>(cells[1]), static_cast<int>(cells[2])});
}

void check_particle_narrower_than_domain(const coupling::SimulationSetup& s) {
  const FaceClearance c =
      face_clearance(*s.shape, s.initial.position_si, s.initial.attitude.body_to_inertial(), s.domain_size_si);
  for (std::size_t a = 0; a < 3; ++a) {
    if (c.width_si[a] < s.domain_size_si[static_cast<Eigen::Index>(a)]) continue;
    // A mesh in millimetres read as metres is a thousand times too large: say so where it helps.
    const bool mesh = s.shape->kind() == "mesh";
    throw InputError(fmt::format(
        "domain.size: the particle is {:.4g} m wide along {} at its initial attitude (particle.euler; its "
        "volume-equivalent diameter is {:.4g} m) but the domain is only {:.4g} m{}; {}",
        c.width_si[a], kAxis[a], s.shape->equivalent_diameter(), s.domain_size_si[static_cast<Eigen::Index>(a)],
        s.boundaries[a] == lbm::Boundary::periodic ? ", and periodic: the particle would overlap its own image" : "",
        mesh ? "if the mesh's coordinates are not in metres, set particle.scale (e.g. 0.001 for millimetres); "
               "otherwise enlarge domain.size"
             : fmt::format("enlarge domain.size along {}", kAxis[a])));
  }
}

void check_net_weight(const coupling::SimulationSetup& s) {
  if (s.motion != body::MotionKind::free) return;
  const double excess_density = s.particle_density_si - s.fluid_density_si;
  if (excess_density == 0.0 || s.gravity_si.norm() == 0.0) return;
  const bool heavy = excess_density > 0.0;
  for (int a = 0; a < 3; ++a) {
    if (s.boundaries[static_cast<std::size_t>(a)] != lbm::Boundary::periodic || s.gravity_si[a] == 0.0) continue;
    const bool drifts_up = (heavy ? s.gravity_si[a] : -s.gravity_si[a]) > 0.0;
    throw InputError(fmt::format(
        "domain.walls.{}: a free particle {} than the fluid (particle.density = {} kg/m^3, fluid.density = {} kg/m^3) "
        "{} along {}{} under fluid.gravity, and the domain is periodic along {}: nothing carries its net weight, so "
        "fluid and particle would accelerate without bound. Use \"no-slip\" or \"free-slip\" along {} (with "
        "domain.follow_particle = true for a long path), or particle.motion = \"fixed\" or \"towed\"",
        kAxis[a], heavy ? "heavier" : "lighter", s.particle_density_si, s.fluid_density_si, heavy ? "sinks" : "rises",
        drifts_up ? "+" : "-", kAxis[a], kAxis[a], kAxis[a]));
  }
}

void check_output_directory(const fs::path& dir, std::string_view flag) {
  std::error_code error;
  const fs::path target = dir.empty() ? fs::path(".") : dir;
  const fs::file_status status = fs::status(target, error);
  if (fs::exists(status)) {
    if (!fs::is_directory(status))
      throw InputError(fmt::format("{} {}: exists and is not a directory", flag, target.string()));
    if (const std::string why = write_refusal(target); !why.empty())
      throw InputError(fmt::format("{} {}: the directory is not writable ({})", flag, target.string(), why));
    return;
  }
  // The nearest ancestor that exists must be a directory we may create entries in.
  fs::path ancestor = target.parent_path();
  while (!ancestor.empty() && !fs::exists(fs::status(ancestor, error))) ancestor = ancestor.parent_path();
  if (ancestor.empty()) ancestor = target.is_absolute() ? target.root_path() : fs::path(".");
  if (!fs::is_directory(fs::status(ancestor, error)))
    throw InputError(
        fmt::format("{} {}: cannot be created: {} is not a directory", flag, target.string(), ancestor.string()));
  if (const std::string why = write_refusal(ancestor); !why.empty())
    throw InputError(fmt::format("{} {}: cannot be created: {} is not writable ({})", flag, target.string(),
                                 ancestor.string(), why));
}

std::string PreflightReport::surface_text() const {
  return fmt::format("about {:.3g} {}", surface_elements, surface_element_name);
}

std::string PreflightReport::summary() const {
  const std::string budget = memory_budget_bytes
                                 ? fmt::format("budget {}, {}", bytes_text(*memory_budget_bytes), memory_budget_source)
                                 : std::string("available memory unknown");
  return fmt::format("grid {}x{}x{} = {:.3g} cells, {:.4g} steps, {}; memory estimate {} ({})", cells[0], cells[1],
                     cells[2], cell_count, steps, surface_text(), bytes_text(memory.total_bytes()), budget);
}

PreflightReport preflight(const coupling::SimulationSetup& s, const PreflightOptions& options) {
  check_numbers(s);
  check_particle_narrower_than_domain(s);
  PreflightReport r(checked_plan(s));
  check_net_weight(s);
  const double dx_si = r.plan.units.dx_si(), dt_si = r.plan.units.dt_si();

  const GridExtent grid{r.plan.cells};
  r.cell_count = grid.total();
  check_grid_size(grid, dx_si, s.domain_size_si, rough_grid_bytes(grid, s));
  for (std::size_t a = 0; a < 3; ++a) r.cells[a] = static_cast<int>(grid.cells[a]);

  check_particle_in_domain(s, dx_si, grid.cells);
  coupling::start_wall_contact(s, dx_si, dt_si, r.cells, Eigen::Vector3d::Zero());  // refuses a start inside the spring
  // The momentum exchange's boundary cells (those its links leave) are about one per cell^2 of area.
  const bool immersed = s.coupling == coupling::CouplingKind::immersed_boundary;
  r.surface_elements = immersed ? estimated_markers(s, dx_si) : s.shape->surface_area() / (dx_si * dx_si);
  r.surface_element_name = immersed ? "markers" : "boundary cells";
  r.steps = checked_steps(s, r.plan);

  MemoryInputs memory;
  memory.cells = r.cells;
  memory.lattice = s.lattice;
  memory.precision = s.precision;
  const double reach = coupling::coupling_reach_cells(coupling::coupling_options(s));
  const double box_side = 2.0 * (s.shape->bounding_radius() / dx_si + reach) + 2.0;
  memory.body_box_cells = box_side * box_side * box_side;
  memory.surface_elements = r.surface_elements;
  memory.samples = sample_count(s, r.steps);
  memory.velocity_field_per_sample = s.motion == body::MotionKind::fixed;
  r.memory = estimate_memory(memory);
  if (options.memory_budget_bytes) {
    r.memory_budget_bytes = options.memory_budget_bytes;
    r.memory_budget_source = "--max-memory";
  } else if (const auto available = available_memory_bytes()) {
    r.memory_budget_bytes = available;
    r.memory_budget_source = "MemAvailable in /proc/meminfo";
  }
  if (r.memory_budget_bytes) check_memory(r.memory, *r.memory_budget_bytes, r.memory_budget_source);

  if (!options.output_directory.empty()) check_output_directory(options.output_directory);
  r.warnings = advisories(s, r.plan);
  return r;
}

}  // namespace settle::io
