// Immersed-body bookkeeping (coupling/immersed_body.hpp, coupling/simulation.hpp): markers at a
// pose, volume fractions, the force and torque balance between markers and grid, and the
// internal-momentum term for bodies at rest and in steady translation.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <random>

#include <omp.h>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "body/ellipsoid.hpp"
#include "body/shape_factory.hpp"
#include "coupling/immersed_body.hpp"
#include "coupling/immersed_boundary_coupling.hpp"
#include "coupling/simulation.hpp"
#include "ibm/forcing.hpp"
#include "lbm/solver.hpp"
#include "support/default_setup.hpp"

namespace test_immersed_body {

using namespace settle;
using namespace settle::coupling;

std::shared_ptr<const body::Shape> sphere(double diameter) {
  body::ShapeSpec spec;
  spec.shape = "sphere";
  spec.diameter = diameter;
  return body::make_shape(spec);
}

std::shared_ptr<const body::Shape> spheroid(double diameter, double aspect_ratio) {
  body::ShapeSpec spec;
  spec.shape = "spheroid";
  spec.diameter = diameter;
  spec.aspect_ratio = aspect_ratio;
  return body::make_shape(spec);
}

// Every cell within `radius` + `margin` of `centre` (lattice units): a box large enough for a
// sphere of that radius and its forcing stencils, independent of either coupling's own rule.
CellBox box_around(const Eigen::Vector3d& centre, double radius, double margin) {
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    const int lo = static_cast<int>(std::floor(centre[a] - radius - margin));
    const int hi = static_cast<int>(std::ceil(centre[a] + radius + margin));
    box.origin[static_cast<std::size_t>(a)] = lo;
    box.extent[static_cast<std::size_t>(a)] = hi - lo + 1;
  }
  return box;
}

TEST(Markers, PlacedMarkersAreTheRotatedBodyFrameMarkers) {
  const auto shape = spheroid(2.0e-3, 2.5);
  const double dx = 2.0e-4;
  const BodyMarkers markers = make_body_markers(*shape, dx, 0.3);
  ASSERT_GT(markers.size(), 50u);
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d centre(10.3, 11.7, 9.2), velocity(0.01, -0.02, 0.005), omega(0.001, 0.002, -0.003);
  const ibm::Markers placed = place_markers(markers, centre, rotation, velocity, omega);
  ASSERT_EQ(placed.size(), markers.size());
  for (std::size_t l = 0; l < placed.size(); ++l) {
    const Eigen::Vector3d arm = rotation * markers.offset_b[l];
    // Same arithmetic in a different order: agreement to round-off (1e-13 of lengths ~10).
    EXPECT_LT((placed.position[l] - (centre + arm)).norm(), 1e-13);
    EXPECT_LT((placed.target_velocity[l] - (velocity + omega.cross(arm))).norm(), 1e-15);
    // Rigid motion: the marker's distance from the centre is the body-frame one (round-off).
    EXPECT_NEAR((placed.position[l] - centre).norm(), markers.offset_b[l].norm(), 1e-12);
  }
}

TEST(Markers, RetractionMovesMarkersInsideBySpecifiedDistance) {
  const double dx = 1.0e-4, d = 16 * dx;
  const auto shape = sphere(d);
  const BodyMarkers markers = make_body_markers(*shape, dx, 0.4);
  // On a sphere the markers lie on the sphere of radius R - r_d (normals are radial): exact
  // to round-off of the marker construction (1e-12 cells).
  for (const Eigen::Vector3d& p : markers.offset_b) EXPECT_NEAR(p.norm(), 8.0 - 0.4, 1e-12);
  // The volumes tile the retracted shell: total = 4 pi (R - r_d)^2 (cells^3 for a 1-cell shell);
  // the Fibonacci areas sum to the exact sphere area (round-off).
  double volume = 0.0;
  for (double v : markers.volume) volume += v;
  EXPECT_NEAR(volume, 4.0 * std::numbers::pi * 7.6 * 7.6, 1e-9 * volume);
}

