// Principal frames and the inertia tensor from second moments.
#include <cmath>

#include <gtest/gtest.h>

#include "body/mass_properties.hpp"

namespace settle::body {
namespace test_mass_properties {

TEST(MassProperties, InertiaFromSecondMomentOfUnitCube) {
  // Unit cube about its centre: S = diag(1/12) per unit volume, I = rho (tr S - S) = rho/6.
  const Eigen::Matrix3d s = Eigen::Matrix3d::Identity() / 12.0;
  const Eigen::Matrix3d inertia = inertia_from_second_moment(s, 3.0);
  EXPECT_TRUE(inertia.isApprox(Eigen::Matrix3d::Identity() * 3.0 / 6.0, 1e-15));
}

TEST(MassProperties, DiagonalTensorKeepsBodyAxesSortedAscending) {
  const PrincipalFrame frame = principal_frame(Eigen::Vector3d(3.0, 1.0, 2.0).asDiagonal());
  EXPECT_EQ(frame.moments, Eigen::Vector3d(1.0, 2.0, 3.0));
  EXPECT_EQ(frame.axes.col(0).cwiseAbs(), Eigen::Vector3d::UnitY());
  EXPECT_EQ(frame.axes.col(1).cwiseAbs(), Eigen::Vector3d::UnitZ());
  EXPECT_EQ(frame.axes.col(2).cwiseAbs(), Eigen::Vector3d::UnitX());
  EXPECT_NEAR(frame.axes.determinant(), 1.0, 1e-15);
}

TEST(MassProperties, DegenerateDiagonalTensorKeepsBodyAxes) {
  // A sphere's or cube's isotropic tensor: any basis is principal; the body's own is returned.
  const PrincipalFrame frame = principal_frame(Eigen::Matrix3d::Identity() * 2.0);
  EXPECT_TRUE(frame.axes.isApprox(Eigen::Matrix3d::Identity(), 1e-15));
}

TEST(MassProperties, RotatedTensorRecoversRotation) {
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
                                    Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  const Eigen::Vector3d moments(0.5, 1.25, 4.0);
  const Eigen::Matrix3d tensor = rotation * moments.asDiagonal() * rotation.transpose();
  const PrincipalFrame frame = principal_frame(tensor);
  // Eigen's symmetric solver is backward stable: 1e-14 relative to the largest moment.
  EXPECT_TRUE(frame.moments.isApprox(moments, 1e-14));
  EXPECT_NEAR(frame.axes.determinant(), 1.0, 1e-14);
  EXPECT_TRUE((frame.axes * frame.moments.asDiagonal() * frame.axes.transpose()).isApprox(tensor, 1e-14));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(std::abs(frame.axes.col(i).dot(rotation.col(i))), 1.0, 1e-14);
}

TEST(MassProperties, MassPropertiesScaleWithDensity) {
  VolumeMoments m;
  m.volume = 2.0;
  m.centroid = Eigen::Vector3d(1, 2, 3);
  m.second_moment = Eigen::Vector3d(1.0, 2.0, 3.0).asDiagonal();
  const MassProperties p = mass_properties_from_moments(m, 1000.0);
  EXPECT_DOUBLE_EQ(p.mass, 2000.0);
  EXPECT_EQ(p.centroid, m.centroid);
  EXPECT_DOUBLE_EQ(p.inertia(0, 0), 1000.0 * 5.0);
  EXPECT_DOUBLE_EQ(p.inertia(2, 2), 1000.0 * 3.0);
  EXPECT_TRUE(p.rotation_body_from_principal().toRotationMatrix().isApprox(p.principal.axes, 1e-15));
}

}  // namespace test_mass_properties
}  // namespace settle::body
