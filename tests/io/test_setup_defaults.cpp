// One default per key (docs/architecture.md, "Case file"): the case schema declares each key's
// default once, and the set-up of the minimal case (only the keys without a default given;
// tests/support/default_setup.hpp) holds exactly those defaults. The check walks the schema's own
// list of keys, so a key added to the schema fails here until io::simulation_setup carries it into
// the set-up (or the key is listed below as read elsewhere).
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/error.hpp"
#include "coupling/case_plan.hpp"
#include "coupling/immersed_body.hpp"
#include "io/case.hpp"
#include "io/case_schema.hpp"
#include "support/default_setup.hpp"

namespace settle::io {
namespace test_setup_defaults {

using coupling::SimulationSetup;
// A key's value as the set-up holds it, in the schema's form; nullopt: the set-up holds "not given".
using Reader = std::function<std::optional<Value>(const SimulationSetup&)>;

Value vec(const Eigen::Vector3d& v) { return Value(std::vector<double>{v.x(), v.y(), v.z()}); }
Value text(std::string s) { return Value(std::move(s)); }
Value face(const std::optional<lbm::Face>& f) { return text(f ? lbm::to_string(*f) : "none"); }

// Every key that io::simulation_setup carries into the set-up.
std::map<std::string, Reader> setup_readers() {
  return {
      {"fluid.density", [](const SimulationSetup& s) { return Value(s.fluid_density_si); }},
      {"fluid.dynamic_viscosity", [](const SimulationSetup& s) { return Value(s.dynamic_viscosity_si); }},
      {"fluid.gravity", [](const SimulationSetup& s) { return vec(s.gravity_si); }},
      {"fluid.body_force", [](const SimulationSetup& s) { return vec(s.body_force_si); }},
      {"particle.density", [](const SimulationSetup& s) { return Value(s.particle_density_si); }},
      {"particle.motion",
       [](const SimulationSetup& s) {
         return text(s.motion == body::MotionKind::free    ? "free"
                     : s.motion == body::MotionKind::towed ? "towed"
                                                           : "fixed");
       }},
      {"particle.towing_velocity",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (s.motion != body::MotionKind::towed) return std::nullopt;
         return vec(s.initial.velocity_si);
       }},
      // Absent: the domain's centre.
      {"particle.position",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (s.initial.position_si == 0.5 * s.domain_size_si) return std::nullopt;
         return vec(s.initial.position_si);
       }},
      {"particle.euler", [](const SimulationSetup& s) { return vec(s.initial.attitude.set1_angles()); }},
      {"particle.velocity", [](const SimulationSetup& s) { return vec(s.initial.velocity_si); }},
      {"particle.angular_velocity", [](const SimulationSetup& s) { return vec(s.initial.angular_velocity_b_si); }},
      {"particle.release_time", [](const SimulationSetup& s) { return Value(s.release_time_si); }},
      {"particle.hold_ramp_time", [](const SimulationSetup& s) { return Value(s.hold_ramp_time_si); }},
      {"particle.lock_rotation", [](const SimulationSetup& s) { return Value(s.rotation_locked); }},
      {"domain.size", [](const SimulationSetup& s) { return vec(s.domain_size_si); }},
      {"domain.walls.x", [](const SimulationSetup& s) { return text(lbm::to_string(s.boundaries[0])); }},
      {"domain.walls.y", [](const SimulationSetup& s) { return text(lbm::to_string(s.boundaries[1])); }},
      {"domain.walls.z", [](const SimulationSetup& s) { return text(lbm::to_string(s.boundaries[2])); }},
      {"domain.inflow", [](const SimulationSetup& s) { return face(s.inflow); }},
      {"domain.inflow_velocity",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (!s.inflow) return std::nullopt;
         return vec(s.inflow_velocity_si);
       }},
      {"domain.outflow", [](const SimulationSetup& s) { return face(s.outflow); }},
      {"domain.follow_particle", [](const SimulationSetup& s) { return Value(s.follow_particle); }},
      {"numerics.cells_per_diameter", [](const SimulationSetup& s) { return Value(s.cells_per_diameter); }},
      {"numerics.lattice", [](const SimulationSetup& s) { return text(lbm::to_string(s.lattice)); }},
      {"numerics.collision", [](const SimulationSetup& s) { return text(lbm::to_string(s.collision)); }},
      {"numerics.trt_magic", [](const SimulationSetup& s) { return Value(s.trt_magic); }},
      {"numerics.subgrid_model", [](const SimulationSetup& s) { return text(lbm::to_string(s.subgrid_model)); }},
      {"numerics.smagorinsky_constant", [](const SimulationSetup& s) { return Value(s.smagorinsky_constant); }},
      {"numerics.precision", [](const SimulationSetup& s) { return text(lbm::to_string(s.precision)); }},
      {"numerics.coupling", [](const SimulationSetup& s) { return text(coupling::to_string(s.coupling)); }},
      {"numerics.wall_rule", [](const SimulationSetup& s) { return text(lbm::to_string(s.wall_rule)); }},
      {"numerics.covered_cell_torque", [](const SimulationSetup& s) { return Value(s.covered_cell_torque); }},
      {"numerics.lattice_steps_per_body_step",
       [](const SimulationSetup& s) { return Value(std::int64_t{s.lattice_steps_per_body_step}); }},
      {"numerics.delta_kernel", [](const SimulationSetup& s) { return text(std::string(ibm::to_string(s.kernel))); }},
      {"numerics.forcing_iterations",
       [](const SimulationSetup& s) { return Value(std::int64_t{s.forcing_iterations}); }},
      // Absent: the calibration of the marker layout.
      {"numerics.marker_retraction",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (s.marker_retraction_cells == coupling::calibrated_marker_retraction_cells(s.interior_markers))
           return std::nullopt;
         return Value(s.marker_retraction_cells);
       }},
      {"numerics.interior_markers", [](const SimulationSetup& s) { return Value(s.interior_markers); }},
      {"numerics.max_lattice_velocity", [](const SimulationSetup& s) { return Value(s.max_lattice_velocity); }},
      {"numerics.max_tau", [](const SimulationSetup& s) { return Value(s.max_tau); }},
      {"numerics.tau",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (!s.tau) return std::nullopt;
         return Value(*s.tau);
       }},
      {"contact.enabled", [](const SimulationSetup& s) { return Value(s.wall_contact); }},
      {"contact.restitution", [](const SimulationSetup& s) { return Value(s.contact_restitution); }},
      {"contact.wet_stokes_scale", [](const SimulationSetup& s) { return Value(s.contact_wet_stokes_scale); }},
      {"contact.collision_steps", [](const SimulationSetup& s) { return Value(s.contact_collision_steps); }},
      {"contact.distance_cells",
       [](const SimulationSetup& s) -> std::optional<Value> {
         if (!s.contact_distance_cells) return std::nullopt;
         return Value(*s.contact_distance_cells);
       }},
      {"run.end_time", [](const SimulationSetup& s) { return Value(s.end_time_si); }},
      {"run.output_interval", [](const SimulationSetup& s) { return Value(s.output_interval_si); }},
  };
}