TEST(Markers, InteriorLatticeFillsTheBodyOneCellBelowTheSurfaceMarkers) {
  const double dx = 1.0e-4, d = 16 * dx;
  const auto shape = sphere(d);
  const BodyMarkers surface_only = make_body_markers(*shape, dx, 0.4);
  const BodyMarkers markers = make_body_markers(*shape, dx, 0.4, true);
  ASSERT_GT(markers.size(), surface_only.size());
  // The surface markers come first and are unchanged.
  for (std::size_t l = 0; l < surface_only.size(); ++l) EXPECT_EQ(markers.offset_b[l], surface_only.offset_b[l]);
  // Interior markers: integer offsets of unit volume, none closer than r_d + 1 = 1.4 cells to the
  // surface (radius 8), that is |p| <= 6.6.
  std::size_t interior = 0;
  for (std::size_t l = surface_only.size(); l < markers.size(); ++l, ++interior) {
    const Eigen::Vector3d& p = markers.offset_b[l];
    EXPECT_EQ(p, p.array().round().matrix());
    EXPECT_LE(p.norm(), 6.6 + 1e-12);
    EXPECT_EQ(markers.volume[l], 1.0);
  }
  // Lattice points in a ball of radius 6.6: the ball's volume 4/3 pi 6.6^3 = 1204 to within the
  // surface-layer fluctuation of a lattice count (Gauss circle problem in 3-D; well under 5%).
  const double ball = 4.0 / 3.0 * std::numbers::pi * std::pow(6.6, 3);
  EXPECT_NEAR(static_cast<double>(interior), ball, 0.05 * ball);
}

TEST(SolidCells, VolumeOfASphereIsRecovered) {
  const double dx = 1.0;
  const auto shape = sphere(12.0);
  const Eigen::Vector3d centre(20.37, 19.81, 20.12);
  const CellBox box = box_around(centre, 6.0, 1.5);
  const SolidCells cells = solid_cells(*shape, dx, box, centre, Eigen::Matrix3d::Identity());
  const double exact = std::numbers::pi / 6.0 * 12.0 * 12.0 * 12.0;
  // Kempe and Froehlich's corner formula is first order per cut cell but its errors largely
  // cancel over a closed surface; 1% of the volume (about 0.2 cells per cut cell of the ~450
  // cut cells would be 90 cells = 10%) is a loose bound that still catches a wrong sign, a
  // misplaced corner (half a cell shifts ~1/3 of the surface cells) or a wrong cell centre.
  EXPECT_NEAR(cells.volume(), exact, 0.01 * exact);
  for (double a : cells.alpha) {
    EXPECT_GT(a, 0.0);
    EXPECT_LE(a, 1.0);
  }
}

// The immersed boundary's tabulated distance (body::DistanceTable, a quarter cell) for the default
// case's prolate spheroid at 8 cells per d_eq, at random poses: no cell beyond the exact ones, and
// every volume fraction at most the exact distances' (the table never falls below a convex body's distance, and
// a corner's fraction falls as its distance rises: Kempe and Froehlich's alpha = I / (I + O) with I
// the inside corners' |phi| and O the outside ones'). The total falls by at most 1%: the table
// errs by 0.01-0.02 cells except near the tips' medial axis (tests/body/test_distance_table.cpp),
// a cut cell's |phi| sum to about 2 cells or more, so each fraction drops by about 0.01 at most,
// and 1% (2.7 cells over ~330 cut cells) would take an error ten times the bound everywhere.
TEST(SolidCells, TabulatedDistancesGiveFractionsJustBelowTheExactOnes) {
  const double dx_si = 1.26e-3 / 8.0;
  const auto shape = std::make_shared<const body::Ellipsoid>(body::Ellipsoid::spheroid(1.0e-3, 2.0));
  const body::DistanceTable table(shape, 0.25 * dx_si, 2.5 * dx_si, 2.5 * dx_si);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int pose = 0; pose < 20; ++pose) {
    const Eigen::Vector3d centre(24.0 + unit(rng), 24.0 + unit(rng), 48.0 + unit(rng));
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(3.0 * unit(rng), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized())
            .toRotationMatrix();
    const CellBox box = immersed_boundary_box(*shape, dx_si, ibm::DeltaKernel::Roma3, centre, rotation);
    const SolidCells exact = solid_cells(*shape, dx_si, box, centre, rotation);
    const SolidCells tabulated = solid_cells(table, dx_si, box, centre, rotation);
    // Both lists are in box order; a cell may drop out of the tabulated one (its fraction to 0).
    std::size_t t = 0;
    for (std::size_t n = 0; n < exact.cell.size(); ++n) {
      const bool listed = t < tabulated.cell.size() && tabulated.cell[t] == exact.cell[n];
      const double alpha = listed ? tabulated.alpha[t++] : 0.0;
      ASSERT_LE(alpha, exact.alpha[n] + 1e-6) << "pose " << pose << " cell " << n;
    }
    ASSERT_EQ(t, tabulated.cell.size()) << "a tabulated cell that the exact distances leave out";
    EXPECT_LT(exact.volume() - tabulated.volume(), 0.01 * exact.volume());
  }
}

