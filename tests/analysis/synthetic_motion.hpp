#pragma once
// Synthetic settling motions with known answers, sampled into the series the analysis reads
// (shared by test_observables.cpp and test_regime.cpp). Each motion is given analytically:
// velocity, attitude C_b^n and inertial angular velocity as functions of time; the position is
// the velocity integrated by the trapezoidal rule (exact for the constant and linear parts).
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "analysis/observables.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"

namespace settle::test {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180.0;

struct Motion {
  std::function<Eigen::Vector3d(double)> velocity = [](double) { return Eigen::Vector3d(0.0, 0.0, -0.01); };
  std::function<Eigen::Matrix3d(double)> attitude = [](double) { return Eigen::Matrix3d::Identity(); };
  std::function<Eigen::Vector3d(double)> omega_n = [](double) { return Eigen::Vector3d::Zero(); };
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< hydrodynamic force, constant
};

inline analysis::SettlingSeries sample_motion(const Motion& motion, double dt, double t_end) {
  analysis::SettlingSeries s;
  Eigen::Vector3d position(0.05, 0.05, 0.5);
  const auto n = static_cast<long>(std::lround(t_end / dt));
  for (long i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) * dt;
    if (i > 0) position += 0.5 * dt * (motion.velocity(t - dt) + motion.velocity(t));
    const Eigen::Matrix3d c = motion.attitude(t);
    const Eigen::Vector3d omega = motion.omega_n(t);
    s.add(t, position, motion.velocity(t), omega, c.transpose() * omega, c, motion.force);
  }
  return s;
}

inline Eigen::Matrix3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// A thin disk (diameter 4 mm, thickness 0.4 mm, aluminium-like 2700 kg/m^3) in water.
inline analysis::ParticleProperties disk_in_water() {
  return analysis::particle_properties(std::make_shared<body::Cylinder>(4e-3, 0.4e-3), 2700.0, 1000.0, 1.0e-3,
                                       Eigen::Vector3d(0.0, 0.0, -9.81));
}

/// A sphere of diameter d and density ratio 1.5 in water.
inline analysis::ParticleProperties sphere_in_water(double d) {
  return analysis::particle_properties(std::make_shared<body::Ellipsoid>(body::Ellipsoid::sphere(d)), 1500.0, 1000.0,
                                       1.0e-3, Eigen::Vector3d(0.0, 0.0, -9.81));
}

/// Deterministic phases in [0, 2 pi) (the bits of a linear congruential generator, so the
/// numbers are the same with every standard library).
inline std::vector<double> phases(std::size_t count, std::uint64_t seed) {
  std::vector<double> p;
  for (std::size_t i = 0; i < count; ++i) {
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    p.push_back(2.0 * kPi * static_cast<double>(seed >> 11) / 9007199254740992.0);
  }
  return p;
}

}  // namespace settle::test