// Keys the set-up does not hold: resolved before it (the fluid preset into fluid.density and
// fluid.dynamic_viscosity, io::apply_fluid_preset), read into the shape (io::shape_spec), or read by
// `settle run` itself (app/cmd_run.cpp: outputs, the terminal stop, checkpoints, the reference).
const std::set<std::string> kReadElsewhere{"fluid.preset",
                                           "fluid.temperature",
                                           "fluid.glycerol_mass_fraction",
                                           "particle.shape",
                                           "particle.diameter",
                                           "particle.aspect_ratio",
                                           "particle.semi_axes",
                                           "particle.exponents",
                                           "particle.length",
                                           "particle.size",
                                           "particle.file",
                                           "particle.scale",
                                           "run.vtk_interval",
                                           "run.stop_at_terminal",
                                           "run.checkpoint_interval",
                                           "run.checkpoint_wall_interval",
                                           "run.reference",
                                           "run.vtk_compression"};

TEST(SetupDefaults, EveryKeyOfTheSchemaIsReadIntoTheSetupOrListedAsReadElsewhere) {
  const auto readers = setup_readers();
  std::set<std::string> declared;
  for (const KeySpec& spec : case_schema().keys()) {
    declared.insert(spec.path);
    EXPECT_NE(readers.count(spec.path) + kReadElsewhere.count(spec.path), 0U)
        << spec.path << ": a new key; carry it into coupling::SimulationSetup (io::simulation_setup) and add it "
        << "here, or list it as read elsewhere";
    EXPECT_LE(readers.count(spec.path) + kReadElsewhere.count(spec.path), 1U) << spec.path;
  }
  for (const auto& [path, reader] : readers) EXPECT_TRUE(declared.count(path)) << path << ": not in the schema";
  for (const std::string& path : kReadElsewhere) EXPECT_TRUE(declared.count(path)) << path << ": not in the schema";
}

