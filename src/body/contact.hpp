#pragma once
// Particle-wall contact: a soft normal contact force between a rigid body of any shape and plane
// walls, applied at the body's point nearest to each wall (so it also exerts a torque), and the
// sub-stepped integration that keeps it stable inside an explicit coupled time step.
//
// Model: the linear spring-dashpot of Cundall and Strack 1979 (Geotechnique 29, 47,
// doi:10.1680/geot.1979.29.1.47) with its stiffness and damping set from a collision time T_c
// stretched to several fluid time steps and a dry normal restitution coefficient e, as in the
// soft-sphere collision models of resolved-particle simulations (Breugem 2010, ASME
// FEDSM-ICNMM2010-30634; Costa, Boersma, Westerweel and Breugem 2015, Phys. Rev. E 92, 053012,
// doi:10.1103/PhysRevE.92.053012; Kempe and Froehlich 2012, J. Fluid Mech. 709, 445,
// doi:10.1017/jfm.2012.343, who use T_c = 10 fluid steps):
//
//   overlap   delta = zeta_c - g            (g: gap between the wall plane and the body)
//   force     F = (k delta - c v_n) n       for delta > 0, zero otherwise
//   k = m (pi^2 + ln^2 e) / T_c^2,          c = -2 ln(e) sqrt(m m_eff) / T_c    (dry contact, e = e_dry)
//
// n is the wall's unit normal into the fluid and v_n = n . (v + omega x r) the normal velocity of
// the contact point (r from the centre of mass). For a centred impact (m_eff = m, a sphere) these
// are the papers' k and c: a free dry impact lasts exactly T_c and leaves with e times the normal
// speed it came in with (the damped oscillator's half period and decrement). As in those papers
// the force is not clipped at zero: near the end of a rebound the dashpot pulls slightly; clipping
// would move e away from its closed form. The dashpot term switches on with the contact, so the
// force jumps by c |v_n| when a moving body first touches; the spring term is continuous.
//
// Why this model for arbitrary shapes:
//  - It needs only the gap and the contact point, which every shape provides through its support
//    function h(u) = max over the body of u . x (body/shape.hpp): the body point nearest to a plane
//    is the support point in the direction of the wall, for convex and non-convex bodies alike (the
//    nearest point lies on the convex hull). Glowinski et al. 1999 (Int. J. Multiphase Flow 25, 755,
//    doi:10.1016/S0301-9322(98)00048-2)'s short-range repulsion needs the same two quantities but
//    has no dissipation (every dry bounce is elastic) and a stiffness parameter without a physical
//    meaning; the spring-dashpot is set by a time scale the fluid solver resolves and by a material
//    property, e.
//  - An off-centre impact (a tilted spheroid touching with its tip) moves the contact point with
//    the effective mass m_eff = 1 / (1/m + (r x n)^T I_n^-1 (r x n)) of a frictionless point
//    impact on a free rigid body (Stronge 2000, Impact Mechanics, Cambridge University Press,
//    chapter 3): a normal impulse J changes the contact point's normal velocity by J / m_eff. The
//    stiffness stays that of the whole mass, so the spring is the force of the potential
//    k delta(pose)^2 / 2 and an elastic (e = 1) contact conserves energy exactly for every shape;
//    the dashpot uses m_eff so the contact oscillator (mass m_eff, stiffness k) keeps the damping
//    ratio -ln e / sqrt(pi^2 + ln^2 e) and hence the restitution e; it lasts T_c sqrt(m_eff / m)
//    <= T_c. For a sphere r is parallel to n and m_eff = m (Costa et al. 2015's particle-wall mass).
//  - Lubrication corrections (Brenner 1961, Cox and Brenner 1967) are not added. They are closed
//    forms for a smooth curved surface near a wall; a flat face parallel to the wall (cuboid,
//    cylinder end, mesh facet) has a squeeze-film force that diverges as 1/h^3 and an edge one
//    that diverges logarithmically, with no published closed form for arbitrary bodies. The
//    dissipation of the unresolved gap is left to the restitution (below) and to the resolved flow;
//    docs/rigid-body.md.
//
// Wet restitution: in a viscous liquid the film drained in the last part of the approach takes
// most of the impact energy, and an immersed sphere does not rebound at all below an impact Stokes
// number St = rho_p v d / (9 mu) of about 10 (Gondret, Lance and Petit 2002, Phys. Fluids 14, 643,
// doi:10.1063/1.1427920). The fluid solver cannot resolve that film: the spring starts zeta_c
// (about 1.5 cells) above the wall. So each contact takes the measured effective restitution of
// Legendre, Zenit, Daniel and Guiraud 2006 (Chem. Eng. Sci. 61, 3543,
// doi:10.1016/j.ces.2005.12.033), their fit to Gondret's and Joseph's data,
//
//   e = e_dry exp(-beta / St),   beta = 35 (contact.wet_stokes_scale; 0 keeps every contact dry),
//
// with v the normal speed of the contact point when the gap first falls below zeta_c, rho_p the
// body's mean density and d its volume-equivalent diameter (exact for a sphere; for other shapes an
// approximation: the fit was made with spheres). The restitution, and with it c, is then fixed for
// that contact until the gap opens again; a body resting on a wall is one long contact.
// The liquid changes only the dashpot: k stays the dry one (the solids' stiffness, and the static
// compression W/k with it), and c = 2 zeta sqrt(k m_eff) takes the damping ratio
// zeta = -ln e / sqrt(pi^2 + ln^2 e) of the wet e. A wet contact therefore lasts longer than T_c,
// T_c sqrt((pi^2 + ln^2 e) / (pi^2 + ln^2 e_dry)) for a centred impact, which also spreads the
// stop over more fluid steps. e is floored at 1e-3 e_dry (zeta = 0.91, the contact lasting 2.45 T_c
// for e_dry = 0.97): an underdamped contact ends, and a rebound of 1e-3 of the impact speed is
// none in practice. The overlap stays below v T_c / pi (max_overlap_bound): damping only lowers it.
//
// Contact distance zeta_c (the shift): the spring starts when the gap falls below zeta_c rather
// than at g = 0. The immersed boundary smears the surface over its delta kernel's half-width, so a
// gap below about a cell is not represented by the fluid, and the kernel's stencils of the surface
// markers must stay inside the grid (coupling/simulation.hpp chooses zeta_c from the kernel). The
// body rests at g = zeta_c - W/k under a net weight W; an impact at normal speed v reaches at most
// delta = 2 W/k + v T_c / pi (max_overlap_bound; the contact's angular frequency is at least
// pi / T_c).
//
// No tangential force (friction) is modelled: the contact force is normal to the wall. A body
// sliding or rolling on the wall is slowed only by the fluid.
//
// Contact point: the support point, i.e. the gradient of h, taken by central differences of the
// support function with a relative step of 1e-4 (support_point). Where h is smooth (sphere,
// ellipsoid, superellipsoid, a generic pose of any shape) this is the nearest point to within
// O(1e-8) of the body's size. Where the nearest set is a face or an edge parallel to the wall
// (a cuboid or a cylinder lying flat, a mesh facet), the central difference returns the middle of
// its extent along each axis, so a face resting on the wall is pushed at its centre and feels no
// spurious torque; within a few 1e-4 rad of that alignment the point moves continuously to the
// corner or the rim.
//
// Integration: the wall force changes on the time scale T_c (a few fluid steps), so the step's
// corrector is split into substeps of at most h = T_c / N (N = substeps_per_collision, 100); in
// each the contact wrench is evaluated at the substep's midpoint (explicit midpoint rule, second
// order), the other external wrench (the fluid's) held constant over the whole step as the coupled
// step does. The dashpot switching on and off inside a substep is not located: each switch costs at
// most half a substep of dashpot impulse, c |v_n| h / 2, so a dry impact's restitution is e to
// within |ln e| (1 + e) / N (0.6% of e for e = 0.97, 2% for e = 0.5; tests/body/test_contact.cpp).
//
// Frames and units: inertial frame, SI; torques about the centre of mass. The walls are fixed
// planes; a body moves in front of them.
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "body/rigid_body.hpp"
#include "body/shape.hpp"

