// The momentum exchange's walls (coupling::body_walls) with the table that settles most cells'
// inside test (inside_table_for, a mesh's) are the walls the shape's own test gives: the same solid
// cells and links in the same order, the same q and wall velocities to the bit, at every pose of a
// short stretch of a body's motion (a step's worth of moving and turning, as the coupled step places
// the body), for the shipped grain at its 10 cells per d_eq and at the golden test's 6.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include "body/mesh_shape.hpp"
#include "body/shape_factory.hpp"
#include "coupling/momentum_exchange.hpp"
#include "lbm/solver.hpp"

namespace settle::coupling {
namespace {

void expect_same_walls(const BodyWalls& fast, const BodyWalls& reference) {
  ASSERT_EQ(fast.obstacle.solid_cells, reference.obstacle.solid_cells);
  ASSERT_EQ(fast.obstacle.links.size(), reference.obstacle.links.size());
  for (std::size_t k = 0; k < fast.obstacle.links.size(); ++k) {
    const lbm::WallLink& a = fast.obstacle.links[k];
    const lbm::WallLink& b = reference.obstacle.links[k];
    ASSERT_EQ(a.cell, b.cell);
    ASSERT_EQ(a.dir, b.dir);
    ASSERT_EQ(a.q, b.q);
    ASSERT_EQ(a.wall_velocity, b.wall_velocity);
    ASSERT_EQ(fast.crossing[k], reference.crossing[k]);
  }
}

TEST(MomentumExchangeWalls, TheInsideTableGivesTheWallsOfTheShapesOwnTest) {
  const auto grain = std::shared_ptr<const body::Shape>(
      body::load_mesh_shape(std::filesystem::path(SETTLE_SOURCE_DIR) / "cases/grain.stl"));
  const auto velocities = lbm::velocity_set(lbm::LatticeKind::D3Q19);
  for (const double cells_per_diameter : {6.0, 10.0}) {
    const double dx = grain->equivalent_diameter() / cells_per_diameter;
    const auto table = inside_table_for(grain, dx);
    ASSERT_TRUE(table);
    LatticePose pose;
    pose.centre = Eigen::Vector3d(30.37, 29.81, 40.12);
    pose.velocity = Eigen::Vector3d(0.011, -0.007, -0.043);           // cells per step
    pose.angular_velocity_n = Eigen::Vector3d(0.004, -0.009, 0.006);  // rad per step
    Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    std::size_t links = 0;
    for (int step = 0; step < 6; ++step) {
      pose.centre += pose.velocity;
      rotation = Eigen::AngleAxisd(pose.angular_velocity_n.norm(), pose.angular_velocity_n.normalized()) * rotation;
      pose.body_to_inertial = rotation;
      const CellBox box = momentum_exchange_box(*grain, dx, pose.centre, pose.body_to_inertial);
      const BodyWalls fast = body_walls(*grain, dx, box, pose, velocities, lbm::WallRule::bouzidi, table.get());
      const BodyWalls reference = body_walls(*grain, dx, box, pose, velocities, lbm::WallRule::bouzidi);
      expect_same_walls(fast, reference);
      links = fast.obstacle.links.size();
    }
    EXPECT_GT(links, 100u) << cells_per_diameter;
  }
}

// Shapes whose inside test is a closed form take no table.
TEST(MomentumExchangeWalls, ClosedFormShapesTakeNoTable) {
  for (const char* shape : {"sphere", "superellipsoid", "cuboid"}) {
    body::ShapeSpec spec;
    spec.shape = shape;
    if (spec.shape == "sphere") spec.diameter = 1.0;
    if (spec.shape == "superellipsoid") spec.semi_axes = {{0.5, 0.5, 0.5}}, spec.exponents = {{0.4, 0.4}};
    if (spec.shape == "cuboid") spec.size = {{1.0, 1.0, 1.0}};
    EXPECT_FALSE(inside_table_for(std::shared_ptr<const body::Shape>(body::make_shape(spec)), 0.1)) << shape;
  }
}

}  // namespace
}  // namespace settle::coupling
