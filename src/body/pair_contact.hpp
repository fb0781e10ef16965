#pragma once
// Body-body contact: the force and torque between two rigid bodies of any convex shape that touch,
// and a sub-stepped integrator of free bodies under these contacts alone (no fluid). The building
// block of many-particle runs (issue 72); nothing in coupling/ uses it yet.
//
// Geometry: the signed distance d, the normal n (from A towards B) and the closest points p_a, p_b
// of the two bodies (body/convex_distance.hpp). The contact acts at the midpoint x_c = (p_a + p_b)/2
// with the overlap delta = zeta_c - d (zeta_c the contact distance, as the wall's: the spring starts
// zeta_c before the surfaces touch) and the arms r_a = x_c - x_A, r_b = x_c - x_B.
//
// Normal force: the wall model's linear spring-dashpot (Cundall and Strack 1979, Geotechnique 29, 47,
// doi:10.1680/geot.1979.29.1.47; body/contact.hpp) with the pair's masses,
//
//   F_n = k delta - c u_n,     u_n = n . u,   u = (v_B + omega_B x r_b) - (v_A + omega_A x r_a),
//   k = m* (pi^2 + ln^2 e) / T_c^2,   c = -2 ln(e) sqrt(m* m_eff) / T_c,   m* = m_A m_B / (m_A + m_B),
//   m_eff = 1 / (1/m_A + 1/m_B + (r_a x n)^T I_A^-1 (r_a x n) + (r_b x n)^T I_B^-1 (r_b x n)),
//
// m_eff the effective mass of a frictionless point impact between two free bodies (Stronge 2000,
// Impact Mechanics, Cambridge University Press, chapter 3): a normal impulse J changes u_n by
// J / m_eff. For a centred impact (two spheres) m_eff = m*, and a dry free collision lasts exactly T_c
// and leaves with e times the normal speed it came in with, as a sphere on a wall does with m; an
// off-centre one lasts T_c sqrt(m_eff / m*) with the same e (the spring is the gradient of the
// potential k delta^2 / 2 and the dashpot keeps the damping ratio). As at the wall the force is not
// clipped at zero (the dashpot pulls slightly near the end of a rebound) and the dashpot switches on
// with the contact. The restitution is the dry one: the wet restitution of the wall model (Legendre
// et al. 2006) is not applied to pairs here.
//
// Tangential force: Coulomb friction with a tangential spring that remembers the tangential
// displacement xi of the contact during a contact (Cundall and Strack 1979; Luding 2008, Granular
// Matter 10, 235, doi:10.1007/s10035-008-0099-x):
//
//   d xi / dt = u_t = u - u_n n,      F_t = -k_t xi,      |F_t| <= mu max(F_n, 0),
//
// On every evaluation xi is first rotated into the current tangent plane (its normal component
// removed and its length kept, Luding's rule for a normal that turns during the contact); when
// k_t |xi| exceeds mu F_n the contact slides: F_t is cut to mu F_n along its direction and xi to
// -F_t / k_t, so the spring holds no more than the friction can (Luding 2008). xi starts at zero when
// a contact begins and is forgotten when it ends. A pulling normal force (the dashpot's, near the end
// of a rebound) transmits no friction: Luding bounds F_t by mu |F_n|, which would let the pull add a
// tangential impulse; with F_n's positive part, the tangential impulse of a contact is at most mu times
// its compressive impulse. No tangential dashpot: a stuck contact's
// tangential motion is undamped and dissipation is by sliding only (Luding adds one; an
// approximation, noted here, that leaves the tangential restitution of a fully stuck impact at -1).
// k_t = kappa k with kappa = tangential_stiffness_ratio, 2/7 by default: the stuck tangential motion
// of two solid spheres is then an oscillator with the normal one's frequency (the contact point's
// tangential mobility is 7 / (2 m*) against the normal 1 / m*), so the two have the same time scale
// T_c and the sub-stepping resolves both. mu = 0 gives a frictionless contact.
//
// The force on B is F = F_n n + F_t and on A -F, both at x_c: equal and opposite, torques r_a x (-F)
// and r_b x F about each centre of mass, so linear and angular momentum about any point are
// conserved exactly by each evaluation.
//
// Parameters a user sets: the restitution e, the friction coefficient mu, the collision time T_c
// (k, c and k_t follow from them and the masses as above), the contact distance zeta_c, and, rarely,
// kappa and the substeps per collision.
//
// Integration (advance_in_contact): as the wall contact (body/contact.hpp), substeps of at most
// T_c / N (N = substeps_per_collision, 100) with the explicit midpoint rule: each substep evaluates
// every pair's force at its start, moves every body half a substep with it, evaluates again there,
// and takes the whole substep with that midpoint wrench; the spring of each pair advances by the
// midpoint's u_t times the substep. Only pairs whose bounding spheres are within zeta_c are asked
// (all pairs are tried: O(N^2), for a few bodies).
//
// Frames and units: inertial frame, SI; torques about each body's centre of mass.
#include <cstddef>
#include <map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "body/contact.hpp"
#include "body/convex_distance.hpp"
#include "body/rigid_body.hpp"
#include "body/shape.hpp"

