#include "body/point_grid.hpp"

namespace settle::body {

PointGrid::PointGrid(const std::vector<Eigen::Vector3d>& points, double cell_size) : points_(points), cell_(cell_size) {
  if (points_.empty()) {
    start_.assign(2, 0);
    return;
  }
  Eigen::Vector3d lo = points_.front(), hi = lo;
  for (const auto& p : points_) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  constexpr double kMaxCells = 1.6e7;
  const Eigen::Vector3d extent = hi - lo;
  double cells = 1.0;
  for (int i = 0; i < 3; ++i) cells *= std::floor(extent(i) / cell_) + 1.0;
  if (cells > kMaxCells) cell_ *= std::cbrt(cells / kMaxCells) * 1.01;
  origin_ = lo;
  for (int i = 0; i < 3; ++i) dims_(i) = static_cast<int>(std::floor(extent(i) / cell_)) + 1;
  const std::size_t cell_count = static_cast<std::size_t>(dims_.prod());
  std::vector<std::size_t> owner(points_.size());
  start_.assign(cell_count + 1, 0);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3i c = cell_of(points_[i]).cwiseMax(0).cwiseMin(dims_ - Eigen::Vector3i::Ones());
    owner[i] = index_of(c.x(), c.y(), c.z());
    ++start_[owner[i] + 1];
  }
  for (std::size_t k = 0; k < cell_count; ++k) start_[k + 1] += start_[k];
  members_.resize(points_.size());
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < points_.size(); ++i) members_[fill[owner[i]]++] = static_cast<std::uint32_t>(i);
}

}  // namespace settle::body
