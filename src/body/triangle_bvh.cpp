#include "body/triangle_bvh.hpp"

#include <algorithm>
#include <limits>

namespace settle::body {
namespace {

constexpr int kLeafSize = 4;

double box_distance_squared(const Eigen::Vector3d& p, const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) {
  const Eigen::Vector3d below = (lower - p).cwiseMax(0.0);
  const Eigen::Vector3d above = (p - upper).cwiseMax(0.0);
  return (below + above).squaredNorm();
}

// Whether the segment o + t d, t in [0, 1] widened by the margin, meets the box (`inverse` = 1 / d,
// taken once per segment).
bool segment_meets_box(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& inverse,
                       const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, double margin) {
  double enter = -margin, leave = 1.0 + margin;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lower[a] || o[a] > upper[a]) return false;
      continue;
    }
    const double t0 = (lower[a] - o[a]) * inverse[a], t1 = (upper[a] - o[a]) * inverse[a];
    enter = std::max(enter, std::min(t0, t1));
    leave = std::min(leave, std::max(t0, t1));
  }
  // The margin again, for the round-off of the slabs when the segment touches a face of the box.
  return enter <= leave + margin;
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c, TriangleFeature* feature) {
  using Kind = TriangleFeature::Kind;
  auto set = [&](Kind kind, int index) {
    if (feature) *feature = {kind, index};
  };
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return set(Kind::vertex, 0), a;

  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return set(Kind::vertex, 1), b;

  const double vc = d1 * d4 - d3 * d2;  // barycentric weight of c, unnormalised
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return set(Kind::edge, 0), Eigen::Vector3d(a + d1 / (d1 - d3) * ab);

  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return set(Kind::vertex, 2), c;

  const double vb = d5 * d2 - d1 * d6;  // weight of b
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return set(Kind::edge, 2), Eigen::Vector3d(a + d2 / (d2 - d6) * ac);

  const double va = d3 * d6 - d5 * d4;  // weight of a
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    return set(Kind::edge, 1), Eigen::Vector3d(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b));
  }
  const double scale = 1.0 / (va + vb + vc);
  set(Kind::face, 0);
  return a + ab * (vb * scale) + ac * (vc * scale);
}

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) {
  const int count = static_cast<int>(mesh.triangles.size());
  std::vector<int> order(count);
  std::vector<Eigen::Vector3d> centres(count);
  for (int t = 0; t < count; ++t) {
    order[t] = t;
    const auto& tri = mesh.triangles[t];
    centres[t] = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
  }
  nodes_.reserve(2 * static_cast<std::size_t>(count) / kLeafSize + 2);
  if (count > 0) build(order, centres, 0, count);
  corners_.resize(count);
  triangle_ids_ = order;
  for (int slot = 0; slot < count; ++slot) {
    const auto& tri = mesh.triangles[order[slot]];
    corners_[slot] = {mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]};
  }
  // Children always follow their parent in nodes_, so one backward pass fills every box.
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    Node& node = nodes_[i];
    if (node.count > 0) {
      node.lower = node.upper = corners_[node.first][0];
      for (int slot = node.first; slot < node.first + node.count; ++slot) {
        for (const auto& corner : corners_[slot]) {
          node.lower = node.lower.cwiseMin(corner);
          node.upper = node.upper.cwiseMax(corner);
        }
      }
    } else {
      node.lower = nodes_[i + 1].lower.cwiseMin(nodes_[node.first].lower);
      node.upper = nodes_[i + 1].upper.cwiseMax(nodes_[node.first].upper);
    }
  }
}

int TriangleBvh::build(std::vector<int>& order, std::vector<Eigen::Vector3d>& centres, int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  Eigen::Vector3d lo = centres[order[begin]], hi = lo;
  for (int i = begin; i < end; ++i) {
    lo = lo.cwiseMin(centres[order[i]]);
    hi = hi.cwiseMax(centres[order[i]]);
  }
  Eigen::Index axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                   [&](int x, int y) { return centres[x](axis) < centres[y](axis); });
  build(order, centres, begin, middle);  // left child: index + 1
  const int right = build(order, centres, middle, end);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

TriangleBvh::Hit TriangleBvh::closest(const Eigen::Vector3d& p) const {
  Hit best;
  best.distance_squared = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best;
  struct Entry {
    int node;
    double bound;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {0, box_distance_squared(p, nodes_[0].lower, nodes_[0].upper)};
  while (top > 0) {
    const Entry entry = stack[--top];
    if (entry.bound >= best.distance_squared) continue;
    const Node& node = nodes_[entry.node];
    if (node.count > 0) {
      for (int slot = node.first; slot < node.first + node.count; ++slot) {
        const auto& c = corners_[slot];
        TriangleFeature feature;
        const Eigen::Vector3d q = closest_point_on_triangle(p, c[0], c[1], c[2], &feature);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best.distance_squared) best = {d2, triangle_ids_[slot], feature, q};
      }
      continue;
    }
    const int left = entry.node + 1, right = node.first;
    const double dl = box_distance_squared(p, nodes_[left].lower, nodes_[left].upper);
    const double dr = box_distance_squared(p, nodes_[right].lower, nodes_[right].upper);
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    if (dl < dr) {
      stack[top++] = {right, dr};
      stack[top++] = {left, dl};
    } else {
      stack[top++] = {left, dl};
      stack[top++] = {right, dr};
    }
  }
  return best;
}