namespace settle::body {

/// Parameters of the body-body contact model (file comment).
struct PairContactParameters {
  double restitution = 0.97;          ///< dry normal restitution e, in (0, 1]
  double friction_coefficient = 0.0;  ///< Coulomb's mu, >= 0
  double collision_time_si = 0.0;     ///< T_c, s, > 0
  double contact_distance_si = 0.0;   ///< zeta_c, m, >= 0: the distance at which the spring starts
  /// k_t / k, > 0: 2/7 gives the stuck tangential motion of two spheres the normal one's frequency.
  double tangential_stiffness_ratio = 2.0 / 7.0;
  int substeps_per_collision = 100;  ///< the substep is at most T_c / this
};

/// Throws std::invalid_argument for e outside (0, 1], mu < 0, T_c <= 0, zeta_c < 0, kappa <= 0 or
/// fewer than one substep per collision.
void validate_pair_contact(const PairContactParameters& parameters);

/// Effective mass (kg) of a frictionless point impact along the unit normal n between two free
/// bodies of masses m_a, m_b and inverse inertia tensors (inertial, about their centres of mass),
/// touching at offsets r_a, r_b from their centres (file comment; Stronge 2000).
double pair_effective_mass(double mass_a_si, const Eigen::Matrix3d& inverse_inertia_a_n,
                           const Eigen::Vector3d& arm_a_si, double mass_b_si,
                           const Eigen::Matrix3d& inverse_inertia_b_n, const Eigen::Vector3d& arm_b_si,
                           const Eigen::Vector3d& normal);

/// Normal stiffness k and damping c of a pair of masses m_a, m_b touching with effective mass m_eff:
/// the wall's law with the reduced mass m* in place of m (file comment).
SpringDashpot pair_spring_dashpot(double mass_a_si, double mass_b_si, double effective_mass_si,
                                  const PairContactParameters& parameters);

/// A body taking part in contacts: its shape and its rigid body (state and mass properties).
struct ContactBody {
  const Shape* shape = nullptr;
  const RigidBody* body = nullptr;
};

/// The contact between two bodies at their current states.
struct PairContactForce {
  bool touching = false;  ///< delta > 0: the force below acts
  ConvexSeparation separation;
  Wrench on_a, on_b;                                              ///< inertial, about each centre of mass
  double normal_force_si = 0.0;                                   ///< F_n, N, along the normal on B
  Eigen::Vector3d tangential_force_si = Eigen::Vector3d::Zero();  ///< F_t on B, N
  /// The tangential spring xi after its rotation into the tangent plane and its cut on sliding, m.
  Eigen::Vector3d spring_si = Eigen::Vector3d::Zero();
  /// u_t, the tangential velocity of B's contact point relative to A's, m/s.
  Eigen::Vector3d tangential_velocity_si = Eigen::Vector3d::Zero();
};

/// Force and torques of the contact between a and b with the tangential spring `spring_si` (zero
/// for a contact that begins now; file comment). Not touching: no force, spring or velocity (the
/// separation is still given).
PairContactForce pair_contact_force(const ContactBody& a, const ContactBody& b, const Eigen::Vector3d& spring_si,
                                    const PairContactParameters& parameters);

/// The tangential springs of the pairs in contact, by the pair's body indices (i < j).
using PairSprings = std::map<std::pair<std::size_t, std::size_t>, Eigen::Vector3d>;

/// What one step of advance_in_contact did.
struct PairContactStep {
  int substeps = 1;       ///< 1 when no pair was within reach
  bool touching = false;  ///< some pair's contact force acted during the step
};

/// Advances free bodies by dt under their pair contacts (plus each body's gravity and buoyancy, as
/// RigidBody::correct applies them), sub-stepped (file comment); `springs` carries the contacts'
/// tangential springs from step to step. Throws std::invalid_argument when the shapes do not match
/// the bodies one to one or the parameters are invalid.
PairContactStep advance_in_contact(std::vector<RigidBody>& bodies, const std::vector<const Shape*>& shapes,
                                   PairSprings& springs, double dt_si, const PairContactParameters& parameters);

}  // namespace settle::body
