#include "body/mass_properties.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace settle::body {
namespace {

// Off-diagonal entries below this fraction of the largest entry are round-off: a box mesh read
// from a file in its own axes has off-diagonals near 1e-17 of the diagonal.
constexpr double kDiagonalTolerance = 1e-12;

bool is_diagonal(const Eigen::Matrix3d& m) {
  const double scale = m.cwiseAbs().maxCoeff();
  const double off = std::max({std::abs(m(0, 1)), std::abs(m(0, 2)), std::abs(m(1, 2)), std::abs(m(1, 0)),
                               std::abs(m(2, 0)), std::abs(m(2, 1))});
  return off <= kDiagonalTolerance * scale;
}

void make_largest_component_positive(Eigen::Ref<Eigen::Vector3d> v) {
  Eigen::Index i = 0;
  v.cwiseAbs().maxCoeff(&i);
  if (v(i) < 0.0) v = -v;
}

}  // namespace

Eigen::Matrix3d inertia_from_second_moment(const Eigen::Matrix3d& second_moment, double density) {
  return density * (second_moment.trace() * Eigen::Matrix3d::Identity() - second_moment);
}

PrincipalFrame principal_frame(const Eigen::Matrix3d& tensor) {
  PrincipalFrame frame;
  if (is_diagonal(tensor)) {
    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int i, int j) { return tensor(i, i) < tensor(j, j); });
    for (int k = 0; k < 3; ++k) {
      frame.moments(k) = tensor(order[k], order[k]);
      frame.axes.col(k) = Eigen::Vector3d::Unit(order[k]);
    }
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 * (tensor + tensor.transpose()));
    frame.moments = solver.eigenvalues();  // ascending
    frame.axes = solver.eigenvectors();
  }
  make_largest_component_positive(frame.axes.col(0));
  make_largest_component_positive(frame.axes.col(1));
  frame.axes.col(2) = frame.axes.col(0).cross(frame.axes.col(1));
  return frame;
}

MassProperties mass_properties_from_moments(const VolumeMoments& moments, double density) {
  MassProperties props;
  props.density = density;
  props.volume = moments.volume;
  props.mass = density * moments.volume;
  props.centroid = moments.centroid;
  props.inertia = inertia_from_second_moment(moments.second_moment, density);
  props.principal = principal_frame(props.inertia);
  return props;
}

}  // namespace settle::body
