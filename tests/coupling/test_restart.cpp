// Restart from a checkpoint continues bit for bit (coupling/checkpoint_state.hpp): a run of N + M
// steps and a run of N steps, a checkpoint, a fresh Simulation restored from it and M steps agree
// in every bit of the body state (attitude chart included), the last step's forces, the moving
// window and the whole fluid, at an odd and at an even N (the two AA parities), and through a
// particle-wall contact, and in float storage on D3Q27. Also: the
// caller's data comes back unchanged, a checkpoint for another case is refused with the quantity
// named, a corrupt one is refused, and a refused restore leaves the simulation untouched.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "body/shape_factory.hpp"
#include "coupling/checkpoint_state.hpp"
#include "coupling/simulation.hpp"
#include "support/default_setup.hpp"

namespace settle::coupling {
namespace test_restart {

namespace fs = std::filesystem;

// A tilted prolate spheroid settling in a column with the moving window on, in lattice-like SI
// units (d_eq = 8 m over 8 cells, rho_f = 1, nu = 1/6 with tau = 1, so dx = dt = 1). It starts
// moving downwards and turning, pitched past pi/4 in a set-1 chart, so that within the first
// steps the integrator switches to set 2 and the window shifts at least once: the checkpoint then
// holds a non-default Euler set and a moved window (shifts near steps 47 and 78). 24 x 24 x 40 cells: above the solver's
// threshold for OpenMP threads, so the threaded kernels are the ones checked.
SimulationSetup settling_spheroid() {
  SimulationSetup s = settle::test::default_setup();
  s.coupling = CouplingKind::immersed_boundary;  // MomentumExchangeContinuesBitForBit... covers the other
  body::ShapeSpec spec;
  spec.shape = "spheroid";
  spec.aspect_ratio = 2.0;
  spec.diameter = 8.0 / std::cbrt(2.0);  // volume-equivalent diameter 8
  s.shape = std::shared_ptr<const body::Shape>(body::make_shape(spec));
  s.motion = body::MotionKind::free;
  s.particle_density_si = 1.5;
  s.fluid_density_si = 1.0;
  s.dynamic_viscosity_si = 1.0 / 6.0;
  s.gravity_si = Eigen::Vector3d(0.0, 0.0, -8.0e-3);  // settles at ~0.03 cells per step
  s.domain_size_si = Eigen::Vector3d(24.0, 24.0, 40.0);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::no_slip};
  s.follow_particle = true;
  s.cells_per_diameter = 8.0;
  s.tau = 1.0;
  // Schiller-Naumann overestimates this speed (0.065 + start speed + rotation) at tau = 1; the
  // actual speed stays below 0.04 (Mach 0.07): the bound only has to let the case through.
  s.max_lattice_velocity = 0.15;
  s.initial.position_si = Eigen::Vector3d(12.0, 12.0, 22.0);
  s.initial.velocity_si = Eigen::Vector3d(0.0, 0.0, -0.03);
  s.initial.attitude = attitude::Attitude::from_set1(0.2, 0.9, 0.1);
  s.initial.angular_velocity_b_si = Eigen::Vector3d(0.0, 0.002, 0.001);
  return s;
}

// The same spheroid without the moving window, released 1.6 cells above the contact distance of
// the bottom wall: the particle-wall contact force acts from step 13 on (tip resting on the wall).
// 24 x 24 x 28 cells.
SimulationSetup spheroid_near_wall() {
  SimulationSetup s = settling_spheroid();
  s.follow_particle = false;
  s.domain_size_si.z() = 28.0;
  const Eigen::Vector3d down_b = s.initial.attitude.body_to_inertial().transpose() * Eigen::Vector3d(0.0, 0.0, -1.0);
  s.initial.position_si.z() = s.shape->support(down_b) + 1.6;
  return s;
}

std::uint64_t bits(double value) { return std::bit_cast<std::uint64_t>(value); }

// Bitwise equality of doubles (EXPECT_EQ on doubles would call -0 and +0 equal).
void expect_same_bits(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const char* what) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bits(a[i]), bits(b[i])) << what << "[" << i << "]: " << a[i] << " vs " << b[i];
}