namespace settle::body {

/// A plane wall: the fluid side is { x : normal . x >= offset_si }. `normal` is the unit normal
/// pointing into the fluid (inertial frame); offset_si the plane's signed distance from the origin.
struct WallPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_si = 0.0;
};

/// The body's point nearest to a wall plane.
struct WallProximity {
  /// Distance from the plane to the nearest body point, m; negative when the body crosses the plane.
  double gap_si = 0.0;
  /// The nearest point (the contact point), inertial, m.
  Eigen::Vector3d point_si = Eigen::Vector3d::Zero();
};

/// The support point of the shape in the body-frame direction `direction_b` (any non-zero
/// length): the gradient of the support function by central differences (file comment). Lies on
/// the surface, and direction . point = support(direction) where the nearest set is a point.
Eigen::Vector3d support_point(const Shape& shape, const Eigen::Vector3d& direction_b);

/// Gap between the wall plane and the shape at a pose (centre of mass `position_si`, attitude
/// C_b^n `body_to_inertial`): the exact support function; no contact point.
double wall_gap(const Shape& shape, const Eigen::Vector3d& position_si, const Eigen::Matrix3d& body_to_inertial,
                const WallPlane& wall);

/// Gap and contact point (file comment).
WallProximity nearest_to_wall(const Shape& shape, const Eigen::Vector3d& position_si,
                              const Eigen::Matrix3d& body_to_inertial, const WallPlane& wall);