TEST(Bookkeeping, GridForceAndTorqueEqualMinusTheMarkerReaction) {
  // A fixed sphere in a uniform stream: after one forcing pass, the force density spread into
  // the grid sums to the total marker force, and its moment about the centre to the markers'
  // moment, because both kernels satisfy sum phi = 1 and sum (r - j) phi = 0 exactly.
  lbm::SolverConfig config;
  config.nx = config.ny = config.nz = 24;
  config.tau = 0.8;
  auto solver = lbm::make_solver(config);
  const Eigen::Vector3d stream(0.03, -0.01, 0.02);
  solver->initialise([&](int, int, int) { return lbm::CellState{1.0, stream}; });
  const auto shape = sphere(8.0);
  const Eigen::Vector3d centre(11.3, 12.1, 11.8);
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const BodyMarkers body_markers = make_body_markers(*shape, 1.0, 0.4);
  const ibm::Markers markers =
      place_markers(body_markers, centre, rotation, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  const CellBox box = box_around(centre, 4.0, 1.5);
  ASSERT_TRUE(box_fits(box, *solver));
  ibm::LocalGrid grid = gather(*solver, box);
  const ibm::ForcingResult forcing = ibm::multi_direct_forcing(grid, markers, {ibm::DeltaKernel::Roma3, 3});
  solver->clear_forces();
  scatter_forces(*solver, grid);

  Eigen::Vector3d grid_force = Eigen::Vector3d::Zero(), grid_torque = Eigen::Vector3d::Zero();
  for (int z = 0; z < 24; ++z)
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        const Eigen::Vector3d f = solver->force(x, y, z);
        grid_force += f;
        grid_torque += (Eigen::Vector3d(x, y, z) - centre).cross(f);
      }
  const LatticeWrench reaction = marker_reaction(markers, forcing.marker_force, centre);
  ASSERT_GT(reaction.force.norm(), 1.0);  // the stream is really being stopped
  // Sums of ~10^4 terms of size ~1e-3: round-off ~1e-12 relative to the total.
  EXPECT_LT((grid_force + reaction.force).norm(), 1e-10 * reaction.force.norm());
  EXPECT_LT((grid_torque + reaction.torque).norm(), 1e-10 * reaction.force.norm() * 4.0);
  // With no change of internal momentum the hydrodynamic wrench is the reaction itself.
  const FluidMomentum same{Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector3d(-1.0, 0.5, 0.0)};
  const LatticeWrench w = hydrodynamic_wrench(reaction, same, same);
  EXPECT_EQ(w.force, reaction.force);
  EXPECT_EQ(w.torque, reaction.torque);
}

SimulationSetup lattice_like_setup(body::MotionKind motion, const Eigen::Vector3d& velocity) {
  SimulationSetup s = settle::test::default_setup();
  s.coupling = CouplingKind::immersed_boundary;
  s.shape = sphere(8.0);
  s.motion = motion;
  s.particle_density_si = 2.0;
  s.fluid_density_si = 1.0;
  s.tau = 0.8;
  s.dynamic_viscosity_si = (0.8 - 0.5) / 3.0;  // dx = dt = 1 with d = 8 m at 8 cells per diameter
  s.cells_per_diameter = 8.0;
  s.gravity_si = Eigen::Vector3d::Zero();
  s.domain_size_si = Eigen::Vector3d::Constant(24.0);
  s.boundaries = {lbm::Boundary::periodic, lbm::Boundary::periodic, lbm::Boundary::periodic};
  s.initial.position_si = Eigen::Vector3d(12.2, 11.9, 12.05);
  s.initial.velocity_si = velocity;
  return s;
}