TEST(SetupDefaults, TheMinimalCasesSetupHoldsEachKeysSchemaDefault) {
  const SimulationSetup s = test::default_setup();
  const CaseValues minimal = load_case_text(test::kMinimalCase, "the minimal case");
  const auto readers = setup_readers();
  int compared = 0;
  for (const KeySpec& spec : case_schema().keys()) {
    const auto reader = readers.find(spec.path);
    if (reader == readers.end()) continue;
    const std::optional<Value> held = reader->second(s);
    if (spec.default_value) {
      ASSERT_TRUE(held.has_value()) << spec.path;
      // Exact: the default's double reaches the set-up unchanged (no arithmetic on the way).
      EXPECT_TRUE(*held == *spec.default_value) << spec.path << ": the set-up holds " << to_toml(*held)
                                                << ", the schema's default is " << to_toml(*spec.default_value);
      ++compared;
    } else if (!minimal.given(spec.path)) {
      EXPECT_FALSE(held.has_value()) << spec.path << ": not given, yet the set-up holds " << to_toml(*held);
    }
  }
  // 40 of the set-up's keys carried a default when this was written; far fewer compared would
  // mean the walk skipped them (a key made required lowers the count by one).
  EXPECT_GE(compared, 30);
}

// A set-up built without io::simulation_setup has no defaults to fall back on: plan_case names the
// member left unassigned instead of running on a value of its own.
TEST(SetupDefaults, AMemberLeftUnassignedIsRefusedByThePlan) {
  const SimulationSetup minimal = test::default_setup();
  EXPECT_NO_THROW((void)coupling::plan_case(minimal));
  SimulationSetup bare;
  bare.shape = minimal.shape;
  EXPECT_THROW((void)coupling::plan_case(bare), std::invalid_argument);
  SimulationSetup forgotten = minimal;
  forgotten.max_tau = coupling::kUnassigned;
  try {
    (void)coupling::plan_case(forgotten);
    ADD_FAILURE() << "an unassigned max_tau was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_tau"), std::string::npos) << e.what();
  }
  forgotten = minimal;
  forgotten.forcing_iterations = coupling::kUnassignedCount;
  EXPECT_THROW((void)coupling::plan_case(forgotten), std::invalid_argument);
}

// The ranges of single keys are checked once, by the schema, when a case is read; the plan
// (coupling/case_plan.cpp) no longer repeats them.
TEST(SetupDefaults, TheSchemaRefusesContactValuesOutOfRange) {
  const std::string minimal(test::kMinimalCase);
  for (const char* contact : {"restitution = 0.0", "restitution = 1.5", "collision_steps = 0.5",
                              "wet_stokes_scale = -1.0", "distance_cells = 1.0e4"}) {
    const std::string text = minimal + "\n[contact]\n" + contact + "\n";
    // The reader names a key by its table and name ("[contact] restitution").
    const std::string key = std::string("[contact] ") + std::string(contact).substr(0, std::string(contact).find(' '));
    try {
      (void)load_case_text(text, "case");
      ADD_FAILURE() << contact << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace test_setup_defaults
}  // namespace settle::io