/// Parameters of the normal contact model.
struct ContactParameters {
  double restitution = 0.97;         ///< dry normal restitution coefficient e, in (0, 1]
  double collision_time_si = 0.0;    ///< T_c, s, > 0
  double contact_distance_si = 0.0;  ///< zeta_c, m, >= 0: the gap at which the spring starts
  /// Substeps per collision time: the substep is at most T_c / this (file comment).
  int substeps_per_collision = 100;
  /// beta of the wet restitution e_dry exp(-beta / St) (file comment); 0: every contact is dry.
  double wet_stokes_scale = 0.0;
  /// Dynamic viscosity of the liquid, Pa s, for the impact Stokes number; > 0 when wet_stokes_scale > 0.
  double fluid_dynamic_viscosity_si = 0.0;
};

/// Smallest wet restitution as a fraction of the dry one (file comment).
inline constexpr double kMinimumWetRestitutionRatio = 1.0e-3;

/// Impact Stokes number rho_p v d / (9 mu) (Gondret et al. 2002): body density (kg/m^3), normal
/// impact speed (m/s, its magnitude is used), diameter (m), dynamic viscosity (Pa s).
double impact_stokes_number(double body_density_si, double impact_speed_si, double diameter_si, double viscosity_si);

/// Restitution of a contact that starts at the given impact Stokes number: e_dry when
/// wet_stokes_scale is 0, else e_dry max(exp(-beta / St), kMinimumWetRestitutionRatio).
double contact_restitution(const ContactParameters& parameters, double impact_stokes_number);

/// Spring stiffness k (N/m) and dashpot coefficient c (N s/m) of the model for a body of mass m
/// touching with effective mass m_eff (kg; file comment): a free impact lasts T_c sqrt(m_eff / m)
/// and has restitution e.
struct SpringDashpot {
  double stiffness = 0.0;
  double damping = 0.0;
};
SpringDashpot spring_dashpot(double mass_si, double effective_mass_si, const ContactParameters& parameters);
/// The same for a contact of restitution e in (0, 1] (a wet contact's): k is still the dry one, and
/// c gives the damping ratio of e (file comment).
SpringDashpot spring_dashpot(double mass_si, double effective_mass_si, const ContactParameters& parameters,
                             double restitution);

/// Effective mass of a frictionless point impact along the unit normal n at offset r (inertial,
/// from the centre of mass) on a body of mass m and inertia I_n (inertial frame, about the centre
/// of mass): 1 / (1/m + (r x n)^T I_n^-1 (r x n)).
double effective_mass(double mass_si, const Eigen::Matrix3d& inverse_inertia_n, const Eigen::Vector3d& offset_si,
                      const Eigen::Vector3d& normal);