// Everything observable that must agree bit for bit; the fluid's whole population buffer (ghost
// layer included) and its forces are compared as raw bytes.
void expect_identical(const Simulation& a, const Simulation& b) {
  EXPECT_EQ(a.steps(), b.steps());
  const auto& sa = a.body().state();
  const auto& sb = b.body().state();
  expect_same_bits(sa.position_si, sb.position_si, "position");
  expect_same_bits(sa.velocity_si, sb.velocity_si, "velocity");
  expect_same_bits(sa.angular_velocity_b_si, sb.angular_velocity_b_si, "angular velocity");
  EXPECT_EQ(sa.attitude.set(), sb.attitude.set());
  expect_same_bits(sa.attitude.angles(), sb.attitude.angles(), "attitude angles");
  expect_same_bits(a.last_step().hydrodynamic.force_si, b.last_step().hydrodynamic.force_si, "force");
  expect_same_bits(a.last_step().hydrodynamic.torque_si, b.last_step().hydrodynamic.torque_si, "torque");
  expect_same_bits(a.last_step().internal_rate.force_si, b.last_step().internal_rate.force_si, "internal rate");
  EXPECT_EQ(bits(a.last_step().slip_max_si), bits(b.last_step().slip_max_si));
  expect_same_bits(a.last_step().contact.force_si, b.last_step().contact.force_si, "contact force");
  expect_same_bits(a.last_step().contact.torque_si, b.last_step().contact.torque_si, "contact torque");
  EXPECT_EQ(bits(a.last_step().wall_gap_si), bits(b.last_step().wall_gap_si));
  expect_same_bits(a.frame().window_origin_si, b.frame().window_origin_si, "window origin");

  const lbm::FluidState fa = a.fluid().export_state();
  const lbm::FluidState fb = b.fluid().export_state();
  EXPECT_EQ(fa.step_count, fb.step_count);
  ASSERT_EQ(fa.populations.size(), fb.populations.size());
  EXPECT_EQ(std::memcmp(fa.populations.data(), fb.populations.data(), fa.populations.size()), 0)
      << "population buffers differ";
  EXPECT_EQ(fa.forced_cells, fb.forced_cells);
  ASSERT_EQ(fa.forced_values.size(), fb.forced_values.size());
  for (std::size_t k = 0; k < fa.forced_values.size(); ++k)
    ASSERT_EQ(bits(fa.forced_values[k]), bits(fb.forced_values[k]));
  // A few cells through the public queries (density and velocity include the cell's force).
  const int nx = a.fluid().nx(), ny = a.fluid().ny(), nz = a.fluid().nz();
  for (const auto& c : {std::array{0, 0, 0}, std::array{nx / 2, ny / 2, nz / 2}, std::array{5, ny - 7, nz - 7},
                        std::array{nx - 1, ny - 1, nz - 1}}) {
    const lbm::CellState ca = a.fluid().cell_state(c[0], c[1], c[2]);
    const lbm::CellState cb = b.fluid().cell_state(c[0], c[1], c[2]);
    EXPECT_EQ(bits(ca.density), bits(cb.density));
    expect_same_bits(ca.velocity, cb.velocity, "cell velocity");
  }
}

class RestartTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("settle_restart_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(RestartTest, ContinuesBitForBitAtBothParities) {
  constexpr std::int64_t kTotal = 100;
  Simulation reference(settling_spheroid());
  for (std::int64_t n = 0; n < kTotal; ++n) reference.step();

  // A second run writes checkpoints at an even and an odd step; it is never compared after that,
  // so writing cannot mask a change it might make to the state it reads.
  CheckpointCallerData caller;
  caller.resolved_case = "[particle]\nshape = \"spheroid\"\n";
  Simulation first(settling_spheroid());
  for (const std::int64_t at : {60, 61}) {
    while (first.steps() < at) first.step();
    caller.values["checkpoint_step"] = static_cast<double>(at);
    write_checkpoint(first, caller, dir_ / ("checkpoint_" + std::to_string(at) + ".bin"));
    // The case must exercise what is saved: a switched Euler set, a moved window, forced cells.
    ASSERT_EQ(first.body().state().attitude.set(), attitude::EulerSet::set2);
    ASSERT_NE(first.frame().window_origin_si.z(), 0.0) << "the window has not moved: enlarge the run";
    ASSERT_GT(first.fluid().forced_cell_count(), 0u);
  }

  for (const std::int64_t at : {60, 61}) {
    SCOPED_TRACE("checkpoint at step " + std::to_string(at));
    const SimulationCheckpoint checkpoint(dir_ / ("checkpoint_" + std::to_string(at) + ".bin"));
    EXPECT_EQ(checkpoint.steps(), at);
    // The clock is steps x dt, not a sum of steps (dt is 1 s here only to round-off: 8 / cbrt(2)
    // cubed back depends on the compiler's cbrt).
    EXPECT_EQ(bits(checkpoint.time_si()), bits(static_cast<double>(at) * first.units().dt_si()));
    EXPECT_EQ(checkpoint.caller().values.at("checkpoint_step"), static_cast<double>(at));
    EXPECT_EQ(checkpoint.caller().resolved_case, caller.resolved_case);

    Simulation restarted(settling_spheroid());
    checkpoint.restore(restarted);
    EXPECT_EQ(restarted.steps(), at);
    EXPECT_EQ(restarted.fluid().step_count(), at);
    while (restarted.steps() < kTotal) restarted.step();
    expect_identical(reference, restarted);
  }
  // The window moved after the checkpoints too, so the restored anchor and origin were used.
  EXPECT_NE(reference.frame().window_origin_si.z(), first.frame().window_origin_si.z());
}

