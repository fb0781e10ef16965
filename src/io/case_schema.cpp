#include "io/case_schema.hpp"

#include <cmath>

#include "common/physical_defaults.hpp"
#include "coupling/body_coupling.hpp"
#include "coupling/units.hpp"
#include "lbm/config.hpp"
#include "lbm/solver.hpp"

namespace settle::io {
namespace {

constexpr double kInf = INFINITY;

Range positive() { return {0.0, kInf, false, true}; }
Range non_negative() { return {0.0, kInf, true, true}; }
Range closed(double lo, double hi) { return {lo, hi, true, true}; }

Value vec(double x, double y, double z) { return Value(std::vector<double>{x, y, z}); }
Value text(const char* s) { return Value(std::string(s)); }

// Shorthands keep the declaration readable as a table.
KeySpec real(const char* path, std::optional<Value> def, const char* unit, Range range, const char* doc) {
  return {path, Kind::Real, std::move(def), unit, doc, range, {}, 0};
}
KeySpec vector3(const char* path, std::optional<Value> def, const char* unit, Range range, const char* doc) {
  return {path, Kind::RealArray, std::move(def), unit, doc, range, {}, 3};
}
KeySpec choice(const char* path, const char* def, std::vector<std::string> choices, const char* doc) {
  return {path, Kind::String, text(def), "", doc, {}, std::move(choices), 0};
}
KeySpec integer(const char* path, std::int64_t def, Range range, const char* doc) {
  return {path, Kind::Integer, Value(def), "", doc, range, {}, 0};
}
KeySpec boolean(const char* path, bool def, const char* doc) {
  return {path, Kind::Boolean, Value(def), "", doc, {}, {}, 0};
}

std::vector<KeySpec> declare() {
  const std::vector<std::string> walls{"no-slip", "free-slip", "periodic"};
  const std::vector<std::string> faces{"none", "x-", "x+", "y-", "y+", "z-", "z+"};
  const std::string default_coupling = coupling::to_string(coupling::kDefaultCoupling);
  const std::string default_wall_rule = lbm::to_string(lbm::kDefaultWallRule);
  const std::string default_precision = lbm::to_string(lbm::kDefaultPrecision);
  return {
      // [fluid]
      real("fluid.density", Value(defaults::fluid_density_si), "kg/m^3", positive(),
           "fluid density (when given, overrides fluid.preset)"),
      real("fluid.dynamic_viscosity", Value(defaults::dynamic_viscosity_si), "Pa s", positive(),
           "dynamic viscosity (when given, overrides fluid.preset)"),
      // Presets (io/fluid_presets.hpp): the ranges are those of the correlations' sources.
      choice("fluid.preset", "none", {"none", "water", "glycerol-water"},
             "liquid whose density and viscosity follow from fluid.temperature (docs/case-file.md, Fluid presets)"),
      real("fluid.temperature", std::nullopt, "degrees C", closed(0.0, 100.0),
           "temperature of the preset liquid (only with fluid.preset)"),
      real("fluid.glycerol_mass_fraction", std::nullopt, "", closed(0.0, 1.0),
           "mass of glycerol per mass of mixture (fluid.preset = \"glycerol-water\" only)"),
      vector3("fluid.gravity", vec(0.0, 0.0, -defaults::gravity_si), "m/s^2", {}, "gravitational acceleration"),
      vector3("fluid.body_force", vec(0.0, 0.0, 0.0), "N/m^3", {},
              "force density on the fluid (drives flow past a fixed body in a periodic box)"),
      // [particle]
      choice("particle.shape", "sphere",
             {"sphere", "spheroid", "ellipsoid", "cylinder", "cuboid", "superellipsoid", "mesh"}, "particle shape"),
      real("particle.diameter", std::nullopt, "m", positive(), "sphere, spheroid (equatorial) and cylinder diameter"),
      // The shape factory's bound (body/shape_factory.hpp): beyond it no grid resolves the body.
      real("particle.aspect_ratio", std::nullopt, "", closed(1.0e-3, 1.0e3),
           "spheroid polar / equatorial diameter (> 1 prolate, < 1 oblate)"),
      vector3("particle.semi_axes", std::nullopt, "m", positive(),
              "ellipsoid and superellipsoid semi-axes along body x, y, z"),
      // Superellipsoid::kMinExponent..kMaxExponent (convex superellipsoids only).
      {"particle.exponents",
       Kind::RealArray,
       std::nullopt,
       "",
       "superellipsoid exponents e1 (z), e2 (x-y)",
       closed(0.1, 2.0),
       {},
       2},
      real("particle.length", std::nullopt, "m", positive(),
           "cylinder length along body z (a disk is a short cylinder)"),
      vector3("particle.size", std::nullopt, "m", positive(), "cuboid edge lengths along body x, y, z"),
      {"particle.file",
       Kind::String,
       std::nullopt,
       "",
       "mesh: watertight STL file (relative to the case file)",
       {},
       {},
       0},
      // Optional rather than defaulted: a default would be written to case.resolved.toml and read
      // back as given, and the shape factory refuses scale for every shape but a mesh.
      real("particle.scale", std::nullopt, "m per file unit", positive(),
           "mesh: factor from file units to metres (absent: 1)"),
      real("particle.density", std::nullopt, "kg/m^3", positive(), "particle density (required: no default)"),
      choice("particle.motion", "free", {"free", "towed", "fixed"},
             "free (6 degrees of freedom), towed (constant velocity and attitude) or fixed"),
      vector3("particle.towing_velocity", std::nullopt, "m/s", {}, "velocity of a towed particle"),
      vector3("particle.position", std::nullopt, "m", {}, "initial centre of mass (default: the domain's centre)"),
      vector3("particle.euler", vec(0.0, 0.0, 0.0), "rad", {},
              "initial attitude, set-1 Euler angles (psi, theta, gamma), body to inertial"),
      vector3("particle.velocity", vec(0.0, 0.0, 0.0), "m/s", {}, "initial velocity"),
      vector3("particle.angular_velocity", vec(0.0, 0.0, 0.0), "rad/s", {}, "initial angular velocity, body frame"),
      real("particle.release_time", Value(0.0), "s", non_negative(),
           "free bodies: held at the initial velocity and angular velocity until this time while the flow around "
           "them develops, then free (0: free from the start)"),
      real("particle.hold_ramp_time", Value(0.0), "s", non_negative(),
           "free bodies held before their release, and towed bodies: the held (towing) velocities grow linearly "
           "from rest to the given ones over this time, at most particle.release_time (towed: run.end_time; 0: the "
           "body starts at them)"),
      boolean("particle.lock_rotation", false,
              "free bodies: the body keeps its initial attitude and only translates (its torque is measured, not "
              "applied): a control for the part rotation plays in a path (docs/rigid-body.md)"),
      // [domain]
      vector3("domain.size", std::nullopt, "m", positive(), "extent of the domain from the origin"),
      choice("domain.walls.x", "no-slip", walls, "boundary of the two faces normal to x"),
      choice("domain.walls.y", "no-slip", walls, "boundary of the two faces normal to y"),
      choice("domain.walls.z", "no-slip", walls, "boundary of the two faces normal to z"),
      choice("domain.inflow", "none", faces,
             "face where a uniform stream enters with domain.inflow_velocity (a velocity inlet), e.g. \"z-\"; replaces "
             "domain.walls on that face; the fluid starts as that stream"),
      vector3("domain.inflow_velocity", std::nullopt, "m/s", {}, "velocity of the stream entering at domain.inflow"),
      choice("domain.outflow", "none", faces,
             "face where the fluid leaves (a pressure outlet at the reference density), e.g. \"z+\"; replaces "
             "domain.walls on that face"),
      boolean("domain.follow_particle", false,
              "moving window: the fluid window follows the particle along the axes that are not periodic"),
      // [numerics]
      real("numerics.cells_per_diameter", Value(16.0), "", closed(4.0, 256.0),
           "grid cells per volume-equivalent diameter"),
      choice("numerics.lattice", "D3Q19", {"D3Q19", "D3Q27"}, "lattice"),
      choice("numerics.collision", "trt", {"bgk", "trt", "recursive_regularized", "cumulant"},
             "collision model (docs/lbm.md); cumulant needs numerics.lattice = \"D3Q27\""),
      // Up to 1: the values in use (1/12, 1/6, 3/16, 1/4) lie well inside; larger ones move the
      // walls of a coarse grid and slow the odd moments' relaxation without known use.
      real("numerics.trt_magic", Value(lbm::kWallExactTrtMagic), "", {0.0, 1.0, false, true},
           "TRT's magic parameter Lambda = (tau+ - 1/2)(tau- - 1/2): 3/16 puts half-way walls mid-way for any "
           "viscosity (docs/lbm.md)"),
      choice("numerics.subgrid_model", "auto", {"auto", "none", "smagorinsky"},
             "subgrid model: Smagorinsky's eddy viscosity, (C_S dx)^2 times the strain rate read from each cell's "
             "non-equilibrium stress (Hou et al. 1996; no wall damping), or none; auto: Smagorinsky's with TRT above "
             "a cell Reynolds number of 20, where TRT alone diverged, none otherwise (docs/lbm.md)"),
      // Up to 0.5, about three times Lilly's 0.17, the largest value in common use.
      real("numerics.smagorinsky_constant", Value(lbm::kDefaultSmagorinskyConstant), "", {0.0, 0.5, false, true},
           "C_S of the Smagorinsky model (numerics.subgrid_model = \"smagorinsky\", or \"auto\" where it chooses it), "
           "the filter width being dx: 0.1 as in wall-bounded "
           "and shear flows (Deardorff 1970; docs/lbm.md)"),
      choice("numerics.precision", default_precision.c_str(), {"double", "float"},
             "storage precision of the populations"),
      choice("numerics.coupling", default_coupling.c_str(), {"immersed_boundary", "momentum_exchange"},
             "how the body meets the fluid: diffuse immersed boundary, or sharp-interface momentum exchange with "
             "interpolated bounce-back (docs/coupling.md, Couplings)"),
      choice("numerics.wall_rule", default_wall_rule.c_str(), {"bouzidi", "quadratic", "central_linear", "halfway"},
             "momentum exchange: bounce-back interpolated at the true surface, linearly (bouzidi), from three "
             "points (quadratic) or by Ginzburg's central linear rule (central_linear), or half-way on the cells' "
             "faces (halfway, a staircase)"),
      boolean("numerics.covered_cell_torque", coupling::kDefaultCoveredCellTorque,
              "momentum exchange: the body also takes the angular momentum by which the fluid of the cells it "
              "covers lags its rotation (docs/coupling.md)"),
      integer("numerics.lattice_steps_per_body_step", 1, closed(1, 2),
              "momentum exchange: 2 moves the body once per two lattice steps with the wrench averaged over both "
              "(Rettinger and Ruede 2017), 1 every step with each step's wrench averaged with the one before "
              "(docs/coupling.md, Force averaging)"),
      choice("numerics.delta_kernel", "roma3", {"roma3", "peskin4"}, "immersed-boundary delta kernel"),
      integer("numerics.forcing_iterations", 3, closed(1, 50), "multi-direct forcing sweeps per step"),
      real("numerics.marker_retraction", std::nullopt, "cells", closed(0.0, 0.5),
           "markers sit this far inside the surface (Breugem 2012); if not given, the calibrated 0.4, or 0.5 "
           "with interior_markers (docs/coupling.md)"),
      boolean("numerics.interior_markers", false,
              "also force the fluid inside the body, on a body-fixed lattice of one-cell spacing (docs/coupling.md)"),
      real("numerics.max_lattice_velocity", Value(0.05), "", {0.0, 0.2, false, true},
           "largest lattice velocity U dt/dx of the expected speed (Mach bound for choosing dt)"),
      // tau must exceed the converter's smallest (coupling::kMinTau).
      real("numerics.max_tau", Value(2.0), "", {coupling::kMinTau, 5.0, false, true},
           "largest relaxation time when choosing dt"),
      real("numerics.tau", std::nullopt, "", {coupling::kMinTau, 5.0, false, true},
           "relaxation time; when given, dt follows from it instead of the Mach and tau bounds"),
      // [contact]: particle-wall contact (body/contact.hpp, docs/rigid-body.md); the ranges are
      // checked here only (plan_case, coupling/case_plan.cpp, checks the rules between keys).
      boolean("contact.enabled", true,
              "spring-dashpot contact with the walls of non-periodic axes (free bodies, fixed window only)"),
      real("contact.restitution", Value(0.97), "", {0.0, 1.0, false, true},
           "dry normal restitution coefficient e (glass, steel: about 0.97)"),
      real("contact.wet_stokes_scale", Value(35.0), "", closed(0.0, 1.0e3),
           "wet restitution: each contact takes restitution x exp(-beta/St), St = rho_p v d_eq / (9 mu) at impact, "
           "beta this "
           "value (Legendre et al. 2006; docs/rigid-body.md); 0: dry contacts"),
      real("contact.collision_steps", Value(10.0), "", closed(1.0, 1.0e4),
           "collision time T_c in fluid time steps (Kempe and Froehlich 2012)"),
      // The lower bound depends on the coupling (coupling::coupling_reach_cells - 0.5: 0.5 for the
      // momentum exchange, 1 for the immersed boundary with roma3, 1.5 with peskin4); the schema holds
      // the smallest, the Simulation's check (and preflight) the coupling's own.
      real("contact.distance_cells", std::nullopt, "cells", closed(0.5, 1.0e3),
           "gap at which the contact spring starts (absent: the coupling's reach, 1 for the momentum exchange, the "
           "delta kernel's half-width for the immersed boundary; at least reach - 0.5)"),
      // [run]
      real("run.end_time", Value(1.0), "s", positive(), "simulated time to run"),
      real("run.output_interval", Value(0.005), "s", non_negative(),
           "interval of timeseries.csv rows (0 = every step)"),
      real("run.vtk_interval", Value(0.0), "s", non_negative(), "interval of VTK output (0 = none)"),
      choice("run.vtk_compression", "zlib", {"zlib", "none"},
             "encoding of the VTK files' arrays: zlib (deflated blocks, what ParaView writes) or none (raw bytes)"),
      boolean("run.stop_at_terminal", false, "end once the terminal state is reached"),
      real("run.checkpoint_interval", Value(0.0), "s", non_negative(),
           "simulated time between checkpoints in DIR/checkpoint.bin (0 = none; SIGINT or SIGTERM writes one anyway)"),
      real("run.checkpoint_wall_interval", Value(0.0), "s", non_negative(),
           "wall-clock time between checkpoints, whichever of the two comes first (0 = none)"),
      {"run.reference",
       Kind::String,
       std::nullopt,
       "",
       "key of validation/reference-data.json the run is compared with (e.g. \"tenCate2002_E1\"), copied to "
       "summary.json",
       {},
       {},
       0},
  };
}

}  // namespace

const Schema& case_schema() {
  static const Schema schema(declare());
  return schema;
}

}  // namespace settle::io
