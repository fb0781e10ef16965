#pragma once
// A sampled time series of body angular velocity, for reconstructing an attitude from
// measured or simulated body rates (the standalone use of the dual-Euler solver in
// Cheng et al. 2023, doi:10.1063/5.0165555, supplementary material).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace settle::attitude {

/// Body rates omega_b (body frame, rad/s) sampled at strictly increasing times (s), read
/// between samples by linear interpolation (an approximation of the unknown signal that is
/// second-order accurate in the sample spacing; it limits the attitude accuracy when the
/// samples are coarser than the integration step).
class BodyRateSeries {
 public:
  /// Throws std::invalid_argument unless there are at least two samples, the sizes match,
  /// every value is finite and the times increase strictly.
  BodyRateSeries(std::vector<double> times_si, std::vector<Eigen::Vector3d> omega_b);

  /// Reads a CSV file whose header is t,wx,wy,wz followed by one sample per row (blank lines
  /// ignored, spaces around fields allowed). Throws settle::InputError naming the file and
  /// line for an unreadable file, a wrong header, a malformed row or non-increasing times.
  [[nodiscard]] static BodyRateSeries read_csv(const std::string& path);

  /// omega_b at time t by linear interpolation. Throws std::out_of_range outside
  /// [start_time(), end_time()].
  [[nodiscard]] Eigen::Vector3d at(double t_si) const;

  [[nodiscard]] double start_time() const { return times_.front(); }
  [[nodiscard]] double end_time() const { return times_.back(); }
  [[nodiscard]] std::size_t size() const { return times_.size(); }

 private:
  std::vector<double> times_;
  std::vector<Eigen::Vector3d> omega_b_;
};

}  // namespace settle::attitude