bool TriangleBvh::triangle_hits(const Node& leaf, const Eigen::Vector3d& from, const Eigen::Vector3d& d,
                                std::span<SegmentHit> hits, int& found) const {
  for (int slot = leaf.first; slot < leaf.first + leaf.count; ++slot) {
    const auto& c = corners_[slot];
    const Eigen::Vector3d e1 = c[1] - c[0], e2 = c[2] - c[0];
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);  // -d . (e1 x e2): positive when entering
    if (det == 0.0) continue;
    const Eigen::Vector3d s = from - c[0];
    const double u = s.dot(p) / det;
    if (u < -kHitMargin || u > 1.0 + kHitMargin) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    if (v < -kHitMargin || u + v > 1.0 + kHitMargin) continue;
    const double t = e2.dot(q) / det;
    if (t < -kHitMargin || t > 1.0 + kHitMargin) continue;
    if (found == static_cast<int>(hits.size())) return false;
    hits[static_cast<std::size_t>(found++)] = {t, det > 0.0};
  }
  return true;
}

int TriangleBvh::segment_hits(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                              std::span<SegmentHit> hits) const {
  if (nodes_.empty()) return 0;
  const Eigen::Vector3d d = to - from;
  const Eigen::Vector3d inverse = d.cwiseInverse();
  int found = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int index = stack[--top];
    const Node& node = nodes_[index];
    if (!segment_meets_box(from, d, inverse, node.lower, node.upper, kHitMargin)) continue;
    if (node.count > 0) {
      if (!triangle_hits(node, from, d, hits, found)) return -1;
    } else {
      stack[top++] = node.first;
      stack[top++] = index + 1;
    }
  }
  return found;
}

void TriangleBvh::leaves_near(const Eigen::Vector3d& p, double radius, LeavesNear& near) const {
  near.point = p;
  near.count = 0;
  if (nodes_.empty()) return;
  const double reach_squared = radius * radius * kReachMargin;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int index = stack[--top];
    const Node& node = nodes_[index];
    const double distance_squared = box_distance_squared(p, node.lower, node.upper);
    if (distance_squared > reach_squared) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = index + 1;
      continue;
    }
    if (near.count == LeavesNear::kCapacity) {
      near.count = -1;
      return;
    }
    const auto at = static_cast<std::size_t>(near.count++);
    const double widen = kHitMargin * (node.upper - node.lower).maxCoeff();
    near.node[at] = index;
    near.distance_squared[at] = distance_squared;
    for (std::size_t a = 0; a < 3; ++a) {
      near.lower[a][at] = node.lower[static_cast<Eigen::Index>(a)] - p[static_cast<Eigen::Index>(a)] - widen;
      near.upper[a][at] = node.upper[static_cast<Eigen::Index>(a)] - p[static_cast<Eigen::Index>(a)] + widen;
    }
  }
}

int TriangleBvh::segment_hits(const LeavesNear& near, const Eigen::Vector3d& to, std::span<SegmentHit> hits) const {
  const Eigen::Vector3d d = to - near.point;
  // The slabs of a direction component that is zero would give 0 * inf = NaN where the segment
  // lies in a face's plane; the widened boxes make a tiny stand-in for it exact: the point is then
  // strictly inside the slab (no bound) or strictly outside (none of its triangles can be met).
  std::array<double, 3> inverse{};
  for (std::size_t a = 0; a < 3; ++a) {
    const double component = d[static_cast<Eigen::Index>(a)];
    inverse[a] = 1.0 / (component != 0.0 ? component : 1e-300);
  }
  const double reach_squared = d.squaredNorm() * kReachMargin;
  // The slab test of every leaf, without branches (vectorised), then the triangles of those met.
  std::array<unsigned char, LeavesNear::kCapacity> met{};
  for (int i = 0; i < near.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    double enter = -kHitMargin, leave = 1.0 + kHitMargin;
    for (std::size_t a = 0; a < 3; ++a) {
      const double t0 = near.lower[a][k] * inverse[a], t1 = near.upper[a][k] * inverse[a];
      enter = std::max(enter, std::min(t0, t1));
      leave = std::min(leave, std::max(t0, t1));
    }
    met[k] = static_cast<unsigned char>((enter <= leave + kHitMargin) & (near.distance_squared[k] <= reach_squared));
  }
  int found = 0;
  for (int i = 0; i < near.count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (met[k] && !triangle_hits(nodes_[static_cast<std::size_t>(near.node[k])], near.point, d, hits, found)) return -1;
  }
  return found;
}

}  // namespace settle::body