TEST(Bookkeeping, BodyAtRestInFluidAtRestFeelsNoForce) {
  Simulation sim(lattice_like_setup(body::MotionKind::fixed, Eigen::Vector3d::Zero()));
  for (int i = 0; i < 5; ++i) {
    sim.step();
    // Fluid at rest has no slip: every term is zero up to round-off of the equilibrium
    // populations (1e-15 per cell; the forces are ~1e-14 of the unit scale).
    EXPECT_LT(sim.last_step().internal_rate.force_si.norm(), 1e-12);
    EXPECT_LT(sim.last_step().hydrodynamic.force_si.norm(), 1e-12);
    EXPECT_LT(sim.last_step().hydrodynamic.torque_si.norm(), 1e-12);
  }
}

TEST(Bookkeeping, SteadyTranslationHasNoInternalMomentumRateAfterTheStart) {
  const Eigen::Vector3d velocity(0.02, 0.0, 0.0);  // lattice units (dx = dt = 1)
  Simulation sim(lattice_like_setup(body::MotionKind::towed, velocity));
  sim.step();
  // Start: the fluid inside is accelerated from rest to the body velocity within a step or
  // two, so the rate starts at about the full internal momentum rho V U (~5.4) per step.
  const double start_rate = sim.last_step().internal_rate.force_si.norm();
  const double internal_momentum = std::numbers::pi / 6.0 * 512.0 * velocity.norm();
  EXPECT_GT(start_rate, 0.3 * internal_momentum);
  for (int i = 0; i < 100; ++i) sim.step();
  double largest_rate = 0.0;
  Eigen::Vector3d rate_sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < 50; ++i) {  // one full cell of travel: every sub-cell position
    sim.step();
    largest_rate = std::max(largest_rate, sim.last_step().internal_rate.force_si.norm());
    rate_sum += sim.last_step().internal_rate.force_si;
  }
  std::printf("start rate %.4g, internal momentum %.4g, largest later rate %.4g, mean over a cell %.4g\n", start_rate,
              internal_momentum, largest_rate, rate_sum.norm() / 50.0);
  // After the start the internal fluid moves with the body; what remains is the wobble of the
  // discrete volume sum of alpha as the sphere crosses the cells (first-order corner formula:
  // about 1% of V over a cell of travel, i.e. ~1e-3 of rho V U per step at 50 steps per cell).
  EXPECT_LT(largest_rate, 5e-3 * start_rate);
  // The wobble is periodic in the sub-cell position, so over one cell of travel it averages
  // out: the mean rate (what is left of a real change of internal momentum, here from the
  // slowly changing pressure of the periodic box that the body drags along) must be an order
  // of magnitude below the wobble's peak.
  EXPECT_LT(rate_sum.norm() / 50.0, 0.1 * largest_rate);
}

TEST(Determinism, FreeBodyIsTheSameWithOneAndTwoThreads) {
  // A free, heavy sphere released in fluid at rest, 30 steps with 1 and with 2 OpenMP threads, with
  // each coupling. The fluid kernel updates every cell independently of how cells are split among
  // threads, the momentum exchange's walls are found plane by plane and joined in plane order, the
  // immersed boundary spreads its forces slab by slab in marker order, and every other sum of the
  // couplings runs serially in a fixed order, so the results must be identical
  // bit for bit (no tolerance: any difference means an order-dependent reduction crept in). The
  // 32^3 box is above the size at which the fluid solver and the wall links go parallel.
  const auto run_with = [](int threads, CouplingKind coupling) {
    omp_set_num_threads(threads);
    SimulationSetup s = lattice_like_setup(body::MotionKind::free, Eigen::Vector3d::Zero());
    s.coupling = coupling;
    s.domain_size_si = Eigen::Vector3d::Constant(32.0);
    s.initial.position_si = Eigen::Vector3d(16.2, 15.9, 16.05);
    s.particle_density_si = 1.5;
    s.gravity_si = Eigen::Vector3d(0.0, 0.0, -1e-5);
    Simulation sim(s);
    for (int i = 0; i < 30; ++i) sim.step();
    return std::make_pair(sim.body().state().velocity_si, sim.last_step().hydrodynamic.torque_si);
  };
  const int original = omp_get_max_threads();
  for (const CouplingKind coupling : {CouplingKind::immersed_boundary, CouplingKind::momentum_exchange}) {
    const auto one = run_with(1, coupling);
    const auto two = run_with(2, coupling);
    ASSERT_GT(one.first.norm(), 0.0);  // it moved
    EXPECT_EQ(one.first, two.first);
    EXPECT_EQ(one.second, two.second);
  }
  omp_set_num_threads(original);
}

}  // namespace test_immersed_body
