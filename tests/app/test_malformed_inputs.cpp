// Case tests of input checking: bad input to `settle run` gets a clear error, never a crash or a wrong
// run. Each malformed input must
//  - exit with status 2 (an InputError; a crash or a signal gives something else),
//  - name the key (or flag, or file) at fault in stderr,
//  - leave the results directory exactly as it was: every test passes `-o DIR` for a DIR that
//    already holds a sentinel file, and compares DIR's listing (names, sizes, modification times,
//    the directory's own modification time) before and after.
// The inputs are malformations of one small valid case (a 1 mm sphere, 32 x 32 x 48 cells, a few
// steps), which itself runs and writes its results (the positive controls at the end), so each
// refusal is due to the one thing changed. Every refusal happens before the grid exists, so each
// test takes a few milliseconds.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "cli_support.hpp"

namespace test_malformed_inputs {

namespace fs = std::filesystem;
using settle::test::CliResult;

std::string data_file(const std::string& name) { return std::string(SETTLE_SOURCE_DIR) + "/tests/data/" + name; }

// The [particle] shape lines of the valid case; mesh tests replace them.
const char* kSphere = "shape = \"sphere\"\ndiameter = 1.0e-3\n";

std::string valid_case(const std::string& shape_lines = kSphere) {
  return "[fluid]\ndensity = 998.2\ndynamic_viscosity = 1.0e-3\ngravity = [0.0, 0.0, -9.81]\n"
         "[particle]\n" +
         shape_lines +
         "density = 1100.0\nposition = [2.0e-3, 2.0e-3, 3.0e-3]\n"
         "[domain]\nsize = [4.0e-3, 4.0e-3, 6.0e-3]\n"
         "[numerics]\ncells_per_diameter = 8\n"
         "[run]\nend_time = 1.0e-3\noutput_interval = 5.0e-4\n";
}

// One entry per file or folder under the results directory, and the directory itself.
using Listing = std::vector<std::tuple<std::string, std::uintmax_t, fs::file_time_type>>;

Listing listing(const fs::path& dir) {
  Listing entries{{".", 0, fs::last_write_time(dir)}};
  for (const auto& e : fs::recursive_directory_iterator(dir))
    entries.emplace_back(fs::relative(e.path(), dir).string(), e.is_regular_file() ? e.file_size() : 0,
                         e.last_write_time());
  std::sort(entries.begin(), entries.end());
  return entries;
}

class MalformedInput : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = settle::test::scratch(::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    results_ = root_ / "results";
    fs::create_directories(results_);
    std::ofstream(results_ / "sentinel.txt") << "results of an earlier run\n";
    write_case(valid_case());
    before_ = listing(results_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::permissions(root_, fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(root_, ignored);
  }

  void write_case(const std::string& text) { std::ofstream(case_path()) << text; }
  fs::path case_path() const { return root_ / "case.toml"; }

  /// `settle run <case.toml> <arguments> -o <results>`.
  CliResult run_case(const std::string& arguments) {
    return settle::test::run_settle("run", case_path().string() + " " + arguments + " -o " + results_.string());
  }

  /// Exit status 2 and every fragment in stderr (the key, and what is wrong), with the results
  /// directory untouched.
  void expect_refused(const CliResult& r, std::initializer_list<std::string> fragments) {
    RecordProperty("stderr", r.err);  // in --gtest_output=xml: the messages, for docs/errors.md
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("settle: error:"), std::string::npos) << r.err;
    for (const std::string& f : fragments)
      EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in\n" << r.err;
    EXPECT_EQ(listing(results_), before_) << "the results directory changed; stderr:\n" << r.err;
  }
  void expect_refused_set(const std::string& sets, std::initializer_list<std::string> fragments) {
    expect_refused(run_case(sets), fragments);
  }
  void expect_refused_text(const std::string& text, std::initializer_list<std::string> fragments) {
    write_case(text);
    expect_refused(run_case(""), fragments);
  }

  fs::path root_, results_;
  Listing before_;
};

// ---- the case file itself ---------------------------------------------------------------------

TEST_F(MalformedInput, MissingCaseFile) {
  fs::remove(case_path());
  expect_refused(run_case(""), {case_path().string(), "no such case file"});
}

TEST_F(MalformedInput, EmptyCaseArgument) {
  // settle run "$CASE" with CASE unset: it ran the built-in default case (25 s) into -o DIR.
  expect_refused(settle::test::run_settle("run", "'' --threads 1 -o " + results_.string()), {"CASE", "empty"});
}

TEST_F(MalformedInput, EmptyRestartArgument) {
  expect_refused(settle::test::run_settle("run", "--restart '' --threads 1"), {"--restart", "empty"});
}

TEST_F(MalformedInput, CaseFileIsADirectory) {
  fs::remove(case_path());
  fs::create_directory(case_path());
  expect_refused(run_case(""), {"is a directory"});
}

TEST_F(MalformedInput, AnEndlessStreamAsTheCaseFile) {
  // /dev/zero was read forever, the memory growing by 250 MB/s; now refused after 64 MiB.
  const CliResult r = settle::test::run_settle("run", "/dev/zero --threads 1 -o " + results_.string());
  expect_refused(r, {"/dev/zero", "not a case file"});
}

TEST_F(MalformedInput, TomlSyntaxError) {
  expect_refused_text("[fluid\ndensity = 998.2\n", {"case.toml:1", "TOML syntax error"});
}

TEST_F(MalformedInput, DuplicateKey) {
  expect_refused_text(valid_case() + "[fluid]\ndensity = 1000.0\n", {"case.toml", "TOML syntax error"});
}

// ---- types ------------------------------------------------------------------------------------

TEST_F(MalformedInput, StringWhereANumberIsDeclared) {
  std::string text = valid_case();
  text.replace(text.find("density = 998.2"), 15, "density = \"water\"");
  expect_refused_text(text, {"[fluid] density", "water", "expected a number"});
}

TEST_F(MalformedInput, NumberWhereAnArrayIsDeclared) {
  expect_refused_set("--set fluid.gravity=-9.81", {"fluid.gravity", "expected an array of numbers"});
}

TEST_F(MalformedInput, StringWhereABooleanIsDeclared) {
  expect_refused_set("--set 'domain.follow_particle=\"yes\"'", {"domain.follow_particle", "expected a boolean"});
}

TEST_F(MalformedInput, FractionWhereAnIntegerIsDeclared) {
  expect_refused_set("--set numerics.forcing_iterations=2.5", {"numerics.forcing_iterations", "expected an integer"});
}

TEST_F(MalformedInput, ArrayOfTheWrongLength) {
  expect_refused_set("--set 'domain.size=[4e-3, 4e-3]'", {"[domain] size", "an array of 3 numbers"});
}

TEST_F(MalformedInput, ChoiceOutsideTheAllowedStrings) {
  expect_refused_set("--set 'domain.walls.x=\"open\"'",
                     {"[domain] walls.x", "\"open\"", "\"no-slip\", \"free-slip\", \"periodic\""});
}

// ---- values out of range, not finite ------------------------------------------------------------

TEST_F(MalformedInput, IntegerOutsideItsRange) {
  expect_refused_set("--set numerics.lattice_steps_per_body_step=3",
                     {"[numerics] lattice_steps_per_body_step", "must be in [1, 2]"});
}

TEST_F(MalformedInput, TwoLatticeStepsPerBodyStepWithTheImmersedBoundary) {
  expect_refused_set("--set numerics.lattice_steps_per_body_step=2 --set 'numerics.coupling=\"immersed_boundary\"'",
                     {"numerics.lattice_steps_per_body_step", "momentum_exchange"});
}

TEST_F(MalformedInput, ZeroFluidDensity) { expect_refused_set("--set fluid.density=0", {"[fluid] density", "> 0.0"}); }

TEST_F(MalformedInput, NegativeParticleDensity) {
  expect_refused_set("--set particle.density=-1100", {"[particle] density", "-1100"});
}

TEST_F(MalformedInput, SubnormalParticleDensity) {
  // Positive, so the schema takes it, but the mass underflows: the preflight passed and building
  // the body failed with an internal error (status 1).
  expect_refused_set("--set particle.density=1e-320", {"particle.density", "1e-320", "mass"});
}

TEST_F(MalformedInput, SubnormalParticleDensityInADryRun) {
  expect_refused_set("--set particle.density=1e-320 --dry-run", {"particle.density", "mass"});
}

TEST_F(MalformedInput, ZeroViscosity) {
  expect_refused_set("--set fluid.dynamic_viscosity=0.0", {"[fluid] dynamic_viscosity", "> 0.0"});
}

TEST_F(MalformedInput, NegativeViscosity) {
  expect_refused_set("--set fluid.dynamic_viscosity=-1e-3", {"[fluid] dynamic_viscosity"});
}

TEST_F(MalformedInput, NanDensityInTheFile) {
  std::string text = valid_case();
  text.replace(text.find("density = 1100.0"), 16, "density = nan");
  expect_refused_text(text, {"[particle] density", "nan", "finite"});
}

TEST_F(MalformedInput, InfiniteGravityComponent) {
  expect_refused_set("--set 'fluid.gravity=[0.0, 0.0, -inf]'", {"[fluid] gravity", "finite"});
}

TEST_F(MalformedInput, NanDiameter) {
  expect_refused_set("--set particle.diameter=nan", {"[particle] diameter", "finite"});
}

TEST_F(MalformedInput, RelaxationTimeAtTheStabilityLimit) {
  expect_refused_set("--set numerics.tau=0.5", {"[numerics] tau", "(0.501, 5.0]"});
}

TEST_F(MalformedInput, AHugeValueIsCutInTheMessage) {
  // A 100 kB string and an array of 20 000 numbers: the message quoted each whole, on one line of
  // stderr (10 MB for a 10 MB value). It names the key and shows the start of the value.
  std::string text = valid_case("shape = \"" + std::string(100000, 's') + "\"\ndiameter = 1.0e-3\n");
  CliResult r = (write_case(text), run_case(""));
  expect_refused(r, {"[particle] shape = \"sss", "..."});
  EXPECT_LT(r.err.size(), 1000u) << r.err.substr(0, 1000);
  std::string numbers;
  for (int i = 0; i < 20000; ++i) numbers += (i ? ", " : "") + std::to_string(i);
  text = valid_case();
  const std::string position = "position = [2.0e-3, 2.0e-3, 3.0e-3]";
  text.replace(text.find(position), position.size(), "position = [" + numbers + "]");
  r = (write_case(text), run_case(""));
  expect_refused(r, {"[particle] position = [0.0, 1.0, 2.0", "..."});
  EXPECT_LT(r.err.size(), 1000u) << r.err.substr(0, 1000);
}

// ---- shapes -------------------------------------------------------------------------------------

TEST_F(MalformedInput, ZeroDiameter) { expect_refused_set("--set particle.diameter=0", {"[particle] diameter"}); }

TEST_F(MalformedInput, NegativeSemiAxis) {
  expect_refused_text(valid_case("shape = \"ellipsoid\"\nsemi_axes = [1e-3, -0.5e-3, 0.5e-3]\n"),
                      {"[particle] semi_axes", "> 0.0"});
}

TEST_F(MalformedInput, ZeroCuboidEdge) {
  expect_refused_text(valid_case("shape = \"cuboid\"\nsize = [1e-3, 0.0, 1e-3]\n"), {"[particle] size"});
}

TEST_F(MalformedInput, AspectRatioZero) {
  expect_refused_text(valid_case("shape = \"spheroid\"\ndiameter = 1e-3\naspect_ratio = 0.0\n"),
                      {"[particle] aspect_ratio", "in [0.001, 1000.0]"});
}

TEST_F(MalformedInput, AspectRatioOfANeedle) {
  expect_refused_text(valid_case("shape = \"spheroid\"\ndiameter = 1e-3\naspect_ratio = 1e6\n"),
                      {"[particle] aspect_ratio"});
}

TEST_F(MalformedInput, SuperellipsoidExponentBeyondConvex) {
  expect_refused_text(
      valid_case("shape = \"superellipsoid\"\nsemi_axes = [5e-4, 5e-4, 5e-4]\nexponents = [3.0, 1.0]\n"),
      {"[particle] exponents", "in [0.1, 2.0]"});
}

TEST_F(MalformedInput, ShapeKeyMissing) {
  expect_refused_text(valid_case("shape = \"spheroid\"\ndiameter = 1e-3\n"),
                      {"particle.aspect_ratio", "required for shape 'spheroid'"});
}

TEST_F(MalformedInput, KeyTheShapeDoesNotUse) {
  expect_refused_text(valid_case("shape = \"cylinder\"\ndiameter = 1e-3\nlength = 1e-3\naspect_ratio = 2.0\n"),
                      {"particle.aspect_ratio", "not used by shape 'cylinder'"});
}

// ---- meshes -------------------------------------------------------------------------------------

std::string mesh_lines(const std::string& file) {
  return "shape = \"mesh\"\nfile = \"" + file + "\"\nscale = 1.0e-3\n";
}

TEST_F(MalformedInput, MeshFileMissing) {
  expect_refused_text(valid_case(mesh_lines("no_such_grain.stl")),
                      {"particle.file", "no_such_grain.stl", "no such file"});
}

TEST_F(MalformedInput, MeshNotWatertight) {
  expect_refused_text(valid_case(mesh_lines(data_file("open_box.stl"))), {"particle.file", "not watertight"});
}

TEST_F(MalformedInput, MeshFileEmpty) {
  expect_refused_text(valid_case(mesh_lines(data_file("empty.stl"))), {"particle.file", "empty"});
}

TEST_F(MalformedInput, MeshFileNotAnStl) {
  expect_refused_text(valid_case(mesh_lines(data_file("garbage.stl"))), {"particle.file", "not an STL file"});
}

TEST_F(MalformedInput, MeshInMillimetresReadAsMetres) {
  // The 1 mm cube of cube_ascii.stl (coordinates 0 to 1, meant with scale = 1e-3) without its scale
  // is 1 m wide: such a mesh was reported as a resolution to raise (796 952 cells per diameter) or
  // a domain of 0 cells, never as a mesh in the wrong units.
  expect_refused_text(valid_case("shape = \"mesh\"\nfile = \"" + data_file("cube_ascii.stl") + "\"\n"),
                      {"domain.size", "1 m wide", "particle.scale"});
}

TEST_F(MalformedInput, MeshScaleZero) {
  expect_refused_text(valid_case("shape = \"mesh\"\nfile = \"" + data_file("cube_ascii.stl") + "\"\nscale = 0.0\n"),
                      {"[particle] scale"});
}

// ---- the particle in the domain -------------------------------------------------------------------

TEST_F(MalformedInput, BuoyantParticleUnderAPeriodicTop) {
  // Lighter than water, gravity down, z periodic: it would rise with nothing to carry its net
  // weight (io/preflight.hpp, check_net_weight; docs/errors.md).
  expect_refused_set("--set particle.density=900 --set 'domain.walls.z=\"periodic\"'",
                     {"domain.walls.z", "lighter than the fluid", "rises along +z"});
}

TEST_F(MalformedInput, HeavyParticleInAPeriodicColumn) {
  expect_refused_set("--set 'domain.walls.z=\"periodic\"'",
                     {"domain.walls.z", "heavier than the fluid", "sinks along -z"});
}

TEST_F(MalformedInput, ParticleLargerThanTheDomain) {
  expect_refused_set("--set particle.diameter=5e-3", {"domain.size", "wide along x"});
}

TEST_F(MalformedInput, ParticleOverlapsTheBottomWall) {
  expect_refused_set("--set 'particle.position=[2e-3, 2e-3, 3e-4]'",
                     {"particle.position", "overlaps the wall at z = 0"});
}

TEST_F(MalformedInput, TiltedCuboidOverlapsAWallOnlyBecauseOfItsAttitude) {
  // A 2 x 0.4 x 0.4 mm rod at y = 0.7 mm: along x it clears the wall at y = 0 by 0.5 mm, but
  // turned by psi = pi/2 about z it lies along y and reaches y = -0.3 mm.
  std::string text = valid_case("shape = \"cuboid\"\nsize = [2e-3, 0.4e-3, 0.4e-3]\n");
  const std::string centred = "position = [2.0e-3, 2.0e-3, 3.0e-3]";
  text.replace(text.find(centred), centred.size(),
               "position = [2.0e-3, 0.7e-3, 3.0e-3]\neuler = [1.5707963267948966, 0.0, 0.0]");
  expect_refused_text(text, {"particle.position", "overlaps the wall at y = 0", "reaches down to y = -0.0003"});
}

TEST_F(MalformedInput, ParticleTooCloseToAWallForTheForcingStencil) {
  // 0.1 mm of water under the sphere: no overlap, but the Roma kernel's stencil needs one cell
  // (0.125 mm) of fluid between the surface and the wall.
  expect_refused_set("--set 'particle.position=[2e-3, 2e-3, 6e-4]' --set 'numerics.coupling=\"immersed_boundary\"'",
                     {"particle.position", "stencil"});
}

TEST_F(MalformedInput, ParticleInsideTheWallContactDistance) {
  // 0.8 cells (0.1 mm) of water under the sphere: enough for the momentum exchange's links (more
  // than half a cell), but inside the wall-contact spring's reach (one cell): refused
  // (coupling::start_wall_contact, the rule the preflight and the Simulation constructor share),
  // leaving the results directory untouched.
  expect_refused_set("--set 'particle.position=[2e-3, 2e-3, 6e-4]'", {"particle.position", "wall-contact"});
}

TEST_F(MalformedInput, ParticleCentreOutsideTheDomain) {
  expect_refused_set("--set 'particle.position=[-1e-3, 2e-3, 3e-3]'", {"particle.position", "outside the domain"});
}

TEST_F(MalformedInput, DomainOfFewerThanFourCells) {
  // A flat plate (d_eq 0.58 mm, dx 0.072 mm) 0.1 mm thick in a domain 0.2 mm high: narrower than the
  // domain (a particle wider than it is refused before, by its size), but 3 cells high.
  std::string text = valid_case("shape = \"cuboid\"\nsize = [1.0e-3, 1.0e-3, 1.0e-4]\n");
  text.replace(text.find("position = [2.0e-3, 2.0e-3, 3.0e-3]"), 35, "position = [2.0e-3, 2.0e-3, 1.0e-4]");
  text.replace(text.find("size = [4.0e-3, 4.0e-3, 6.0e-3]"), 31, "size = [4.0e-3, 4.0e-3, 2.0e-4]");
  expect_refused_text(text, {"domain.size", "at least 4"});
}

// ---- resolution, time step, memory ----------------------------------------------------------------

TEST_F(MalformedInput, ZeroCellsPerDiameter) {
  expect_refused_set("--set numerics.cells_per_diameter=0", {"[numerics] cells_per_diameter", "in [4.0, 256.0]"});
}

TEST_F(MalformedInput, MillionCellsPerDiameter) {
  expect_refused_set("--set numerics.cells_per_diameter=1e6", {"[numerics] cells_per_diameter"});
}

TEST_F(MalformedInput, GridBeyondTwoBillionCells) {
  expect_refused_set(
      "--set numerics.cells_per_diameter=256 --set 'domain.size=[1.0, 1.0, 1.0]' "
      "--set 'particle.position=[0.5, 0.5, 0.5]'",
      {"numerics.cells_per_diameter", "cells", "GiB"});
}

TEST_F(MalformedInput, GridBeyondTheMemoryBudget) {
  // 32 x 32 x 48 cells of D3Q19 doubles need about 10 MiB; the budget is 1 MiB.
  expect_refused_set("--max-memory 0.0009765625", {"numerics.cells_per_diameter", "--max-memory"});
}

TEST_F(MalformedInput, EveryStepKeptForAnAbsurdEndTime) {
  // output_interval = 0 keeps a row per step: 1e7 s at dt ~ 1e-4 s is ~1e11 rows in memory.
  expect_refused_set("--set run.output_interval=0 --set run.end_time=1e7", {"run.output_interval", "memory"});
}

TEST_F(MalformedInput, MoreStepsThanTimeCanCount) {
  expect_refused_set("--set run.end_time=1e14", {"run.end_time", "steps"});
}

// Extreme fluid properties: the messages named numerics.cells_per_diameter ("at least inf") or
// run.end_time for what the fluid's numbers cause. Each must name the fluid keys.
TEST_F(MalformedInput, KinematicViscosityBelowDoublePrecision) {
  expect_refused_set("--set fluid.density=1e308", {"fluid.density", "fluid.dynamic_viscosity", "kinematic viscosity"});
}

TEST_F(MalformedInput, ReynoldsNumberBeyondAnyGrid) {
  const CliResult r = run_case("--set fluid.dynamic_viscosity=1e-300");
  expect_refused(r, {"fluid.dynamic_viscosity", "fluid.density", "beyond any grid"});
  EXPECT_EQ(r.err.find("inf"), std::string::npos) << r.err;
}

TEST_F(MalformedInput, TimeStepBelowDoublePrecision) {
  expect_refused_set("--set fluid.dynamic_viscosity=1e308", {"fluid.dynamic_viscosity", "fluid.density", "dt"});
}

TEST_F(MalformedInput, TimeStepTooShortToCountBecauseOfTheFluid) {
  expect_refused_set("--set fluid.density=1e-300", {"fluid.dynamic_viscosity", "fluid.density", "2^53"});
}

TEST_F(MalformedInput, FastTowedBodyUnderResolved) {
  // Re = 5000 at 8 cells per diameter: no dt meets the Mach and tau bounds together.
  expect_refused_set("--set 'particle.motion=\"towed\"' --set 'particle.towing_velocity=[0, 0, -5]'",
                     {"numerics.cells_per_diameter", "under-resolve"});
}

TEST_F(MalformedInput, FixedRelaxationTimeBreaksTheMachBound) {
  expect_refused_set(
      "--set 'particle.motion=\"towed\"' --set 'particle.towing_velocity=[0, 0, -0.5]' "
      "--set numerics.tau=1.9",
      {"numerics.tau", "Mach"});
}

TEST_F(MalformedInput, BodyForceOnAFreeParticle) {
  expect_refused_set("--set 'fluid.body_force=[1.0, 0.0, 0.0]'", {"fluid.body_force"});
}

TEST_F(MalformedInput, TowedWithoutVelocity) {
  expect_refused_set("--set 'particle.motion=\"towed\"'", {"particle.towing_velocity"});
}

TEST_F(MalformedInput, ReleaseTimeOfATowedBody) {
  expect_refused_set(
      "--set 'particle.motion=\"towed\"' --set 'particle.towing_velocity=[0, 0, -0.01]' "
      "--set particle.release_time=0.01",
      {"particle.release_time", "free"});
}

TEST_F(MalformedInput, ReleaseAfterTheEndOfTheRun) {
  expect_refused_set("--set run.end_time=0.1 --set particle.release_time=0.1",
                     {"particle.release_time", "run.end_time"});
}

TEST_F(MalformedInput, HoldRampLongerThanTheHold) {
  expect_refused_set("--set run.end_time=0.1 --set particle.release_time=0.01 --set particle.hold_ramp_time=0.02",
                     {"particle.hold_ramp_time", "particle.release_time", "0 to"});
}

TEST_F(MalformedInput, TowingRampLongerThanTheRun) {
  expect_refused_set(
      "--set run.end_time=0.1 --set 'particle.motion=\"towed\"' --set 'particle.towing_velocity=[0, 0, -0.01]' "
      "--set particle.hold_ramp_time=0.2",
      {"particle.hold_ramp_time", "run.end_time", "towed"});
}

TEST_F(MalformedInput, RotationLockOfATowedBody) {
  expect_refused_set(
      "--set 'particle.motion=\"towed\"' --set 'particle.towing_velocity=[0, 0, -0.01]' "
      "--set particle.lock_rotation=true",
      {"particle.lock_rotation", "free"});
}

TEST_F(MalformedInput, RotationLockOfASpinningBody) {
  expect_refused_set("--set particle.lock_rotation=true --set 'particle.angular_velocity=[0, 2, 0]'",
                     {"particle.lock_rotation", "particle.angular_velocity", "[0, 2, 0]"});
}

TEST_F(MalformedInput, NegativeReleaseTime) {
  expect_refused_set("--set particle.release_time=-0.01", {"release_time", "must be >= 0"});
}

// ---- keys, tables, --set -------------------------------------------------------------------------

TEST_F(MalformedInput, UnknownKeyInTheFileWithASuggestion) {
  std::string text = valid_case();
  text.replace(text.find("dynamic_viscosity"), 17, "dynamic_viscosty");
  expect_refused_text(text, {"unknown key [fluid] dynamic_viscosty", "did you mean [fluid] dynamic_viscosity?"});
}

TEST_F(MalformedInput, UnknownKeyOnTheCommandLineWithASuggestion) {
  expect_refused_set("--set numerics.cells_per_diametre=8",
                     {"unknown key numerics.cells_per_diametre", "did you mean numerics.cells_per_diameter?"});
}

TEST_F(MalformedInput, UnknownEmptyTable) {
  expect_refused_text(valid_case() + "[flud]\n", {"unknown table [flud]", "did you mean [fluid]?"});
}

TEST_F(MalformedInput, ScalarGivenForTheWallsTable) {
  std::string text = valid_case();
  text.replace(text.find("[domain]\n"), 9, "[domain]\nwalls = \"no-slip\"\n");
  expect_refused_text(text, {"[domain] walls", "expected a table with the keys x, y, z"});
}

TEST_F(MalformedInput, SetWithoutAnEqualsSign) {
  expect_refused_set("--set fluid.density", {"--set fluid.density", "expected key=value"});
}

TEST_F(MalformedInput, SetWithoutAValue) {
  expect_refused_set("--set fluid.density=", {"--set fluid.density=", "no value"});
}

TEST_F(MalformedInput, SetStringWithoutQuotes) {
  expect_refused_set("--set particle.shape=sphere", {"particle.shape", "double quotes"});
}

TEST_F(MalformedInput, SetTwoValuesAtOnce) {
  expect_refused_set("--set 'fluid.density=1000.0\nfoo = 2'", {"--set", "a single value"});
}

// ---- flags and the output directory --------------------------------------------------------------

TEST_F(MalformedInput, NegativeThreadCount) { expect_refused_set("--threads -2", {"--threads"}); }

TEST_F(MalformedInput, ThreadCountBeyondWhatOpenMpCanCreate) {
  // 100 000 threads crashed libgomp (SIGSEGV) after the results directory was prepared.
  expect_refused_set("--threads 100000", {"--threads", "100000"});
}

TEST_F(MalformedInput, NegativeMemoryBudget) { expect_refused_set("--max-memory -1", {"--max-memory"}); }

TEST_F(MalformedInput, OutputPathIsAFile) {
  const CliResult r =
      settle::test::run_settle("run", case_path().string() + " -o " + (results_ / "sentinel.txt").string());
  expect_refused(r, {"-o", "sentinel.txt", "not a directory"});
}

TEST_F(MalformedInput, OutputDirectoryBelowAFile) {
  const fs::path below = results_ / "sentinel.txt" / "run";
  const CliResult r = settle::test::run_settle("run", case_path().string() + " -o " + below.string());
  expect_refused(r, {"-o", "cannot be created", "is not a directory"});
}

TEST_F(MalformedInput, OutputDirectoryNotWritable) {
  // Permission bits do not bind root; the two tests above cover the path checks there.
  if (::geteuid() == 0) GTEST_SKIP() << "running as root: permission bits are not enforced";
  fs::permissions(results_, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
  before_ = listing(results_);
  const CliResult r = settle::test::run_settle("run", case_path().string() + " -o " + (results_ / "run").string());
  expect_refused(r, {"-o", "not writable"});
}

TEST_F(MalformedInput, ARefusedRunDoesNotCreateItsOutputDirectory) {
  const fs::path fresh = root_ / "fresh";
  const CliResult r =
      settle::test::run_settle("run", case_path().string() + " --set fluid.density=-1 -o " + fresh.string());
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_FALSE(fs::exists(fresh));
}

TEST_F(MalformedInput, AStaleSummaryDoesNotSurviveARunThatFailsAfterItsChecks) {
  // An earlier run's summary.json, and a folder where the temporary of case.resolved.toml must go
  // (a folder, so not a file of settle's it may replace): every check passes, the run starts
  // writing, then cannot write case.resolved.toml. summary.json marks a finished run (cmd_run.cpp),
  // so the stale one must be gone rather than sit beside the new files.
  std::ofstream(results_ / "summary.json") << "{\"case\": \"case\", \"steps\": 1, \"stop_reason\": \"end_time\"}\n";
  fs::create_directory(results_ / "case.resolved.toml.tmp");
  const CliResult r = run_case("--threads 1 --overwrite");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("case.resolved.toml"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(results_ / "summary.json"));
  EXPECT_TRUE(fs::exists(results_ / "sentinel.txt"));
}

// ---- promise 1: nothing the user wrote is ever deleted (docs/errors.md, "Promises") -------------
// A fresh run replaces or removes only the files an earlier settle run left, recognised by their
// format (app/earlier_run.hpp); a file or folder of the user's under one of the names a run writes
// is a refusal, with the results directory untouched.

TEST_F(MalformedInput, AFolderNamedLikeTheCheckpointIsRefusedNotDeleted) {
  fs::create_directories(results_ / "checkpoint.bin" / "deep");
  std::ofstream(results_ / "checkpoint.bin" / "notes.txt") << "precious\n";
  std::ofstream(results_ / "checkpoint.bin" / "deep" / "precious") << "precious\n";
  before_ = listing(results_);
  expect_refused(run_case("--threads 1"), {"-o", "checkpoint.bin", "not a settle checkpoint"});
}

TEST_F(MalformedInput, AFileOfTheUsersAmongTheCheckpointPartsIsRefusedNotDeleted) {
  fs::create_directories(results_ / "checkpoint.bin.parts" / "mydata");
  std::ofstream(results_ / "checkpoint.bin.parts" / "mydata" / "precious") << "precious\n";
  before_ = listing(results_);
  expect_refused(run_case("--threads 1"), {"-o", "checkpoint.bin.parts/mydata", "not a part of a settle checkpoint"});
}

TEST_F(MalformedInput, ASummaryJsonOfTheUsersIsRefusedNotDeleted) {
  std::ofstream(results_ / "summary.json") << "my own notes, not JSON\n";
  before_ = listing(results_);
  expect_refused(run_case("--threads 1"), {"-o", "summary.json", "not a summary settle run wrote"});
}

TEST_F(MalformedInput, ATimeSeriesOfTheUsersIsRefusedNotOverwritten) {
  std::ofstream(results_ / "timeseries.csv") << "time,height\n0,1\n";
  before_ = listing(results_);
  expect_refused(run_case("--threads 1"), {"-o", "timeseries.csv", "not a time series settle run wrote"});
}

// A JSON file of the user's under the sidecar's name: valid JSON, but not settle's column list.
TEST_F(MalformedInput, ATimeSeriesJsonOfTheUsersIsRefusedNotOverwritten) {
  std::ofstream(results_ / "timeseries.json") << "{\"columns\": [\"time\", \"height\"]}\n";
  before_ = listing(results_);
  expect_refused(run_case("--threads 1"), {"-o", "timeseries.json", "not the column list settle run writes"});
}

TEST_F(MalformedInput, ACaseNamedDotDotIsRefusedWithoutOutputDirectory) {
  // "...toml" leaves the case name "..": without -o its results would go to runs/.., the current
  // directory, whose summary.json (here the user's) a run removes.
  const fs::path work = root_ / "work";
  fs::create_directories(work);
  fs::copy_file(case_path(), work / "...toml");
  std::ofstream(work / "summary.json") << "keep\n";
  const Listing work_before = listing(work);
  const CliResult r = settle::test::run_settle("run", "...toml --threads 1", work);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("...toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("-o DIR"), std::string::npos) << r.err;
  EXPECT_EQ(listing(work), work_before) << r.err;
  EXPECT_FALSE(fs::exists(work / "runs"));
}

TEST_F(MalformedInput, AFreshRunRemovesTheEarlierRunsFilesAndKeepsTheUsers) {
  // The first run writes VTK frames and a checkpoint; the second (--overwrite), shorter and
  // without VTK, must leave none of them (a stale vtk/fluid.pvd would list frames of the other
  // run), but keep the user's files, also the one inside vtk/. Its checkpoint is its own end's.
  ASSERT_EQ(run_case("--threads 1 --set run.vtk_interval=5e-4 --set run.checkpoint_interval=5e-4").status, 0);
  ASSERT_TRUE(fs::exists(results_ / "vtk" / "fluid.pvd"));
  ASSERT_TRUE(fs::exists(results_ / "checkpoint.bin"));
  std::ofstream(results_ / "vtk" / "notes.txt") << "my notes on the frames\n";
  const CliResult r = run_case("--threads 1 --set run.end_time=5e-4 --overwrite");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::size_t end_at = r.err.find("checkpoint at the end, t = ");
  ASSERT_NE(end_at, std::string::npos) << r.err;
  const std::string end_time = r.err.substr(end_at + 27, r.err.find(' ', end_at + 27) - end_at - 27);
  const CliResult extended =
      settle::test::run_settle("run", "--restart " + results_.string() + " --set run.end_time=1e-3 --threads 1");
  EXPECT_NE(extended.err.find("at t = " + end_time + " s (step"), std::string::npos) << end_time << "\n"
                                                                                     << extended.err;
  EXPECT_FALSE(fs::exists(results_ / "vtk" / "fluid.pvd"));
  EXPECT_FALSE(fs::exists(results_ / "vtk" / "fluid_000000.vti"));
  EXPECT_TRUE(fs::exists(results_ / "vtk" / "notes.txt"));
  EXPECT_TRUE(fs::exists(results_ / "sentinel.txt"));
  EXPECT_TRUE(fs::exists(results_ / "summary.json"));
}

// ---- promise 2: a restart continues only the run its checkpoint belongs to ------------------------
// (the mesh, an edited series and an older checkpoint: tests/app/test_restart_cli.cpp)

TEST_F(MalformedInput, ARestartFromAnotherRunsCheckpointIsRefused) {
  // Two runs of the valid case, the second with a denser particle; its checkpoint copied into the
  // first one's directory used to continue it there, splicing its rows after the first one's.
  const fs::path other = root_ / "other";
  const std::string checkpointed = " --threads 1 --set run.checkpoint_interval=1e-3";
  ASSERT_EQ(run_case(checkpointed).status, 0);
  ASSERT_EQ(settle::test::run_settle(
                "run", case_path().string() + checkpointed + " --set particle.density=1200 -o " + other.string())
                .status,
            0);
  // The first run's series is the shorter (1465 bytes against 1496): its checkpoint in the second
  // run's directory passed the length check, the only one there was.
  ASSERT_LT(fs::file_size(results_ / "timeseries.csv"), fs::file_size(other / "timeseries.csv"));
  fs::copy_file(results_ / "checkpoint.bin", other / "checkpoint.bin", fs::copy_options::overwrite_existing);
  const Listing other_before = listing(other);
  before_ = listing(results_);
  expect_refused(settle::test::run_settle("run", "--restart " + other.string() + " --set run.end_time=2e-3"),
                 {"checkpoint.bin", "timeseries.csv is not the time series this checkpoint belongs to"});
  EXPECT_EQ(listing(other), other_before);
}

// ---- promise 4: no signal ends a run without a message -------------------------------------------
// (SIGINT, SIGTERM, SIGHUP: tests/app/test_restart_cli.cpp, with the continuation.)

TEST_F(MalformedInput, AFileSizeLimitIsReportedNotASilentDeath) {
  // ulimit -f (100 or 200 KiB: the shell's blocks are 512 or 1024 bytes) lets the time series and
  // the resolved case through, not the 7.5 MB checkpoint: SIGXFSZ killed the run (status 153, no
  // message, a checkpoint.bin.tmp left). Ignored, the write fails with EFBIG and is reported as a
  // full disk is: status 2, the file and the reason named, the temporary removed.
  if (std::getenv("SETTLE_LAUNCHER") != nullptr)
    GTEST_SKIP() << "under mpirun the limit binds mpirun's own files first (PMIx's shared-memory store fails with "
                    "OUT-OF-RESOURCE before settle starts)";
  const CliResult r = settle::test::run_settle(
      "run", case_path().string() + " -o " + results_.string() + " --threads 1 --set run.checkpoint_interval=5e-4", {},
      "ulimit -f 200; ");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("checkpoint"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(results_ / "checkpoint.bin.tmp"));
  EXPECT_FALSE(fs::exists(results_ / "summary.json"));
  EXPECT_TRUE(fs::exists(results_ / "sentinel.txt"));
}

// ---- positive controls: the valid case and its neighbours run ------------------------------------

TEST_F(MalformedInput, TheValidCaseRunsAndWritesBesideTheSentinel) {
  const CliResult r = run_case("--threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(results_ / "summary.json"));
  EXPECT_TRUE(fs::exists(results_ / "timeseries.csv"));
  EXPECT_TRUE(fs::exists(results_ / "sentinel.txt"));
  EXPECT_NE(r.err.find("memory estimate"), std::string::npos) << r.err;  // the estimate is printed
}

TEST_F(MalformedInput, ABuoyantParticleUnderAWallRuns) {
  const CliResult r = run_case("--threads 1 --set particle.density=900");
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST_F(MalformedInput, AWatertightMeshRuns) {
  write_case(valid_case(mesh_lines(data_file("cube_ascii.stl"))));
  const CliResult r = run_case("--threads 1");
  EXPECT_EQ(r.status, 0) << r.err;
}

}  // namespace test_malformed_inputs
