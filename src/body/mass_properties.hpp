#pragma once
// Volume moments and rigid-body mass properties of a homogeneous solid.
//
// Frames: the "input frame" is the frame the shape was given in (for analytic shapes the body
// frame itself; for a mesh, the STL file's axes after scaling). The body frame has the same
// axes with its origin at the centroid, so a tensor has the same components in both.
#include <Eigen/Dense>

namespace settle::body {

/// Geometric moments of a solid (density 1): volume, centroid (input frame) and the second
/// moment about the centroid, S = int (x - c)(x - c)^T dV (symmetric, positive definite).
struct VolumeMoments {
  double volume = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second_moment = Eigen::Matrix3d::Zero();
};

/// Principal moments (ascending) and the matching unit principal axes, stored as the columns
/// of a proper rotation matrix P (det P = +1), so that inertia = P diag(moments) P^T. P maps
/// principal-frame coordinates to body-frame coordinates: v_body = P v_principal.
struct PrincipalFrame {
  Eigen::Vector3d moments = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};

/// Mass properties for a uniform density (SI: kg/m^3 with lengths in m). The inertia tensor is
/// about the centroid in body axes: I = rho int (|r|^2 1 - r r^T) dV.
struct MassProperties {
  double density = 0.0;
  double volume = 0.0;
  double mass = 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  ///< input frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();   ///< about the centroid, body axes
  PrincipalFrame principal;

  /// The rotation taking the principal frame to the body frame (the quaternion of P).
  Eigen::Quaterniond rotation_body_from_principal() const { return Eigen::Quaterniond(principal.axes); }
};

/// Inertia tensor about the centroid from the second moment: I = rho (tr(S) 1 - S).
Eigen::Matrix3d inertia_from_second_moment(const Eigen::Matrix3d& second_moment, double density);

/// Principal moments and axes of a symmetric tensor. When the tensor is already diagonal to
/// round-off (every analytic shape, and meshes aligned with their file axes) the body axes are
/// returned, sorted, so that degenerate moments (spheres, spheroids, cubes) keep the shape's own
/// axes instead of an arbitrary basis of the eigenspace. Signs are canonical: the largest
/// component of the first two axes is positive, the third completes a right-handed frame.
PrincipalFrame principal_frame(const Eigen::Matrix3d& tensor);

/// Mass properties of a homogeneous solid of the given density from its volume moments.
MassProperties mass_properties_from_moments(const VolumeMoments& moments, double density);

}  // namespace settle::body
