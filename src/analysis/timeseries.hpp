#pragma once
// A run's timeseries.csv (docs/architecture.md, "Contracts"; written by io/output_files.cpp), read back for
// analysis: first as named columns of numbers (Timeseries), then as the typed settling series
// the analysis works on (SettlingSeries).
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>  // Vector3d and Matrix3d need no aligned allocator (not 16-byte multiples)

namespace settle::coupling {
struct Sample;
}

namespace settle::analysis {

/// Columns of numbers addressed by their header names, in file order. Every column has the
/// same number of rows. Values are stored as read (non-finite values included).
class Timeseries {
 public:
  Timeseries() = default;
  /// `source` names the data in error messages (usually the file path).
  explicit Timeseries(std::string source) : source_(std::move(source)) {}

  /// Appends a column; std::invalid_argument when the name repeats or the length differs from
  /// the columns already present.
  void add_column(const std::string& name, std::vector<double> values);

  [[nodiscard]] bool has(std::string_view name) const;
  /// The column of that name; settle::InputError "<source>: missing column '<name>'" otherwise.
  [[nodiscard]] const std::vector<double>& column(std::string_view name) const;
  [[nodiscard]] const std::vector<std::string>& names() const { return names_; }
  [[nodiscard]] std::size_t rows() const { return columns_.empty() ? 0 : columns_.front().size(); }
  [[nodiscard]] const std::string& source() const { return source_; }

 private:
  std::string source_ = "timeseries";
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
};

/// Parses CSV text: one header line of unique, non-empty names, then rows of as many numbers
/// (std::from_chars syntax; surrounding blanks and a trailing CR are ignored; blank lines are
/// skipped). settle::InputError naming `source`, the line and the column on any problem.
Timeseries parse_timeseries_csv(std::string_view text, const std::string& source);

/// Reads and parses a CSV file; settle::InputError naming the file when it cannot be read.
Timeseries read_timeseries_csv(const std::filesystem::path& path);

/// The first sample time that belongs to the free motion of a body released at release_time_si:
/// the release time less a relative 1e-9, so that a sample taken at the release (its time summed
/// from steps of dt) counts.
inline double released_from(double release_time_si) { return release_time_si * (1.0 - 1e-9); }

/// The motion of a settling particle, sample by sample. SI units, inertial frame (z up in
/// settle's cases) unless named body. body_to_inertial is C_b^n (v_n = C_b^n v_b), built from
/// the set-1 Euler angles (psi, theta, gamma) of the file (attitude/attitude.hpp).
struct SettlingSeries {
  std::vector<double> t_si;
  std::vector<Eigen::Vector3d> position_si;
  std::vector<Eigen::Vector3d> velocity_si;
  std::vector<Eigen::Vector3d> angular_velocity_n_si;  ///< rad/s, inertial frame
  std::vector<Eigen::Vector3d> angular_velocity_b_si;  ///< rad/s, body frame
  std::vector<Eigen::Matrix3d> body_to_inertial;
  std::vector<Eigen::Vector3d> force_si;   ///< hydrodynamic force, N
  std::vector<Eigen::Vector3d> torque_si;  ///< hydrodynamic torque about the centre of mass, N m
  /// Particle-wall contact force, N (timeseries.csv's Fcx, Fcy, Fcz): one per sample, or none when
  /// the source has no such columns (a series written before they existed).
  std::vector<Eigen::Vector3d> contact_force_si;

  [[nodiscard]] std::size_t size() const { return t_si.size(); }
  /// The samples at t >= released_from(t0_si): the free motion of a body released at t0
  /// (particle.release_time).
  [[nodiscard]] SettlingSeries since(double t0_si) const;
  /// Appends one sample (tests build synthetic series with this).
  void add(double t, const Eigen::Vector3d& position, const Eigen::Vector3d& velocity,
           const Eigen::Vector3d& angular_velocity_n, const Eigen::Vector3d& angular_velocity_b,
           const Eigen::Matrix3d& body_to_inertial_matrix, const Eigen::Vector3d& force = Eigen::Vector3d::Zero(),
           const Eigen::Vector3d& torque = Eigen::Vector3d::Zero());
};

/// The columns a SettlingSeries is built from.
const std::vector<std::string>& settling_series_columns();

/// The settling series of a timeseries.csv. settle::InputError naming the source and the column
/// when a column is missing, and the line when a value is not finite or t does not increase;
/// at least two rows are required.
SettlingSeries settling_series(const Timeseries& table);

/// The settling series of the samples settle run took (coupling::RunResult::samples), the same
/// numbers that timeseries.csv holds. std::invalid_argument when t does not increase.
SettlingSeries settling_series(const std::vector<coupling::Sample>& samples);

}  // namespace settle::analysis
