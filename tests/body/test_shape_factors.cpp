// Shape factors for oblique flow and triaxial shapes, against closed forms.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "body/carlson.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"
#include "body/shape_factors.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace test_shape_factors {

using std::numbers::pi;

constexpr double kClosedForm = 1e-13;

TEST(ShapeFactors, TriaxialEllipsoidExtentsAndCorey) {
  // Semi-axes 1 > 0.6 > 0.3 along x, y, z: L = 2, I = 1.2, S = 0.6.
  const ShapeFactors f = compute_shape_factors(Ellipsoid(Eigen::Vector3d(1.0, 0.6, 0.3)), Eigen::Vector3d::UnitX());
  EXPECT_TRUE(f.principal_extents.isApprox(Eigen::Vector3d(2.0, 1.2, 0.6), kClosedForm));
  EXPECT_NEAR(f.corey_shape_factor, 0.3 / std::sqrt(0.6), kClosedForm);
  EXPECT_NEAR(f.flatness, 0.5, kClosedForm);
  EXPECT_NEAR(f.elongation, 0.6, kClosedForm);
  // Flow along x: the shadow is the y-z ellipse, pi b c.
  EXPECT_NEAR(f.projected_area_along_flow, pi * 0.18, kClosedForm);
  const double d_eq = std::cbrt(8.0 * 0.18);
  EXPECT_NEAR(f.crosswise_sphericity, d_eq * d_eq / (4.0 * 0.18), kClosedForm);
}

TEST(ShapeFactors, ObliqueFlowOnACylinder) {
  // Flow at 60 degrees from the axis of a cylinder (R = 0.5, L = 2): the shadow is
  // pi R^2 cos 60 + 2 R L sin 60; the side views average 2 R^2 s + (4 R L / pi) E(s) with
  // s = sin 60 (the axis' component across the flow).
  const Cylinder c(1.0, 2.0);
  const double s = std::sin(pi / 3), co = std::cos(pi / 3);
  const ShapeFactors f = compute_shape_factors(c, Eigen::Vector3d(s, 0.0, co) * 3.0);  // any length
  EXPECT_NEAR(f.flow_direction.norm(), 1.0, 1e-15);
  EXPECT_NEAR(f.projected_area_along_flow, pi * 0.25 * co + 2.0 * s, kClosedForm);
  EXPECT_NEAR(f.mean_projected_area_across_flow, 2 * 0.25 * s + 4.0 / pi * complete_elliptic_e(s), kClosedForm);
  const double sphere_section = pi / 4 * std::pow(6.0 * c.volume() / pi, 2.0 / 3.0);
  EXPECT_NEAR(f.lengthwise_sphericity, sphere_section / (0.5 * c.surface_area() - f.mean_projected_area_across_flow),
              kClosedForm);
}

TEST(ShapeFactors, RefusesZeroFlowDirection) {
  EXPECT_THROW(compute_shape_factors(Ellipsoid::sphere(1.0), Eigen::Vector3d::Zero()), settle::InputError);
}

}  // namespace test_shape_factors
}  // namespace settle::body
