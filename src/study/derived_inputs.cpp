#include "study/derived_inputs.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include <fmt/core.h>

#include "attitude/euler.hpp"
#include "body/shape_factory.hpp"
#include "common/error.hpp"
#include "io/case.hpp"
#include "io/window_advice.hpp"

namespace settle::study {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

double equivalent_diameter_m(const io::CaseValues& values, const std::filesystem::path& base_directory) {
  body::ShapeFactoryOptions options;
  options.base_directory = base_directory;
  return body::make_shape(io::shape_spec(values), options)->equivalent_diameter();
}

double kinematic_viscosity_m2_s(const io::CaseValues& values) {
  return values.real("fluid.dynamic_viscosity") / values.real("fluid.density");
}

Eigen::Vector3d vector3(const io::CaseValues& values, std::string_view key) {
  const std::vector<double>& v = values.reals(key);
  return {v[0], v[1], v[2]};
}

void set_vector3(io::CaseValues& values, std::string_view key, const Eigen::Vector3d& v) {
  values.set(key, io::Value(std::vector<double>{v[0], v[1], v[2]}), "study");
}

// The direction of the relative flow's source: the base's towing direction, else along gravity.
Eigen::Vector3d towing_direction(const io::CaseValues& values) {
  if (values.has("particle.towing_velocity")) {
    const Eigen::Vector3d v = vector3(values, "particle.towing_velocity");
    if (v.norm() > 0.0) return v.normalized();
  }
  const Eigen::Vector3d g = vector3(values, "fluid.gravity");
  return g.norm() > 0.0 ? Eigen::Vector3d(g.normalized()) : Eigen::Vector3d(0.0, 0.0, -1.0);
}

// Re = U d_eq / nu of a towed body (its towing speed) or a fixed body in an inflow (the inflow
// speed); a free body's Reynolds number is an outcome of the run, not an input.
void set_reynolds(io::CaseValues& values, double reynolds, const std::filesystem::path& base_directory) {
  if (!(reynolds > 0.0)) throw InputError(fmt::format("reynolds: {} is not > 0", reynolds));
  const double speed_m_s = reynolds * kinematic_viscosity_m2_s(values) / equivalent_diameter_m(values, base_directory);
  const std::string& motion = values.string("particle.motion");
  if (motion == "towed") {
    set_vector3(values, "particle.towing_velocity", speed_m_s * towing_direction(values));
  } else if (motion == "fixed" && values.has("domain.inflow_velocity")) {
    const Eigen::Vector3d inflow = vector3(values, "domain.inflow_velocity");
    if (inflow.norm() <= 0.0) throw InputError("reynolds: the base case's domain.inflow_velocity is zero");
    set_vector3(values, "domain.inflow_velocity", speed_m_s * inflow.normalized());
  } else {
    throw InputError(fmt::format(
        "reynolds: the base case's body is {} without an inflow; reynolds sets the towing speed of a towed body "
        "(particle.motion = \"towed\") or the inflow speed of a fixed one; for a free body vary galileo",
        motion));
  }
}

// Ga = sqrt(|rho_p / rho_f - 1| g d_eq^3) / nu, solved for the dynamic viscosity.
void set_galileo(io::CaseValues& values, double galileo, const std::filesystem::path& base_directory) {
  if (!(galileo > 0.0)) throw InputError(fmt::format("galileo: {} is not > 0", galileo));
  if (values.string("particle.motion") != "free")
    throw InputError(
        "galileo: sets the viscosity of a free body's case; the base case's body is not free "
        "(particle.motion); for a towed body vary reynolds");
  const double rho_f = values.real("fluid.density");
  const double excess = std::abs(io::particle_density_si(values) / rho_f - 1.0);
  const double g = vector3(values, "fluid.gravity").norm();
  if (excess <= 0.0 || g <= 0.0)
    throw InputError(
        "galileo: the base case has no net weight (particle.density equals fluid.density, or no "
        "gravity), so the Galileo number is zero");
  const double d = equivalent_diameter_m(values, base_directory);
  values.set("fluid.dynamic_viscosity", io::Value(rho_f * std::sqrt(excess * g * d * d * d) / galileo), "study");
}

// The body turned by the incidence about the inertial y axis, after its base attitude: with the
// flow along z and a spheroid at euler = [0, 0, 0], the angle between its axis and the flow.
void set_incidence(io::CaseValues& values, double incidence_deg) {
  const Eigen::Matrix3d base = attitude::set1_body_to_inertial(vector3(values, "particle.euler"));
  const Eigen::Matrix3d turned = Eigen::AngleAxisd(incidence_deg * kDegree, Eigen::Vector3d::UnitY()) * base;
  set_vector3(values, "particle.euler", attitude::set1_angles_from_matrix(turned));
}

// The run's length as diameters of travel of a towed body (or of inflow past a fixed one):
// run.end_time = N d_eq / U, so that a map over Re costs the same travel, not the same seconds.
void set_travel(io::CaseValues& values, double diameters, const std::filesystem::path& base_directory) {
  if (!(diameters > 0.0)) throw InputError(fmt::format("travel_diameters: {} is not > 0", diameters));
  const std::string& motion = values.string("particle.motion");
  const char* key = relative_flow_key(values);
  if (key == nullptr || !values.has(key) || vector3(values, key).norm() <= 0.0)
    throw InputError(
        fmt::format("travel_diameters: the base case's body is {} without a towing or inflow speed; "
                    "a free body's travel is an outcome (set run.end_time)",
                    motion));
  values.set("run.end_time",
             io::Value(diameters * equivalent_diameter_m(values, base_directory) / vector3(values, key).norm()),
             "study");
}

// +1 or -1: the body's direction of travel relative to the fluid (io::travel_direction) along z,
// the axis along which settle's windows are long and follow their body, as the window inputs need.
double travel_sign_along_z(const io::CaseValues& values, std::string_view name) {
  const body::MotionKind motion = io::motion_kind(values.string("particle.motion"));
  const Eigen::Vector3d inflow =
      values.has("domain.inflow_velocity") ? vector3(values, "domain.inflow_velocity") : Eigen::Vector3d::Zero();
  if (motion == body::MotionKind::fixed && inflow.norm() <= 0.0)
    throw InputError(fmt::format("{}: the base case's body is fixed without an inflow, so it has no front", name));
  const Eigen::Vector3d travel =
      io::travel_direction(motion, towing_direction(values), inflow, vector3(values, "fluid.gravity"),
                           io::particle_density_si(values) < values.real("fluid.density"));
  if (std::abs(travel.z()) < 1.0 - 1e-12)
    throw InputError(
        fmt::format("{}: the body travels along ({:.3g}, {:.3g}, {:.3g}), not along the z axis, the "
                    "axis the window inputs measure ahead and behind along",
                    name, travel.x(), travel.y(), travel.z()));
  return travel.z() > 0.0 ? 1.0 : -1.0;
}

Eigen::Vector3d body_position(const io::CaseValues& values) {
  return values.has("particle.position") ? vector3(values, "particle.position")
                                         : Eigen::Vector3d(0.5 * vector3(values, "domain.size"));
}

// The window's sides at width_d d_eq each way across (x and y), the body kept at the same offset
// from the axis (a deliberate sub-cell seed survives).
void set_window_width(io::CaseValues& values, double width_d, const std::filesystem::path& base_directory) {
  constexpr std::string_view name = "domain_width_diameters";
  if (!(width_d > 0.0)) throw InputError(fmt::format("{}: {} is not > 0", name, width_d));
  travel_sign_along_z(values, name);
  const double width_m = width_d * equivalent_diameter_m(values, base_directory);
  Eigen::Vector3d size = vector3(values, "domain.size");
  Eigen::Vector3d position = body_position(values);
  for (int a = 0; a < 2; ++a) {
    position[a] += 0.5 * (width_m - size[a]);
    size[a] = width_m;
  }
  set_vector3(values, "domain.size", size);
  set_vector3(values, "particle.position", position);
}

// The fluid ahead of the body's centre (ahead = true) or the wake behind it, in d_eq along z, the
// other end's distance kept.
void set_window_end(io::CaseValues& values, bool ahead, double length_d, const std::filesystem::path& base_directory) {
  const std::string_view name = ahead ? "domain_ahead_diameters" : "domain_behind_diameters";
  if (!(length_d > 0.0)) throw InputError(fmt::format("{}: {} is not > 0", name, length_d));
  const bool front_at_top = travel_sign_along_z(values, name) > 0.0;
  Eigen::Vector3d size = vector3(values, "domain.size");
  Eigen::Vector3d position = body_position(values);
  const double to_top_m = size.z() - position.z();
  const double length_m = length_d * equivalent_diameter_m(values, base_directory);
  const bool sets_top = ahead == front_at_top;
  if (sets_top) {
    size.z() = position.z() + length_m;
  } else {
    position.z() = length_m;
    size.z() = length_m + to_top_m;
  }
  set_vector3(values, "domain.size", size);
  set_vector3(values, "particle.position", position);
}

}  // namespace

