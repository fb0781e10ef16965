#include "body/projected_area.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace settle::body {
namespace {

struct Interval {
  int row;
  double begin, end;
};

// Where the horizontal line y cuts the projected triangle (a, b, c): [begin, end], or nothing.
bool cut_triangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, double y, double* begin,
                  double* end) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const Eigen::Vector2d* corners[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d& p = *corners[k];
    const Eigen::Vector2d& q = *corners[(k + 1) % 3];
    if ((p.y() - y) * (q.y() - y) > 0.0 || p.y() == q.y()) continue;
    const double x = p.x() + (y - p.y()) * (q.x() - p.x()) / (q.y() - p.y());
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  *begin = lo;
  *end = hi;
  return hi > lo;
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> orthonormal_complement(const Eigen::Vector3d& n) {
  // Start from the coordinate axis least aligned with n, so the cross product is well conditioned.
  Eigen::Index i = 0;
  n.cwiseAbs().minCoeff(&i);
  const Eigen::Vector3d u = n.cross(Eigen::Vector3d::Unit(i)).normalized();
  return {u, n.cross(u)};
}

double scanline_projected_area(const TriangleMesh& mesh, const Eigen::Vector3d& direction, int rows) {
  const auto [u0, v0] = orthonormal_complement(direction);
  // Turn the image axes by 1/golden-ratio radians (irrational in degrees and in turns).
  const double turn = 2.0 / (1.0 + std::sqrt(5.0));
  const Eigen::Vector3d u = std::cos(turn) * u0 + std::sin(turn) * v0;
  const Eigen::Vector3d v = direction.cross(u);
  std::vector<Eigen::Vector2d> projected(mesh.vertices.size());
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    projected[i] = {mesh.vertices[i].dot(u), mesh.vertices[i].dot(v)};
    y_lo = std::min(y_lo, projected[i].y());
    y_hi = std::max(y_hi, projected[i].y());
  }
  const double row_height = (y_hi - y_lo) / rows;
  if (!(row_height > 0.0)) return 0.0;

  std::vector<Interval> intervals;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    // Front-facing triangles alone cover the shadow of a closed surface: every line along the
    // view direction that meets the body leaves it through one of them.
    if (triangle_vector_area(mesh, static_cast<int>(t)).dot(direction) <= 0.0) continue;
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector2d& a = projected[tri[0]];
    const Eigen::Vector2d& b = projected[tri[1]];
    const Eigen::Vector2d& c = projected[tri[2]];
    const double t_lo = std::min({a.y(), b.y(), c.y()}), t_hi = std::max({a.y(), b.y(), c.y()});
    const int first = std::max(0, static_cast<int>(std::ceil((t_lo - y_lo) / row_height - 0.5)));
    const int last = std::min(rows - 1, static_cast<int>(std::floor((t_hi - y_lo) / row_height - 0.5)));
    for (int row = first; row <= last; ++row) {
      double begin = 0.0, end = 0.0;
      if (cut_triangle(a, b, c, y_lo + (row + 0.5) * row_height, &begin, &end)) intervals.push_back({row, begin, end});
    }
  }
  std::sort(intervals.begin(), intervals.end(), [](const Interval& p, const Interval& q) {
    return p.row < q.row || (p.row == q.row && p.begin < q.begin);
  });
  double covered = 0.0;
  for (std::size_t i = 0; i < intervals.size();) {
    const int row = intervals[i].row;
    double begin = intervals[i].begin, end = intervals[i].end;
    for (++i; i < intervals.size() && intervals[i].row == row; ++i) {
      if (intervals[i].begin > end) {
        covered += end - begin;
        begin = intervals[i].begin;
      }
      end = std::max(end, intervals[i].end);
    }
    covered += end - begin;
  }
  return covered * row_height;
}

double scanline_mean_projected_area_perpendicular(const TriangleMesh& mesh, const Eigen::Vector3d& axis, int directions,
                                                  int rows) {
  const auto [u, v] = orthonormal_complement(axis);
  double sum = 0.0;
  for (int k = 0; k < directions; ++k) {
    const double phi = std::numbers::pi * k / directions;
    sum += scanline_projected_area(mesh, std::cos(phi) * u + std::sin(phi) * v, rows);
  }
  return sum / directions;
}

}  // namespace settle::body