TEST_F(RestartTest, ContinuesBitForBitThroughAWallContact) {
  constexpr std::int64_t kTotal = 35, kCheckpoint = 21;
  Simulation reference(spheroid_near_wall());
  for (std::int64_t n = 0; n < kTotal; ++n) reference.step();

  Simulation first(spheroid_near_wall());
  ASSERT_TRUE(first.wall_contact().has_value());
  while (first.steps() < kCheckpoint) first.step();
  ASSERT_GT(first.last_step().contact.force_si.z(), 0.0) << "no contact at the checkpoint: move the start";
  write_checkpoint(first, {}, dir_ / "checkpoint.bin");

  Simulation restarted(spheroid_near_wall());
  SimulationCheckpoint(dir_ / "checkpoint.bin").restore(restarted);
  // The contact in progress comes back with the impact speed that fixes its wet restitution.
  const auto& saved = first.wall_contact()->impact_speeds_si();
  const auto& restored = restarted.wall_contact()->impact_speeds_si();
  ASSERT_EQ(saved.size(), restored.size());
  EXPECT_TRUE(std::any_of(saved.begin(), saved.end(), [](const auto& v) { return v.has_value(); }));
  for (std::size_t i = 0; i < saved.size(); ++i) {
    ASSERT_EQ(saved[i].has_value(), restored[i].has_value()) << "wall " << i;
    if (saved[i]) {
      EXPECT_EQ(bits(*saved[i]), bits(*restored[i])) << "wall " << i;
    }
  }
  while (restarted.steps() < kTotal) restarted.step();
  expect_identical(reference, restarted);
}

TEST_F(RestartTest, ContinuesBitForBitInFloatStorageOnD3Q27) {
  SimulationSetup setup = settling_spheroid();
  setup.lattice = lbm::LatticeKind::D3Q27;
  setup.precision = lbm::Precision::float32;
  constexpr std::int64_t kTotal = 20, kCheckpoint = 11;
  Simulation reference(setup);
  for (std::int64_t n = 0; n < kTotal; ++n) reference.step();
  Simulation first(setup);
  while (first.steps() < kCheckpoint) first.step();
  write_checkpoint(first, {}, dir_ / "checkpoint.bin");
  Simulation restarted(setup);
  SimulationCheckpoint(dir_ / "checkpoint.bin").restore(restarted);
  while (restarted.steps() < kTotal) restarted.step();
  EXPECT_EQ(restarted.fluid().export_state().layout.element_bytes, 4u);
  expect_identical(reference, restarted);
}

TEST_F(RestartTest, MomentumExchangeContinuesBitForBitAtBothParities) {
  // The sharp coupling's state between steps is the fluid's solid cells (which cells were solid
  // decides which are refilled next): they come back from the checkpoint, at either parity, with
  // the window moving over them.
  SimulationSetup setup = settling_spheroid();
  setup.coupling = CouplingKind::momentum_exchange;
  // With the covered cells' torque: a restored run's first impose must count its covered cells as
  // the uninterrupted run's step does.
  setup.covered_cell_torque = true;
  constexpr std::int64_t kTotal = 100;
  Simulation reference(setup);
  for (std::int64_t n = 0; n < kTotal; ++n) reference.step();
  Simulation first(setup);
  std::map<std::int64_t, std::vector<std::array<int, 3>>> solid_at_checkpoint;
  for (const std::int64_t at : {60, 61}) {
    while (first.steps() < at) first.step();
    write_checkpoint(first, {}, dir_ / ("checkpoint_" + std::to_string(at) + ".bin"));
    solid_at_checkpoint[at] = first.fluid().solid_cell_list();
    ASSERT_GT(first.fluid().solid_cell_count(), 0u);
    ASSERT_NE(first.frame().window_origin_si.z(), 0.0) << "the window has not moved: enlarge the run";
  }
  for (const std::int64_t at : {60, 61}) {
    SCOPED_TRACE("checkpoint at step " + std::to_string(at));
    Simulation restarted(setup);
    SimulationCheckpoint(dir_ / ("checkpoint_" + std::to_string(at) + ".bin")).restore(restarted);
    EXPECT_EQ(restarted.fluid().solid_cell_list(), solid_at_checkpoint.at(at));
    while (restarted.steps() < kTotal) restarted.step();
    expect_identical(reference, restarted);
    EXPECT_EQ(restarted.fluid().solid_cell_list(), reference.fluid().solid_cell_list());
  }
}

