// The tree's segment queries (the momentum exchange's link crossings on meshes) against closed
// forms: the crossings of a segment with a box are where it meets the faces' planes (the slab
// method), and a segment through an edge or a corner is found there; the walk restricted to the
// leaves near the segment's start finds what the walk from the root finds.
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "body/triangle_bvh.hpp"
#include "shape_test_support.hpp"

namespace settle::body {
namespace test_triangle_bvh {

using Hits = std::vector<TriangleBvh::SegmentHit>;

Hits hits_of(const TriangleBvh& tree, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  std::array<TriangleBvh::SegmentHit, 16> buffer;
  const int count = tree.segment_hits(from, to, buffer);
  EXPECT_GE(count, 0);
  Hits hits(buffer.begin(), buffer.begin() + std::max(count, 0));
  std::sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  return hits;
}

// Where the line from o along d enters and leaves the box [-half, half] (t0 < t1; empty when it
// misses): the slab method, exact but for round-off.
bool slab_interval(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& half, double& t0,
                   double& t1) {
  t0 = -1e300, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double u = (-half[a] - o[a]) / d[a], v = (half[a] - o[a]) / d[a];
    t0 = std::max(t0, std::min(u, v));
    t1 = std::min(t1, std::max(u, v));
  }
  return t0 < t1;
}

// Random segments through a box's neighbourhood: each crossing the slab method puts in [0, 1] is a
// hit (round-off of the plane intersection: 1e-14 of the unit segment), entering at the first and
// leaving at the second, and there are no others (a segment meets a convex body at most twice;
// corners and edges, met with probability zero here, are the next test's).
TEST(TriangleBvh, SegmentHitsOfABoxAreWhereItMeetsTheFacesPlanes) {
  const Eigen::Vector3d half(1.5, 1.0, 0.5);
  const TriangleBvh tree(testing::box_mesh(2.0 * half));
  std::mt19937_64 rng(5);
  int crossings = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d from = testing::random_in_box(rng, 1.5 * half);
    const Eigen::Vector3d to = from + 1.2 * testing::random_unit(rng);
    double t0 = 0.0, t1 = 0.0;
    std::vector<std::pair<double, bool>> expected;
    if (slab_interval(from, to - from, half, t0, t1)) {
      if (t0 >= 0.0 && t0 <= 1.0) expected.emplace_back(t0, true);
      if (t1 >= 0.0 && t1 <= 1.0) expected.emplace_back(t1, false);
    }
    const Hits hits = hits_of(tree, from, to);
    ASSERT_EQ(hits.size(), expected.size()) << from.transpose() << " -> " << to.transpose();
    for (std::size_t k = 0; k < hits.size(); ++k) {
      EXPECT_NEAR(hits[k].t, expected[k].first, 1e-14);
      EXPECT_EQ(hits[k].entering, expected[k].second);
    }
    crossings += static_cast<int>(hits.size());
  }
  EXPECT_GT(crossings, 500);  // enough segments met the box to mean something
}

// A segment through an edge or a corner of the box is not lost between the triangles that meet
// there: each of them reports it (within the hit margin), all entering, at the closed-form t.
TEST(TriangleBvh, ASegmentThroughAnEdgeOrACornerIsFound) {
  const Eigen::Vector3d half(1.5, 1.0, 0.5);
  const TriangleBvh tree(testing::box_mesh(2.0 * half));
  // Through the edge x = 1.5, y = 1 at z = 0.1 (t = 0.5), and through the corner (1.5, 1, 0.5).
  for (const Eigen::Vector3d& target : {Eigen::Vector3d(1.5, 1.0, 0.1), Eigen::Vector3d(1.5, 1.0, 0.5)}) {
    const Eigen::Vector3d from = target + Eigen::Vector3d(0.4, 0.3, 0.2), to = target - Eigen::Vector3d(0.4, 0.3, 0.2);
    const Hits hits = hits_of(tree, from, to);
    ASSERT_GE(hits.size(), 1u) << target.transpose();
    for (const auto& hit : hits) {
      EXPECT_NEAR(hit.t, 0.5, 1e-12) << target.transpose();
      EXPECT_TRUE(hit.entering) << target.transpose();
    }
  }
  // In the plane of a face the segment meets no triangle there (det = 0), only the box's other
  // faces it crosses: from outside along the top face's plane z = 0.5 into the side x = 1.5.
  const Hits along = hits_of(tree, Eigen::Vector3d(2.0, 0.0, 0.5), Eigen::Vector3d(1.0, 0.0, 0.5));
  for (const auto& hit : along) EXPECT_NEAR(hit.t, 0.5, 1e-12);
}

// The leaves within a segment's length of its start hold every triangle it meets: the restricted
// walk returns the same hits, to the bit (the same arithmetic on the same triangles), on an
// icosphere of 1280 triangles about as wide as the links (the grain's proportion).
TEST(TriangleBvh, LeavesNearTheStartHoldEveryHit) {
  const double radius = 10.0;
  const TriangleBvh tree(testing::icosphere(3, radius));
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> shell(radius - 1.5, radius + 1.5);
  int compared = 0, hit_count = 0, empty_starts = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d from = shell(rng) * testing::random_unit(rng);
    const Eigen::Vector3d to = from + std::sqrt(2.0) * testing::random_unit(rng);
    TriangleBvh::LeavesNear leaves;
    tree.leaves_near(from, std::sqrt(2.0), leaves);
    // No leaf within reach (a start up to 1.5 from a surface the segment is sqrt(2) long) is a
    // valid answer: then no triangle can be met, which the comparison below checks.
    ASSERT_GE(leaves.count, 0);
    empty_starts += leaves.count == 0 ? 1 : 0;
    std::array<TriangleBvh::SegmentHit, 16> buffer;
    const int count = tree.segment_hits(leaves, to, buffer);
    Hits near(buffer.begin(), buffer.begin() + count);
    std::sort(near.begin(), near.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
    const Hits all = hits_of(tree, from, to);
    ASSERT_EQ(near.size(), all.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
      EXPECT_EQ(near[k].t, all[k].t);
      EXPECT_EQ(near[k].entering, all[k].entering);
    }
    ++compared;
    hit_count += static_cast<int>(all.size());
  }
  EXPECT_EQ(compared, 2000);
  EXPECT_GT(hit_count, 300);
  // Most starts lie within reach of a leaf: the restricted walk is exercised, not bypassed.
  EXPECT_LT(empty_starts, 200);
}

}  // namespace test_triangle_bvh
}  // namespace settle::body
