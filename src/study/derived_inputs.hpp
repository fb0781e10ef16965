#pragma once
// The inputs researchers think in, turned into case keys (docs/studies.md, "Derived inputs"):
// the Reynolds number, the incidence and the length of run in diameters of travel of a towed body,
// the Galileo number of a free one, the window's width and the fluid ahead of and behind the body
// in equivalent diameters, and attitudes drawn uniformly on the rotation group for
// orientation ensembles.
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "io/schema.hpp"

namespace settle::study {

/// True for the names a study may vary besides the case keys: reynolds, incidence_deg, galileo,
/// travel_diameters and the window inputs (is_window_input).
bool is_derived_input(std::string_view name);

/// True for the inputs that set domain.size and particle.position: domain_width_diameters (x and y
/// extents), domain_ahead_diameters and domain_behind_diameters (from the body's centre to the
/// window's end ahead of it and behind it along z, its direction of travel).
bool is_window_input(std::string_view name);

/// The names of is_derived_input, for messages.
std::string_view derived_input_names();

/// Sets one derived input (is_derived_input) on checked case values. `base_directory` is where a
/// relative mesh path starts (the equivalent diameter needs the shape). settle::InputError names
/// `name` when the case cannot take it (reynolds of a free body, galileo of a towed one).
void set_derived_input(io::CaseValues& values, std::string_view name, double value,
                       const std::filesystem::path& base_directory);

/// The case key that sets the relative flow: particle.towing_velocity for a towed body,
/// domain.inflow_velocity for a fixed body in an inflow; nullptr otherwise (a free body's flow is an
/// outcome of its run).
const char* relative_flow_key(const io::CaseValues& values);

/// `count` rotations uniform on SO(3) (Shoemake 1992, "Uniform random rotations", Graphics Gems
/// III, 124-132: a unit quaternion from three uniform numbers), from std::mt19937_64 seeded with
/// `seed`, whose output the C++ standard fixes: the same seed gives the same rotations everywhere.
std::vector<Eigen::Quaterniond> uniform_rotations(int count, std::uint64_t seed);

/// particle.euler (set-1 angles, body to inertial) of the attitude `body_to_inertial`.
void set_attitude(io::CaseValues& values, const Eigen::Quaterniond& body_to_inertial);

}  // namespace settle::study
