#pragma once
// Small helpers shared by the attitude and rigid-body tests.
#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace settle::test {

/// maximum = max(maximum, value), but a NaN, once seen, stays (std::max would drop it).
inline void raise_to(double& maximum, double value) {
  if (std::isnan(maximum) || std::isnan(value)) {
    maximum = std::nan("");
  } else {
    maximum = std::max(maximum, value);
  }
}

inline double max_abs_difference(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

inline Eigen::Matrix3d rotation_about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

}  // namespace settle::test