const char* relative_flow_key(const io::CaseValues& values) {
  const std::string& motion = values.string("particle.motion");
  if (motion == "towed") return "particle.towing_velocity";
  if (motion == "fixed" && values.has("domain.inflow_velocity")) return "domain.inflow_velocity";
  return nullptr;
}

bool is_derived_input(std::string_view name) {
  return name == "reynolds" || name == "incidence_deg" || name == "galileo" || name == "travel_diameters" ||
         is_window_input(name);
}

bool is_window_input(std::string_view name) {
  return name == "domain_width_diameters" || name == "domain_ahead_diameters" || name == "domain_behind_diameters";
}

std::string_view derived_input_names() {
  return "reynolds, incidence_deg, galileo, travel_diameters, domain_width_diameters, domain_ahead_diameters, "
         "domain_behind_diameters";
}

void set_derived_input(io::CaseValues& values, std::string_view name, double value,
                       const std::filesystem::path& base_directory) {
  if (name == "reynolds") return set_reynolds(values, value, base_directory);
  if (name == "galileo") return set_galileo(values, value, base_directory);
  if (name == "incidence_deg") return set_incidence(values, value);
  if (name == "travel_diameters") return set_travel(values, value, base_directory);
  if (name == "domain_width_diameters") return set_window_width(values, value, base_directory);
  if (name == "domain_ahead_diameters") return set_window_end(values, true, value, base_directory);
  if (name == "domain_behind_diameters") return set_window_end(values, false, value, base_directory);
  throw InputError(fmt::format("{}: not a derived input ({})", name, derived_input_names()));
}

std::vector<Eigen::Quaterniond> uniform_rotations(int count, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  // 53 random bits to a double in [0, 1): unlike std::uniform_real_distribution, the same on every
  // standard library.
  const auto uniform = [&engine] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
  std::vector<Eigen::Quaterniond> rotations;
  rotations.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double u1 = uniform(), u2 = uniform(), u3 = uniform();
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    const double t2 = 2.0 * std::numbers::pi * u2, t3 = 2.0 * std::numbers::pi * u3;
    rotations.emplace_back(b * std::cos(t3), a * std::sin(t2), a * std::cos(t2), b * std::sin(t3));
  }
  return rotations;
}

void set_attitude(io::CaseValues& values, const Eigen::Quaterniond& body_to_inertial) {
  set_vector3(values, "particle.euler", attitude::set1_angles_from_matrix(body_to_inertial.toRotationMatrix()));
}

}  // namespace settle::study