/// Largest overlap (m) an impact can reach: a body pressed on the wall by a steady net force
/// `load_si` (N, along -n) that arrives with normal speed `impact_speed_si` (m/s), for a model of
/// stiffness k: 2 load / k + impact_speed T_c / pi (undamped bound: the static compression plus
/// the amplitude of the oscillation about it, with the contact's angular frequency >= pi / T_c).
double max_overlap_bound(double load_si, double impact_speed_si, double stiffness_si, double collision_time_si);

/// What one contact-aware corrector step did.
struct ContactStep {
  Wrench mean_wrench;  ///< contact impulse and angular impulse over the step divided by dt
  double min_gap_si = std::numeric_limits<double>::infinity();  ///< smallest gap seen at a substep's start or end
  int substeps = 1;                                             ///< 1 when no wall was within reach
  bool touching = false;                                        ///< some wall's contact force acted during the step
};

/// The contact model for one body and a set of plane walls.
class WallContact {
 public:
  /// Throws std::invalid_argument for an empty shape, a non-unit wall normal, e outside (0, 1],
  /// T_c <= 0, zeta_c < 0, fewer than one substep per collision, a negative wet_stokes_scale, or a
  /// wet one without a positive viscosity.
  WallContact(std::shared_ptr<const Shape> shape, std::vector<WallPlane> walls, const ContactParameters& parameters);

  const std::vector<WallPlane>& walls() const { return walls_; }
  const ContactParameters& parameters() const { return parameters_; }
  const Shape& shape() const { return *shape_; }

  /// Contact wrench on a body in the given state (inertial, about the centre of mass; zero when no
  /// wall is within zeta_c). A wall whose contact is in progress uses the restitution fixed when it
  /// began; for any other the contact would begin now, at the state's normal speed.
  Wrench wrench(const RigidBody& body, const RigidBodyState& state) const;

  /// For each wall, the normal speed (m/s, >= 0) at which the contact in progress began, or none.
  /// Part of the body's state for a restart (checkpoints save it).
  const std::vector<std::optional<double>>& impact_speeds_si() const { return impact_speeds_si_; }
  /// Restores impact_speeds_si() (one entry per wall; throws std::invalid_argument otherwise).
  void restore_impact_speeds(std::vector<std::optional<double>> speeds_si);
  /// Restitution of a contact that begins at this normal speed for a body of this mass.
  double restitution_at(double impact_speed_si, double mass_si) const;
  /// Smallest gap to any wall at the state's pose, m (infinity without walls).
  double min_gap_si(const RigidBodyState& state) const;

  /// Advances a free body over dt with `external` (inertial, e.g. hydrodynamic) held constant plus
  /// the contact wrench, sub-stepped when a wall is within reach this step (file comment);
  /// otherwise exactly body.correct(dt, external). Towed and fixed bodies: body.correct(dt, external).
  ContactStep advance(RigidBody& body, double dt_si, const Wrench& external);
  /// The same with the corrector's virtual mass and inertia (RigidBody::correct), applied in every
  /// substep with the whole step's acceleration estimate, so that a body at rest on a wall
  /// (a = a_est = 0) balances exactly as without it.
  ContactStep advance(RigidBody& body, double dt_si, const Wrench& external, const VirtualInertia& virtual_inertia);

 private:
  bool within_reach(const RigidBodyState& state, double dt_si) const;
  int substep_count(double dt_si) const;
  /// Starts or ends each wall's contact record at the state (the impact speed when a gap has just
  /// fallen below zeta_c, none when it is above); returns the smallest gap (as min_gap_si).
  double update_impacts(const RigidBodyState& state);

  std::shared_ptr<const Shape> shape_;
  std::vector<WallPlane> walls_;
  ContactParameters parameters_;
  std::vector<std::optional<double>> impact_speeds_si_;
};

}  // namespace settle::body
