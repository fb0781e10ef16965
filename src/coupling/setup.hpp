#pragma once
// The set-up of one run in SI units: the particle, the fluid, the domain, the numerics and the
// contact model, as io/case.cpp builds it from a case file (docs/case-file.md lists the keys).
// The members of case keys carry no defaults: the case schema (io/case_schema.cpp) declares them,
// io::simulation_setup assigns every member from a checked case, and a number it did not assign
// stays kUnassigned, which plan_case refuses (check_assigned) rather than run on a second default.
// Enumerations and flags start zero-initialised, which claims no default either;
// tests/io/test_setup_defaults.cpp checks that every key's default reaches the set-up.
// Code that needs a set-up without a case file builds one from a minimal case through
// io::simulation_setup (tests/support/default_setup.hpp).
#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "body/rigid_body.hpp"
#include "body/shape.hpp"
#include "coupling/body_coupling.hpp"
#include "coupling/immersed_body.hpp"
#include "ibm/delta.hpp"
#include "lbm/config.hpp"

namespace settle::coupling {

/// A real member of a case key before io::simulation_setup assigns it (file comment).
inline constexpr double kUnassigned = std::numeric_limits<double>::quiet_NaN();
/// A count member (numerics.forcing_iterations, numerics.lattice_steps_per_body_step) likewise:
/// below every count the schema allows.
inline constexpr int kUnassignedCount = 0;

/// Everything a run needs, in SI (built from a case by io/case.hpp).
struct SimulationSetup {
  std::string name = "case";
  std::shared_ptr<const body::Shape> shape;
  double particle_density_si = kUnassigned;
  body::MotionKind motion{};
  /// Initial state. For a towed body, velocity_si and angular_velocity_b_si are the prescribed
  /// constant motion.
  body::RigidBodyState initial;
  /// Free bodies: until this time (s) the body keeps its initial velocity and angular velocity
  /// while the flow around it develops, then it moves freely (particle.release_time).
  double release_time_si = kUnassigned;
  /// Free bodies held before their release, and towed bodies: the held (towing) velocity and
  /// angular velocity grow linearly from rest to the initial ones over this time (s;
  /// particle.hold_ramp_time), so that the fluid is not struck by a body that starts at speed; 0:
  /// an impulsive start.
  double hold_ramp_time_si = kUnassigned;
  /// Towed bodies: the prescribed velocity (m/s, inertial) as a function of time (s), in place of
  /// the constant initial one and its ramp; empty: initial.velocity_si. Set by code, not by a case
  /// key: the oscillating sphere of tests/coupling/oscillating_sphere.hpp.
  std::function<Eigen::Vector3d(double t_si)> towed_velocity_si;
  /// Free bodies: the attitude is held and only Newton's law moves the body (particle.lock_rotation;
  /// body::RigidBody::lock_rotation).
  bool rotation_locked{};

  double fluid_density_si = kUnassigned;
  double dynamic_viscosity_si = kUnassigned;
  Eigen::Vector3d gravity_si = Eigen::Vector3d::Constant(kUnassigned);
  Eigen::Vector3d body_force_si = Eigen::Vector3d::Constant(kUnassigned);  ///< N/m^3 on the fluid

  Eigen::Vector3d domain_size_si = Eigen::Vector3d::Constant(kUnassigned);
  std::array<lbm::Boundary, 3> boundaries{};
  /// A face where the fluid enters with inflow_velocity_si (a uniform stream), and one where it
  /// leaves; each replaces the pair's kind on that face (lbm::OpenFace).
  std::optional<lbm::Face> inflow;
  Eigen::Vector3d inflow_velocity_si = Eigen::Vector3d::Zero();
  std::optional<lbm::Face> outflow;
  bool follow_particle{};

  double cells_per_diameter = kUnassigned;
  lbm::LatticeKind lattice{};
  lbm::CollisionKind collision{};
  double trt_magic = kUnassigned;             ///< TRT only: Lambda = (tau+ - 1/2)(tau- - 1/2)
  lbm::SubgridModel subgrid_model{};          ///< the run's: CasePlan::subgrid_model
  double smagorinsky_constant = kUnassigned;  ///< C_S, with SubgridModel::smagorinsky
  lbm::Precision precision{};
  CouplingKind coupling{};
  lbm::WallRule wall_rule{};   ///< momentum exchange only
  bool covered_cell_torque{};  ///< momentum exchange only
  /// Lattice steps per step of the body (1 or 2; momentum exchange only): with 2 the body moves once
  /// per two lattice steps with the wrench of both (Simulation::step; docs/coupling.md, "Force averaging").
  int lattice_steps_per_body_step = kUnassignedCount;
  ibm::DeltaKernel kernel{};
  int forcing_iterations = kUnassignedCount;
  double marker_retraction_cells = kUnassigned;  ///< cells; docs/coupling.md
  bool interior_markers{};                       ///< volume markers inside the body (make_body_markers)
  double max_lattice_velocity = kUnassigned;
  double max_tau = kUnassigned;
  std::optional<double> tau;

  // Particle-wall contact (body/contact.hpp) with the walls of the non-periodic axes. Off when the
  // window follows the particle (it then never nears a face: the window keeps it at its start).
  bool wall_contact{};
  double contact_restitution = kUnassigned;  ///< dry normal restitution e in (0, 1]
  /// beta of the wet restitution e exp(-beta / St) (body/contact.hpp; Legendre et al. 2006); 0: dry contacts
  double contact_wet_stokes_scale = kUnassigned;
  double contact_collision_steps = kUnassigned;  ///< collision time T_c in fluid time steps (Kempe and Froehlich 2012)
  /// Gap (cells) at which the contact spring starts; unset: the coupling's reach
  /// (contact_distance_cells, case_plan.hpp).
  std::optional<double> contact_distance_cells;

  double end_time_si = kUnassigned;
  double output_interval_si = kUnassigned;
};

}  // namespace settle::coupling
