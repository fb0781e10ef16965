#pragma once
// The set-up of one run in SI units: the particle, the fluid, the domain, the numerics and the
// contact model, as io/case.cpp builds it from a case file (docs/case-file.md lists the keys).
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

/// Everything a run needs, in SI (built from a case by io/case.hpp).
struct SimulationSetup {
  std::string name = "case";
  std::shared_ptr<const body::Shape> shape;
  double particle_density_si = 1050.0;
  body::MotionKind motion = body::MotionKind::free;
  /// Initial state. For a towed body, velocity_si and angular_velocity_b_si are the prescribed
  /// constant motion.
  body::RigidBodyState initial;
  /// Free bodies: until this time (s) the body keeps its initial velocity and angular velocity
  /// while the flow around it develops, then it moves freely (particle.release_time).
  double release_time_si = 0.0;
  /// Free bodies held before their release, and towed bodies: the held (towing) velocity and
  /// angular velocity grow linearly from rest to the initial ones over this time (s;
  /// particle.hold_ramp_time), so that the fluid is not struck by a body that starts at speed; 0:
  /// an impulsive start.
  double hold_ramp_time_si = 0.0;
  /// Towed bodies: the prescribed velocity (m/s, inertial) as a function of time (s), in place of
  /// the constant initial one and its ramp; empty: initial.velocity_si. Set by code, not by a case
  /// key: the oscillating sphere of tests/coupling/oscillating_sphere.hpp.
  std::function<Eigen::Vector3d(double t_si)> towed_velocity_si;
  /// Free bodies: the attitude is held and only Newton's law moves the body (particle.lock_rotation;
  /// body::RigidBody::lock_rotation).
  bool rotation_locked = false;

  double fluid_density_si = 998.2;
  double dynamic_viscosity_si = 1.0e-3;
  Eigen::Vector3d gravity_si{0.0, 0.0, -9.81};
  Eigen::Vector3d body_force_si = Eigen::Vector3d::Zero();  ///< N/m^3 on the fluid

  Eigen::Vector3d domain_size_si = Eigen::Vector3d::Constant(0.01);
  std::array<lbm::Boundary, 3> boundaries{lbm::Boundary::no_slip, lbm::Boundary::no_slip, lbm::Boundary::no_slip};
  /// A face where the fluid enters with inflow_velocity_si (a uniform stream), and one where it
  /// leaves; each replaces the pair's kind on that face (lbm::OpenFace).
  std::optional<lbm::Face> inflow;
  Eigen::Vector3d inflow_velocity_si = Eigen::Vector3d::Zero();
  std::optional<lbm::Face> outflow;
  bool follow_particle = false;

  double cells_per_diameter = 16.0;
  lbm::LatticeKind lattice = lbm::LatticeKind::D3Q19;
  lbm::CollisionKind collision = lbm::CollisionKind::trt;
  double trt_magic = lbm::kWallExactTrtMagic;                      ///< TRT only: Lambda = (tau+ - 1/2)(tau- - 1/2)
  lbm::SubgridModel subgrid_model = lbm::SubgridModel::automatic;  ///< the run's: CasePlan::subgrid_model
  double smagorinsky_constant = lbm::kDefaultSmagorinskyConstant;  ///< C_S, with SubgridModel::smagorinsky
  lbm::Precision precision = lbm::kDefaultPrecision;
  CouplingKind coupling = kDefaultCoupling;
  lbm::WallRule wall_rule = lbm::kDefaultWallRule;       ///< momentum exchange only
  bool covered_cell_torque = kDefaultCoveredCellTorque;  ///< momentum exchange only
  /// Lattice steps per step of the body (1 or 2; momentum exchange only): with 2 the body moves once
  /// per two lattice steps with the wrench of both (Simulation::step; docs/coupling.md, "Force averaging").
  int lattice_steps_per_body_step = 1;
  ibm::DeltaKernel kernel = ibm::DeltaKernel::Roma3;
  int forcing_iterations = 3;
  double marker_retraction_cells = calibrated_marker_retraction_cells(false);  ///< cells; docs/coupling.md
  bool interior_markers = false;  ///< volume markers inside the body (make_body_markers)
  double max_lattice_velocity = 0.05;
  double max_tau = 2.0;
  std::optional<double> tau;

  // Particle-wall contact (body/contact.hpp) with the walls of the non-periodic axes. Off when the
  // window follows the particle (it then never nears a face: the window keeps it at its start).
  bool wall_contact = true;
  double contact_restitution = 0.97;  ///< dry normal restitution e in (0, 1] (glass, steel: ~0.97)
  /// beta of the wet restitution e exp(-beta / St) (body/contact.hpp; Legendre et al. 2006); 0: dry contacts
  double contact_wet_stokes_scale = 35.0;
  double contact_collision_steps = 10.0;  ///< collision time T_c in fluid time steps (Kempe and Froehlich 2012)
  /// Gap (cells) at which the contact spring starts; unset: the coupling's reach
  /// (contact_distance_cells, case_plan.hpp).
  std::optional<double> contact_distance_cells;

  double end_time_si = 1.0;
  double output_interval_si = 0.005;
};

}  // namespace settle::coupling
