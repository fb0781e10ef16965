// The schema machinery: defaults, type and range checks, unknown keys with suggestions,
// overrides, and the resolved TOML reading back to the same values.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "common/error.hpp"
#include "io/case.hpp"
#include "io/schema.hpp"

namespace settle::io {
namespace test_schema {

Schema test_schema() {
  std::vector<KeySpec> keys;
  keys.push_back(
      {"fluid.density", Kind::Real, Value(998.2), "kg/m^3", "fluid density", {0.0, INFINITY, false, true}, {}, 0});
  keys.push_back(
      {"fluid.gravity", Kind::RealArray, Value(std::vector<double>{0, 0, -9.81}), "m/s^2", "gravity", {}, {}, 3});
  keys.push_back(
      {"particle.shape", Kind::String, Value(std::string("sphere")), "", "shape", {}, {"sphere", "spheroid"}, 0});
  keys.push_back({"particle.diameter", Kind::Real, std::nullopt, "m", "diameter", {0.0, INFINITY, false, true}, {}, 0});
  keys.push_back(
      {"domain.walls.x", Kind::String, Value(std::string("no-slip")), "", "x walls", {}, {"no-slip", "periodic"}, 0});
  keys.push_back({"run.steps", Kind::Integer, Value(std::int64_t{10}), "", "steps", {1, 1e6, true, true}, {}, 0});
  keys.push_back({"run.stop", Kind::Boolean, Value(false), "", "stop early", {}, {}, 0});
  return Schema(std::move(keys));
}

std::string error_of(const std::string& toml) {
  try {
    parse_case(test_schema(), toml, "case.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Schema, DefaultsApplyAndGivenValuesOverride) {
  const Schema schema = test_schema();
  const CaseValues v = parse_case(schema, "[fluid]\ndensity = 1000\n[domain]\nwalls = { x = \"periodic\" }\n", "c");
  EXPECT_DOUBLE_EQ(v.real("fluid.density"), 1000.0);  // integer accepted for a real
  EXPECT_TRUE(v.given("fluid.density"));
  EXPECT_FALSE(v.given("fluid.gravity"));
  EXPECT_EQ(v.reals("fluid.gravity"), (std::vector<double>{0, 0, -9.81}));
  EXPECT_EQ(v.string("domain.walls.x"), "periodic");
  EXPECT_FALSE(v.has("particle.diameter"));
  EXPECT_THROW(v.real("particle.diameter"), InputError);  // required by a caller, not given
}

TEST(Schema, ErrorsNameFileKeyValueAndWhatIsAllowed) {
  std::string e = error_of("[fluid]\ndensity = -3.0\n");
  EXPECT_TRUE(contains(e, "case.toml")) << e;
  EXPECT_TRUE(contains(e, "[fluid] density")) << e;
  EXPECT_TRUE(contains(e, "-3.0")) << e;
  EXPECT_TRUE(contains(e, "> 0")) << e;

  e = error_of("[fluid]\ndensity = \"water\"\n");
  EXPECT_TRUE(contains(e, "expected a number")) << e;
  e = error_of("[fluid]\ndensity = nan\n");
  EXPECT_TRUE(contains(e, "finite")) << e;
  e = error_of("[fluid]\ngravity = [0.0, -9.81]\n");
  EXPECT_TRUE(contains(e, "3 numbers")) << e;
  e = error_of("[fluid]\ngravity = [0.0, inf, 1.0]\n");
  EXPECT_TRUE(contains(e, "finite")) << e;
  e = error_of("[particle]\nshape = \"cube\"\n");
  EXPECT_TRUE(contains(e, "\"sphere\", \"spheroid\"")) << e;
  e = error_of("[run]\nsteps = 0\n");
  EXPECT_TRUE(contains(e, "in [1, 1000000]")) << e;  // integer bounds written as integers
  e = error_of("[run]\nstop = 1\n");
  EXPECT_TRUE(contains(e, "boolean")) << e;
  e = error_of("[fluid\ndensity = 1\n");
  EXPECT_TRUE(contains(e, "case.toml:1")) << e;
  EXPECT_TRUE(contains(e, "syntax")) << e;
}

TEST(Schema, UnknownKeysAreErrorsWithASuggestion) {
  std::string e = error_of("[fluid]\ndensty = 1000.0\n");
  EXPECT_TRUE(contains(e, "unknown key [fluid] densty")) << e;
  EXPECT_TRUE(contains(e, "did you mean [fluid] density?")) << e;
  e = error_of("[particle]\ndensity = 1000.0\n");  // right leaf, wrong table
  EXPECT_TRUE(contains(e, "did you mean [fluid] density?")) << e;
  e = error_of("[something]\ncompletely_different = 1\n");
  EXPECT_TRUE(contains(e, "unknown table [something]")) << e;  // the table is reported before its keys
  EXPECT_FALSE(contains(e, "did you mean")) << e;
}

TEST(Schema, UnknownTablesAreErrorsEvenWhenEmpty) {
  std::string e = error_of("[flud]\n");
  EXPECT_TRUE(contains(e, "case.toml: unknown table [flud]")) << e;
  EXPECT_TRUE(contains(e, "did you mean [fluid]?")) << e;
  e = error_of("[domain.wals]\n");
  EXPECT_TRUE(contains(e, "did you mean [domain.walls]?")) << e;
  e = error_of("[completely_unrelated]\n");
  EXPECT_TRUE(contains(e, "unknown table")) << e;
  EXPECT_FALSE(contains(e, "did you mean")) << e;
  EXPECT_EQ(error_of("[fluid]\n[domain.walls]\n"), "");  // known tables may be empty
}

TEST(Schema, AScalarWhereATableBelongsNamesTheTablesKeys) {
  const std::string e = error_of("[domain]\nwalls = \"periodic\"\n");
  EXPECT_TRUE(contains(e, "[domain] walls")) << e;
  EXPECT_TRUE(contains(e, "expected a table with the keys x")) << e;
}

TEST(Schema, ArraysWithoutARangeSayFinite) {
  const std::string e = error_of("[fluid]\ngravity = [0.0, nan, 1.0]\n");
  EXPECT_TRUE(contains(e, "must be an array of finite numbers")) << e;
}

std::string override_error(const std::string& assignment) {
  const Schema schema = test_schema();
  CaseValues v = parse_case(schema, "", "c");
  try {
    apply_override(v, assignment);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Schema, OverrideMistakesAreExplained) {
  EXPECT_TRUE(contains(override_error("fluid.density"), "expected key=value"));
  EXPECT_TRUE(contains(override_error(" =3"), "expected key=value"));
  EXPECT_TRUE(contains(override_error("fluid.density=  "), "no value after '='"));
  std::string e = override_error("particle.shape=spheroid");
  EXPECT_TRUE(contains(e, "double quotes")) << e;
  EXPECT_TRUE(contains(e, "--set 'particle.shape=\"spheroid\"'")) << e;
  e = override_error("fluid.density=1000 x");
  EXPECT_TRUE(contains(e, "not valid TOML")) << e;
  EXPECT_TRUE(contains(e, "expected a number")) << e;
  EXPECT_TRUE(contains(override_error("fluid.density=1000\nrun.steps=3"), "a single value"));
  e = override_error("domain.walls=\"periodic\"");
  EXPECT_TRUE(contains(e, "domain.walls is a table")) << e;
  EXPECT_TRUE(contains(e, "--set domain.walls.x=")) << e;
  e = override_error("fluid.densty=1");
  EXPECT_TRUE(contains(e, "unknown key fluid.densty (did you mean fluid.density?)")) << e;
  EXPECT_TRUE(contains(override_error("run.steps=2.5"), "expected an integer for run.steps"));
  EXPECT_EQ(override_error("particle.shape=\"spheroid\""), "");
}

TEST(Schema, OverridesAreCheckedLikeTheFile) {
  const Schema schema = test_schema();
  CaseValues v = parse_case(schema, "", "c");
  apply_override(v, "fluid.density=1050");
  EXPECT_DOUBLE_EQ(v.real("fluid.density"), 1050.0);
  apply_override(v, "fluid.gravity=[0, 0, -1]");
  EXPECT_EQ(v.reals("fluid.gravity")[2], -1.0);
  EXPECT_THROW(apply_override(v, "fluid.density=-1"), InputError);
  EXPECT_THROW(apply_override(v, "fluid.densty=1"), InputError);
  EXPECT_THROW(apply_override(v, "no_equals_sign"), InputError);
}

TEST(Schema, ResolvedTomlReadsBackToTheSameValues) {
  const Schema schema = test_schema();
  const CaseValues v = parse_case(schema, "[fluid]\ndensity = 1000.1234567890123\n[particle]\ndiameter = 1e-3\n", "c");
  const std::string resolved = write_resolved_toml(v);
  const CaseValues back = parse_case(schema, resolved, "resolved");
  for (const KeySpec& k : schema.keys()) {
    ASSERT_EQ(v.has(k.path), back.has(k.path)) << k.path;
    if (v.has(k.path)) {
      EXPECT_EQ(v.value(k.path), back.value(k.path)) << k.path << "\n" << resolved;
    }
  }
}

// The rewritten text must be what write_resolved_toml writes for the changed values, byte for
// byte (the other keys' "(default)" marks included), and keep what follows the tables.
TEST(Schema, RewritingOneResolvedValueChangesOnlyItsLine) {
  const Schema schema = test_schema();
  const CaseValues v = parse_case(schema, "[fluid]\ndensity = 1000.5\n[particle]\ndiameter = 1e-3\n", "c");
  const std::string trailer = "\n# [derived] not read back\n# steps = 3\n";
  for (const char* assignment : {"run.steps=42", "domain.walls.x=\"periodic\"", "fluid.density=1001"}) {
    CaseValues changed = v;
    apply_override(changed, assignment);
    const std::string path = std::string(assignment).substr(0, std::string(assignment).find('='));
    EXPECT_EQ(rewrite_resolved_value(write_resolved_toml(v) + trailer, changed, path),
              write_resolved_toml(changed) + trailer)
        << assignment;
  }
}

TEST(Schema, MarkdownTableListsEveryKey) {
  const Schema schema = test_schema();
  const std::string md = schema_markdown(schema);
  for (const KeySpec& k : schema.keys()) EXPECT_TRUE(contains(md, k.doc)) << k.path;
}

}  // namespace test_schema
}  // namespace settle::io

#include "io/case_schema.hpp"
#include "lbm/config.hpp"

namespace settle::io {
namespace test_schema {

TEST(CaseSchema, EveryDefaultSatisfiesItsOwnDeclarationAndTheDesignKeysExist) {
  // The Schema constructor rejects a default outside its range; building it is the check.
  const Schema& schema = case_schema();
  // The key names are a contract (docs/architecture.md, "Contracts"): none may go missing.
  for (const char* key : {"fluid.density",
                          "fluid.dynamic_viscosity",
                          "fluid.gravity",
                          "fluid.body_force",
                          "particle.shape",
                          "particle.diameter",
                          "particle.aspect_ratio",
                          "particle.semi_axes",
                          "particle.exponents",
                          "particle.length",
                          "particle.size",
                          "particle.file",
                          "particle.scale",
                          "particle.density",
                          "particle.motion",
                          "particle.towing_velocity",
                          "particle.position",
                          "particle.euler",
                          "particle.velocity",
                          "particle.angular_velocity",
                          "domain.size",
                          "domain.walls.x",
                          "domain.walls.y",
                          "domain.walls.z",
                          "domain.follow_particle",
                          "numerics.cells_per_diameter",
                          "numerics.collision",
                          "numerics.precision",
                          "run.end_time",
                          "run.output_interval",
                          "run.vtk_interval",
                          "run.stop_at_terminal",
                          "run.checkpoint_interval"})
    EXPECT_NE(schema.find(key), nullptr) << key;
}

// The schema lists the allowed names and the fluid solver parses them: a name offered by one and
// refused by the other would pass the case check and fail only when the run starts.
TEST(CaseSchema, EveryNumericsChoiceIsOneTheFluidSolverAccepts) {
  const Schema& schema = case_schema();
  for (const std::string& name : schema.find("numerics.collision")->choices)
    EXPECT_NO_THROW(lbm::parse_collision(name, "numerics.collision")) << name;
  for (const std::string& name : schema.find("numerics.lattice")->choices)
    EXPECT_NO_THROW(lbm::parse_lattice(name, "numerics.lattice")) << name;
  for (const std::string& name : schema.find("numerics.precision")->choices)
    EXPECT_NO_THROW(lbm::parse_precision(name, "numerics.precision")) << name;
  for (const std::string& name : schema.find("numerics.subgrid_model")->choices)
    EXPECT_NO_THROW(lbm::parse_subgrid_model(name, "numerics.subgrid_model")) << name;
}

// TRT's magic parameter reaches the solver's set-up, and set with another operator it is reported
// (it would change nothing); at its default, as a resolved case writes it, it is not.
TEST(CaseSchema, TrtMagicReachesTheSetupAndIsReportedUnderAnotherOperator) {
  const std::string base =
      "[fluid]\ndensity = 1000\ndynamic_viscosity = 1e-3\n[particle]\nshape = \"sphere\"\ndiameter = 1e-3\n"
      "density = 2500\n[domain]\nsize = [8e-3, 8e-3, 8e-3]\n[numerics]\n";
  const auto values_of = [&base](const std::string& numerics) {
    return parse_case(case_schema(), base + numerics, "case.toml");
  };
  EXPECT_EQ(simulation_setup(values_of("trt_magic = 0.0833333\n"), ".", "c").trt_magic, 0.0833333);
  EXPECT_EQ(simulation_setup(values_of(""), ".", "c").trt_magic, lbm::kWallExactTrtMagic);
  EXPECT_TRUE(unsupported_key_warnings(values_of("trt_magic = 0.0833333\n")).empty());
  const auto bgk = unsupported_key_warnings(values_of("collision = \"bgk\"\ntrt_magic = 0.0833333\n"));
  ASSERT_EQ(bgk.size(), 1u);
  EXPECT_NE(bgk[0].find("numerics.trt_magic"), std::string::npos) << bgk[0];
  EXPECT_TRUE(unsupported_key_warnings(values_of("collision = \"bgk\"\ntrt_magic = 0.1875\n")).empty());
  for (const char* bad : {"trt_magic = 0.0\n", "trt_magic = 1.5\n", "trt_magic = -0.1\n"}) {
    try {
      values_of(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("[numerics] trt_magic"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("(0.0, 1.0]"), std::string::npos) << e.what();
    }
  }
}

// The subgrid model and its constant reach the solver's set-up; the constant set without the model is
// reported (it would change nothing), and out of its range refused naming the key.
TEST(CaseSchema, SmagorinskyModelReachesTheSetupAndItsConstantAloneIsReported) {
  const std::string base =
      "[fluid]\ndensity = 1000\ndynamic_viscosity = 1e-3\n[particle]\nshape = \"sphere\"\ndiameter = 1e-3\n"
      "density = 2500\n[domain]\nsize = [8e-3, 8e-3, 8e-3]\n[numerics]\n";
  const auto values_of = [&base](const std::string& numerics) {
    return parse_case(case_schema(), base + numerics, "case.toml");
  };
  const auto plain = simulation_setup(values_of(""), ".", "c");
  EXPECT_EQ(plain.subgrid_model, lbm::SubgridModel::automatic);  // chosen by the plan (lbm::chosen_subgrid_model)
  EXPECT_EQ(plain.smagorinsky_constant, lbm::kDefaultSmagorinskyConstant);
  const auto les =
      simulation_setup(values_of("subgrid_model = \"smagorinsky\"\nsmagorinsky_constant = 0.17\n"), ".", "c");
  EXPECT_EQ(les.subgrid_model, lbm::SubgridModel::smagorinsky);
  EXPECT_EQ(les.smagorinsky_constant, 0.17);
  EXPECT_TRUE(
      unsupported_key_warnings(values_of("subgrid_model = \"smagorinsky\"\nsmagorinsky_constant = 0.17\n")).empty());
  // "auto" may choose the model, so its constant is read; with "none" it is not, and set alone it is reported.
  EXPECT_TRUE(unsupported_key_warnings(values_of("smagorinsky_constant = 0.17\n")).empty());
  const auto alone = unsupported_key_warnings(values_of("subgrid_model = \"none\"\nsmagorinsky_constant = 0.17\n"));
  ASSERT_EQ(alone.size(), 1u);
  EXPECT_NE(alone[0].find("numerics.smagorinsky_constant"), std::string::npos) << alone[0];
  EXPECT_TRUE(unsupported_key_warnings(values_of("subgrid_model = \"none\"\nsmagorinsky_constant = 0.1\n")).empty());
  for (const char* bad :
       {"smagorinsky_constant = 0.0\n", "smagorinsky_constant = 0.6\n", "subgrid_model = \"wale\"\n"}) {
    try {
      values_of(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("[numerics] s"), std::string::npos) << e.what();
    }
  }
}

TEST(CaseSchema, WallRuleReachesTheSetupByName) {
  const std::string base =
      "[fluid]\ndensity = 1000\ndynamic_viscosity = 1e-3\n[particle]\nshape = \"sphere\"\ndiameter = 1e-3\n"
      "density = 2500\n[domain]\nsize = [8e-3, 8e-3, 8e-3]\n[numerics]\n";
  const auto rule_of = [&base](const std::string& numerics) {
    return simulation_setup(parse_case(case_schema(), base + numerics, "case.toml"), ".", "c").wall_rule;
  };
  EXPECT_EQ(rule_of(""), lbm::WallRule::bouzidi);
  EXPECT_EQ(rule_of("wall_rule = \"quadratic\"\n"), lbm::WallRule::quadratic);
  EXPECT_EQ(rule_of("wall_rule = \"halfway\"\n"), lbm::WallRule::halfway);
  EXPECT_EQ(rule_of("wall_rule = \"central_linear\"\n"), lbm::WallRule::central_linear);
  try {
    rule_of("wall_rule = \"cubic\"\n");
    ADD_FAILURE() << "cubic was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[numerics] wall_rule"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("quadratic"), std::string::npos) << e.what();
  }
}

// A key that only the other coupling reads is reported when the case sets it away from its default
// (it would change nothing); a resolved case, which writes every key at its value, is not.
TEST(CaseSchema, KeysOfTheOtherCouplingAreReportedWhenSetAwayFromTheirDefault) {
  const Schema& schema = case_schema();
  const auto warnings_of = [&schema](const std::string& numerics) {
    return unsupported_key_warnings(parse_case(schema, "[numerics]\n" + numerics, "case.toml"));
  };
  const auto halfway = warnings_of("coupling = \"immersed_boundary\"\nwall_rule = \"halfway\"\n");
  ASSERT_EQ(halfway.size(), 1u);
  EXPECT_NE(halfway[0].find("numerics.wall_rule"), std::string::npos) << halfway[0];
  EXPECT_NE(halfway[0].find("momentum_exchange"), std::string::npos) << halfway[0];
  EXPECT_EQ(warnings_of("coupling = \"momentum_exchange\"\nwall_rule = \"halfway\"\n").size(), 0u);

  const auto interior = warnings_of(
      "coupling = \"momentum_exchange\"\ninterior_markers = true\nforcing_iterations = 5\nmarker_retraction = 0.3\n");
  ASSERT_EQ(interior.size(), 3u);
  EXPECT_NE(interior[0].find("numerics.forcing_iterations"), std::string::npos) << interior[0];
  EXPECT_NE(interior[1].find("numerics.marker_retraction"), std::string::npos) << interior[1];
  EXPECT_NE(interior[2].find("numerics.interior_markers"), std::string::npos) << interior[2];
  // Written at their defaults, as case.resolved.toml writes them: nothing to report.
  EXPECT_EQ(warnings_of("coupling = \"momentum_exchange\"\ninterior_markers = false\nforcing_iterations = 3\n"
                        "delta_kernel = \"roma3\"\n")
                .size(),
            0u);
}

// The user guide's key table is generated from the declaration (`settle schema --markdown`); a
// key added, renamed or re-documented without regenerating the page fails here.
TEST(CaseSchema, TheUserGuideHoldsTheCurrentKeyTable) {
  std::ifstream in(std::string(SETTLE_SOURCE_DIR) + "/docs/case-file.md");
  std::stringstream page;
  page << in.rdbuf();
  EXPECT_NE(page.str().find(schema_markdown(case_schema())), std::string::npos)
      << "docs/case-file.md: regenerate the key table with `settle schema --markdown`";
}

TEST(CaseSchema, TheDesignDocumentsExampleCaseParses) {
  const char* example = R"(
[fluid]
density = 998.2
dynamic_viscosity = 1.0e-3
gravity = [0.0, 0.0, -9.81]
[particle]
shape = "spheroid"
diameter = 2.0e-3
aspect_ratio = 2.5
density = 1050.0
motion = "free"
position = [0.02, 0.02, 0.10]
euler = [0.0, 0.5, 0.0]
velocity = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 0.0]
[domain]
size = [0.04, 0.04, 0.12]
walls = { x = "no-slip", y = "no-slip", z = "no-slip" }
follow_particle = false
[numerics]
cells_per_diameter = 16
collision = "trt"
precision = "double"
[run]
end_time = 1.0
output_interval = 0.005
vtk_interval = 0.0
stop_at_terminal = false
checkpoint_interval = 0.0
)";
  const CaseValues v = parse_case(case_schema(), example, "design.toml");
  EXPECT_EQ(v.string("particle.shape"), "spheroid");
  EXPECT_DOUBLE_EQ(v.real("numerics.cells_per_diameter"), 16.0);
  EXPECT_EQ(v.reals("domain.size")[2], 0.12);
}

// numerics.marker_retraction has no fixed default: each marker layout has its own calibrated
// retraction (docs/coupling.md), and a given value wins over both.
TEST(CaseSchema, MarkerRetractionDefaultsToTheCalibrationOfTheMarkerLayout) {
  const std::string base =
      "[fluid]\ndensity = 1000\ndynamic_viscosity = 1e-3\n[particle]\nshape = \"sphere\"\ndiameter = 1e-3\n"
      "density = 2500\n[domain]\nsize = [8e-3, 8e-3, 8e-3]\n[numerics]\n";
  const auto retraction = [&](const std::string& numerics) {
    const CaseValues v = parse_case(case_schema(), base + numerics, "c.toml");
    return simulation_setup(v, ".", "c").marker_retraction_cells;
  };
  EXPECT_EQ(retraction(""), 0.4);
  EXPECT_EQ(retraction("interior_markers = true\n"), 0.5);
  EXPECT_EQ(retraction("interior_markers = true\nmarker_retraction = 0.3\n"), 0.3);
  EXPECT_EQ(retraction("marker_retraction = 0.0\n"), 0.0);
}

}  // namespace test_schema
}  // namespace settle::io