TEST_F(RestartTest, PairedBodyStepsContinueBitForBitFromTheEndOfAPair) {
  // With the body moved once per two lattice steps a checkpoint holds the state between two body
  // steps; half-way through one it is refused rather than written without the held walls.
  SimulationSetup setup = settling_spheroid();
  setup.coupling = CouplingKind::momentum_exchange;
  setup.covered_cell_torque = true;
  setup.lattice_steps_per_body_step = 2;
  constexpr std::int64_t kTotal = 100;
  Simulation reference(setup);
  for (std::int64_t n = 0; n < kTotal; ++n) reference.step();
  Simulation first(setup);
  while (first.steps() < 60) first.step();
  ASSERT_TRUE(first.between_body_steps());
  const fs::path file = dir_ / "checkpoint_60.bin";
  write_checkpoint(first, {}, file);
  ASSERT_NE(first.frame().window_origin_si.z(), 0.0) << "the window has not moved: enlarge the run";
  first.step();
  EXPECT_FALSE(first.between_body_steps());
  EXPECT_THROW(write_checkpoint(first, {}, dir_ / "checkpoint_61.bin"), std::logic_error);
  EXPECT_FALSE(fs::exists(dir_ / "checkpoint_61.bin"));

  Simulation restarted(setup);
  SimulationCheckpoint(file).restore(restarted);
  while (restarted.steps() < kTotal) restarted.step();
  expect_identical(reference, restarted);
  // And the pairs moved the body: it differs from the one-step scheme's.
  setup.lattice_steps_per_body_step = 1;
  Simulation one_step(setup);
  for (std::int64_t n = 0; n < kTotal; ++n) one_step.step();
  EXPECT_NE(one_step.body().state().position_si, reference.body().state().position_si);
}

TEST(FluidState, ImportRefusesAForeignStateAndChangesNothing) {
  lbm::SolverConfig config;
  config.nx = 8;
  config.ny = 6;
  config.nz = 5;
  auto source = lbm::make_solver(config);
  source->initialise([](int x, int, int) { return lbm::CellState{1.0 + 0.01 * x, Eigen::Vector3d(0.01, 0.0, 0.0)}; });
  source->set_force(1, 2, 3, Eigen::Vector3d(1e-4, 0.0, 0.0));
  source->step();

  auto target = lbm::make_solver(config);
  target->initialise([](int, int, int) { return lbm::CellState{}; });
  const auto unchanged = [&] {
    EXPECT_EQ(target->step_count(), 0);
    EXPECT_EQ(target->forced_cell_count(), 0u);
    EXPECT_EQ(target->cell_density(3, 3, 3), 1.0);  // the rest state, exactly (stored as f - w = 0)
  };

  lbm::SolverConfig other = config;
  other.nz = 6;
  auto larger = lbm::make_solver(other);
  EXPECT_THROW(target->import_state(larger->export_state()), std::invalid_argument);
  unchanged();

  lbm::FluidState repeated = source->export_state();
  repeated.forced_cells.push_back(repeated.forced_cells.front());
  repeated.forced_values.insert(repeated.forced_values.end(), {0.0, 0.0, 0.0});
  EXPECT_THROW(target->import_state(repeated), std::invalid_argument);
  unchanged();

  lbm::FluidState short_buffer = source->export_state();
  short_buffer.populations = short_buffer.populations.first(short_buffer.populations.size() - 8);
  EXPECT_THROW(target->import_state(short_buffer), std::invalid_argument);
  unchanged();

  // The real thing is accepted and reproduces the source's cells and forces exactly.
  target->import_state(source->export_state());
  EXPECT_EQ(target->step_count(), 1);
  EXPECT_EQ(bits(target->cell_density(4, 2, 1)), bits(source->cell_density(4, 2, 1)));
  expect_same_bits(target->force(1, 2, 3), source->force(1, 2, 3), "force");
  expect_same_bits(target->cell_velocity(1, 2, 3), source->cell_velocity(1, 2, 3), "velocity");
}

