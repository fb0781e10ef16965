#pragma once
// Distance, closest points and normal between two convex bodies in given poses, from their support
// functions alone (body/shape.hpp): the geometric half of a body-body contact (body/pair_contact.hpp).
//
// Signed distance: the largest separation of the two bodies along any unit direction u,
//
//   s(u) = u . (x_B - x_A) - h_A(u) - h_B(-u),       d = max over unit u of s(u),
//
// (h_A, h_B the support functions in inertial directions, x_A, x_B the centres). d > 0 is the
// Euclidean distance of separated bodies; d < 0 is minus the penetration depth of overlapping ones
// (the length of the shortest translation of B that separates them); the maximising u is the normal,
// from A towards B. In terms of the Minkowski difference D = A - B (support h_D(u) = h_A(u) + h_B(-u)
// plus the centres): d = dist(0, D) when 0 is outside D and -dist(0, boundary of D) when inside.
//
// Methods:
//  - Separated bodies: GJK (Gilbert, Johnson and Keerthi 1988, IEEE J. Robot. Autom. 4, 193,
//    doi:10.1109/56.2083): the point of D nearest the origin from simplices of support points. The
//    nearest point of a simplex is found by trying each of its faces (at most 15 for a tetrahedron)
//    and keeping the nearest affine projection with non-negative barycentric weights, which is the
//    nearest point of the simplex whatever its shape (a brute-force form of Johnson's
//    sub-algorithm, robust to flat simplices: a degenerate face is skipped and its sub-faces used).
//  - Overlapping bodies (or bodies nearer than kNearContact of their size, where GJK's normal is
//    ill-defined): EPA (van den Bergen 2001, "Proximity queries and penetration depth computation on
//    3D game objects", Game Developers Conference): the polytope of support points around the
//    origin inside D is expanded towards its face nearest the origin until the support function in
//    that face's normal is within the tolerance of the face's distance.
//  - Two spheres: the closed form (exact; used whenever both shapes are spheres).
//
// The distance returned is that of the closest points found, which lie on the bodies: for separated
// bodies GJK's |v| (an upper bound of d), for overlapping ones EPA's nearest face of the polytope
// inside D (a bound of the depth from below); both stop when they are within kRelativeTolerance of
// the bodies' size (sum of bounding radii) of the exact value, the gap between them and the
// separation along their normal, s(n), a lower bound of d. Near contact both are asked and the
// normal with the larger s(n) is kept, so the distance is continuous as the bodies move through
// contact. point_b - point_a = d n holds to round-off. The normal is accurate to about the square
// root of the tolerance where the Minkowski difference is curved and exactly where it is flat; the
// points are each body's support points combined with the final simplex's or face's barycentric
// weights. Where the touching set is a face or an edge (two cuboids face to face) any of its points
// is a valid closest point, and which one is returned is not specified.
//
// Support points: the cuboid, the ellipsoid (and sphere, spheroid) and the cylinder use their
// closed forms; other shapes the central differences of support_point (body/contact.hpp), which at
// an edge or a corner blend the two sides of the kink within 1e-4 rad of it, giving a point on the
// supporting plane up to 1e-4 of the size off the body, and so limit the accuracy there.
//
// Non-convex bodies (meshes other than convex ones; every analytic shape is convex) are out of
// scope: a support function only sees a body's convex hull (h is the same for a body and its hull),
// so a mesh is treated as its hull: hollows and concave pockets are filled, two bodies whose
// hulls overlap are "in contact" although their surfaces may not touch, and the contact point can
// lie in the air across a pocket. A non-convex body would need a decomposition into convex parts
// (each with its own support function, the contact taken per pair of parts) or a surface-based
// query on the triangles (the BVH of body/triangle_bvh.hpp).
//
// Frames and units: inertial frame, SI; each body given by its shape (body frame, origin at the
// centroid), centroid position and attitude C_b^n.
#include <Eigen/Core>

#include "body/shape.hpp"

namespace settle::body {

/// A shape placed in the inertial frame: centroid at `position_si`, attitude C_b^n `body_to_inertial`.
struct PlacedShape {
  const Shape* shape = nullptr;
  Eigen::Vector3d position_si = Eigen::Vector3d::Zero();
  Eigen::Matrix3d body_to_inertial = Eigen::Matrix3d::Identity();
};

/// Relative tolerance of the iterations (file comment): a fraction of the sum of bounding radii.
inline constexpr double kRelativeTolerance = 1.0e-10;
/// Below this fraction of the bodies' size GJK's normal (its nearest point's direction) is not
/// trusted and EPA is asked as well (file comment). The support points carry an error of ~1e-8 of
/// the size (support_point's central differences); 1e-6 is well above it.
inline constexpr double kNearContact = 1.0e-6;

/// How two convex bodies stand to each other.
struct ConvexSeparation {
  /// Signed distance d, m: > 0 separated (the gap), < 0 overlapping (minus the penetration depth).
  double distance_si = 0.0;
  /// Unit normal from A towards B: translating B along it by -d (when d < 0) separates them.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
  /// Closest points on A and on B (for an overlap, each body's deepest point inside the other), m:
  /// point_b - point_a = d normal to the accuracy stated in the file comment.
  Eigen::Vector3d point_a_si = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b_si = Eigen::Vector3d::Zero();
  /// GJK plus EPA iterations taken (0 for the closed form).
  int iterations = 0;
};

/// The separation of two convex bodies: the closed form when both are spheres, else
/// support_separation. Throws std::invalid_argument for a missing shape.
ConvexSeparation convex_distance(const PlacedShape& a, const PlacedShape& b);

/// GJK and EPA on the support functions, for any two convex shapes (file comment).
ConvexSeparation support_separation(const PlacedShape& a, const PlacedShape& b);

/// The closed form for two spheres of radii r_a, r_b (m) centred at x_a, x_b: d = |x_b - x_a| - r_a - r_b
/// along the line of centres (the x axis when the centres coincide).
ConvexSeparation sphere_separation(const Eigen::Vector3d& centre_a_si, double radius_a_si,
                                   const Eigen::Vector3d& centre_b_si, double radius_b_si);

/// s(u) of the file comment: the separation of the bodies along the unit direction u (m). Every u
/// gives a lower bound of the signed distance.
double separation_along(const PlacedShape& a, const PlacedShape& b, const Eigen::Vector3d& direction);

}  // namespace settle::body