TEST_F(RestartTest, RestoredSimulationAnswersQueriesAsTheOriginal) {
  Simulation original(settling_spheroid());
  for (int n = 0; n < 7; ++n) original.step();
  write_checkpoint(original, {}, dir_ / "checkpoint.bin");
  Simulation restarted(settling_spheroid());
  SimulationCheckpoint(dir_ / "checkpoint.bin").restore(restarted);
  expect_identical(original, restarted);
  // The superficial velocity sweeps every cell with its force and the solid cells at the pose.
  expect_same_bits(original.superficial_velocity_si(), restarted.superficial_velocity_si(), "superficial velocity");
  ASSERT_EQ(original.timers().entries().size(), restarted.timers().entries().size());
  for (std::size_t k = 0; k < original.timers().entries().size(); ++k) {
    EXPECT_EQ(original.timers().entries()[k].first, restarted.timers().entries()[k].first);
    EXPECT_EQ(bits(original.timers().entries()[k].second), bits(restarted.timers().entries()[k].second));
  }
}

TEST_F(RestartTest, CallerDataComesBackUnchanged) {
  Simulation sim(settling_spheroid());
  CheckpointCallerData caller;
  caller.resolved_case = std::string("# every byte\n\0\xff", 15);
  caller.values = {{"output.next_index", 42.0}, {"accumulator.sum", -0.0}, {"tiny", 4.9e-324}};
  caller.blobs["samples"] = {std::byte{0}, std::byte{1}, std::byte{255}};
  caller.blobs["empty"] = {};
  write_checkpoint(sim, caller, dir_ / "checkpoint.bin");
  const SimulationCheckpoint checkpoint(dir_ / "checkpoint.bin");
  EXPECT_EQ(checkpoint.caller().resolved_case, caller.resolved_case);
  ASSERT_EQ(checkpoint.caller().values.size(), caller.values.size());
  for (const auto& [name, value] : caller.values)
    EXPECT_EQ(bits(checkpoint.caller().values.at(name)), bits(value)) << name;
  EXPECT_EQ(checkpoint.caller().blobs, caller.blobs);
  EXPECT_EQ(checkpoint.steps(), 0);
  EXPECT_FALSE(checkpoint.written_by().empty());
}

TEST_F(RestartTest, CheckpointOfAnotherCaseIsRefusedAndChangesNothing) {
  Simulation sim(settling_spheroid());
  for (int n = 0; n < 3; ++n) sim.step();
  write_checkpoint(sim, {}, dir_ / "checkpoint.bin");
  const SimulationCheckpoint checkpoint(dir_ / "checkpoint.bin");

  SimulationSetup taller = settling_spheroid();
  taller.domain_size_si.z() = 44.0;
  Simulation other(taller);
  const lbm::FluidState before = other.fluid().export_state();
  const std::vector<std::byte> populations_before(before.populations.begin(), before.populations.end());
  try {
    checkpoint.restore(other);
    FAIL() << "restored into a taller grid";
  } catch (const CheckpointError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("grid cells along z is 40 in the checkpoint and 44"), std::string::npos) << message;
  }
  EXPECT_EQ(other.steps(), 0);
  const lbm::FluidState after = other.fluid().export_state();
  EXPECT_EQ(after.step_count, 0);
  EXPECT_TRUE(std::equal(after.populations.begin(), after.populations.end(), populations_before.begin()));

  SimulationSetup denser = settling_spheroid();
  denser.particle_density_si = 1.6;
  Simulation heavier(denser);
  try {
    checkpoint.restore(heavier);
    FAIL() << "restored a particle of another density";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("particle mass"), std::string::npos) << e.what();
  }
}

TEST_F(RestartTest, CorruptOrTruncatedCheckpointIsRefused) {
  Simulation sim(settling_spheroid());
  sim.step();
  const fs::path file = dir_ / "checkpoint.bin";
  write_checkpoint(sim, {}, file);
  const auto size = fs::file_size(file);
  {
    // One flipped bit in the middle of the populations, the largest section.
    std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(static_cast<std::streamoff>(size / 2));
    char c = 0;
    io.get(c);
    io.seekp(static_cast<std::streamoff>(size / 2));
    io.put(static_cast<char>(c ^ 0x04));
  }
  try {
    SimulationCheckpoint checkpoint(file);
    FAIL() << "accepted a corrupt checkpoint";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("section 'fluid/populations' fails its CRC-32 check"), std::string::npos)
        << e.what();
  }
  fs::resize_file(file, size - 1000);
  try {
    SimulationCheckpoint checkpoint(file);
    FAIL() << "accepted a truncated checkpoint";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
}

}  // namespace test_restart
}  // namespace settle::coupling
