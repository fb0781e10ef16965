#include "body/convex_distance.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "body/contact.hpp"
#include "body/cuboid.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"

namespace settle::body {
namespace {

// Iteration caps: GJK converges in a handful of steps on polytopes and linearly on curved bodies
// (about 20 steps for the tolerance); EPA adds about one polytope vertex per step.
constexpr int kMaxGjkIterations = 100;
constexpr int kMaxEpaIterations = 200;
// A face whose area (volume) is below this fraction of the product of its edges' lengths is flat
// (angles below 1e-12 rad): it is skipped and its sub-faces are used instead.
constexpr double kFlatFace = 1.0e-12;

// A support point of the Minkowski difference D = A - B and the points of A and B it came from.
struct Vertex {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
};

// -1, 0 or 1: a zero component of the direction takes the middle of a face or an edge, as
// support_point does, any other the extreme point.
double sign_or_zero(double x) { return static_cast<double>((x > 0.0) - (x < 0.0)); }

// A body point where the support function is attained, body frame, direction of any non-zero length.
// GJK needs points of the body that are the exact maximisers, and near an edge its directions
// converge into the cone where support_point's central differences blend the kink (header), so the
// shapes with closed forms use them.
Eigen::Vector3d body_support_point(const Shape& shape, const Eigen::Vector3d& direction) {
  if (const auto* cuboid = dynamic_cast<const Cuboid*>(&shape))
    return 0.5 * cuboid->size().cwiseProduct(direction.unaryExpr(&sign_or_zero));
  if (const auto* ellipsoid = dynamic_cast<const Ellipsoid*>(&shape)) {
    const Eigen::Vector3d a2u = ellipsoid->semi_axes().cwiseAbs2().cwiseProduct(direction);
    return a2u / std::sqrt(direction.dot(a2u));
  }
  if (const auto* cylinder = dynamic_cast<const Cylinder*>(&shape)) {
    const double radial = direction.head<2>().norm();
    const Eigen::Vector2d rim =
        radial > 0.0 ? Eigen::Vector2d(cylinder->radius() * direction.head<2>() / radial) : Eigen::Vector2d::Zero();
    return {rim.x(), rim.y(), 0.5 * cylinder->length() * sign_or_zero(direction.z())};
  }
  return support_point(shape, direction);
}

Eigen::Vector3d placed_support_point(const PlacedShape& s, const Eigen::Vector3d& direction) {
  return s.position_si + s.body_to_inertial * body_support_point(*s.shape, s.body_to_inertial.transpose() * direction);
}

Vertex support_vertex(const PlacedShape& a, const PlacedShape& b, const Eigen::Vector3d& direction) {
  Vertex v;
  v.a = placed_support_point(a, direction);
  v.b = placed_support_point(b, -direction);
  v.w = v.a - v.b;
  return v;
}

// A face of a simplex (up to four vertices) and the barycentric weights of a point in it.
struct Simplex {
  std::array<Vertex, 4> vertices;
  std::array<double, 4> weights{};
  int size = 0;
  Eigen::Vector3d point() const {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < size; ++i) p += weights[i] * vertices[i].w;
    return p;
  }
};

// Barycentric weights of the origin's projection onto the affine hull of `points` (1 to 4 of them),
// from signed lengths, areas and volumes (the cross products keep thin faces accurate to round-off
// over the sine of their angles; normal equations would square that), or none when the face is flat.
std::optional<std::array<double, 4>> affine_weights(const std::array<Eigen::Vector3d, 4>& p, int count) {
  std::array<double, 4> weights{1.0, 0.0, 0.0, 0.0};
  if (count == 2) {
    const Eigen::Vector3d e = p[1] - p[0];
    const double length2 = e.squaredNorm();
    if (!(length2 > 0.0)) return std::nullopt;
    weights[1] = -p[0].dot(e) / length2;
    weights[0] = 1.0 - weights[1];
  } else if (count == 3) {
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double n2 = n.squaredNorm();
    if (!(n2 > kFlatFace * kFlatFace * (p[1] - p[0]).squaredNorm() * (p[2] - p[0]).squaredNorm())) return std::nullopt;
    const Eigen::Vector3d q = n * (n.dot(p[0]) / n2);  // the origin projected onto the plane
    for (int i = 0; i < 3; ++i) weights[i] = n.dot((p[(i + 1) % 3] - q).cross(p[(i + 2) % 3] - q)) / n2;
  } else if (count == 4) {
    const auto volume = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& d) { return (b - a).dot((c - a).cross(d - a)); };
    const double total = volume(p[0], p[1], p[2], p[3]);
    const double edges = (p[1] - p[0]).norm() * (p[2] - p[0]).norm() * (p[3] - p[0]).norm();
    if (!(std::abs(total) > kFlatFace * edges)) return std::nullopt;
    const Eigen::Vector3d o = Eigen::Vector3d::Zero();
    weights = {volume(o, p[1], p[2], p[3]) / total, volume(p[0], o, p[2], p[3]) / total,
               volume(p[0], p[1], o, p[3]) / total, volume(p[0], p[1], p[2], o) / total};
  }
  return weights;
}

// The face of the simplex `vertices` selected by the bit mask, with the origin's affine projection
// onto it, or none when the face is flat or the projection falls outside it.
std::optional<Simplex> project_onto_face(const std::array<Vertex, 4>& vertices, int count, unsigned mask) {
  Simplex face;
  std::array<Eigen::Vector3d, 4> points;
  for (int i = 0; i < count; ++i)
    if (mask & (1u << i)) {
      points[face.size] = vertices[i].w;
      face.vertices[face.size++] = vertices[i];
    }
  const auto weights = affine_weights(points, face.size);
  if (!weights) return std::nullopt;
  face.weights = *weights;
  for (int i = 0; i < face.size; ++i)
    if (face.weights[i] < 0.0) return std::nullopt;
  return face;
}

// The point of the simplex nearest the origin, on the smallest face holding it (GJK's distance
// sub-algorithm by trying every face: the nearest point of a simplex is the affine projection onto
// the face whose relative interior holds it, and every other admissible projection is a point of the
// simplex, hence no nearer). A full tetrahedron is returned only when it contains the origin.
Simplex nearest_face(const std::array<Vertex, 4>& vertices, int count) {
  Simplex best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (int face_size = 1; face_size <= count; ++face_size)
    for (unsigned mask = 1; mask < (1u << count); ++mask) {
      if (std::popcount(mask) != face_size) continue;
      const auto face = project_onto_face(vertices, count, mask);
      if (!face) continue;
      const double distance = face->point().norm();
      if (distance < best_distance) {
        best_distance = distance;
        best = *face;
      }
    }
  return best;
}

struct GjkResult {
  Simplex simplex;
  bool origin_inside = false;  // D contains the origin to within the tolerance
  int iterations = 0;
};

GjkResult gjk(const PlacedShape& a, const PlacedShape& b, double tolerance) {
  Eigen::Vector3d start = b.position_si - a.position_si;  // -(the centre of D): towards the origin
  if (start.squaredNorm() == 0.0) start = Eigen::Vector3d::UnitX();
  GjkResult r;
  r.simplex.vertices[0] = support_vertex(a, b, start.normalized());
  r.simplex.weights[0] = 1.0;
  r.simplex.size = 1;
  for (r.iterations = 1; r.iterations <= kMaxGjkIterations; ++r.iterations) {
    const Eigen::Vector3d v = r.simplex.point();
    const double upper = v.norm();
    if (upper <= tolerance) {
      r.origin_inside = true;
      return r;
    }
    const Vertex w = support_vertex(a, b, -v / upper);
    // Lower bound of dist(0, D): min over D of (v/|v|) . x, reached at w.
    if (upper - v.dot(w.w) / upper <= tolerance) return r;
    std::array<Vertex, 4> grown = r.simplex.vertices;
    grown[r.simplex.size] = w;
    const Simplex next = nearest_face(grown, r.simplex.size + 1);
    if (next.size == 4) {
      r.simplex = next;
      r.origin_inside = true;
      return r;
    }
    // No progress: the support points' round-off floor is reached.
    if (next.size == 0 || !(next.point().norm() < upper)) return r;
    r.simplex = next;
  }
  return r;
}

// Completes GJK's final simplex to a tetrahedron of non-zero volume inside D with support points in
// the directions it does not yet span; false when D is flat.
bool grow_to_tetrahedron(const PlacedShape& a, const PlacedShape& b, std::vector<Vertex>& points, double scale) {
  const double tiny = kFlatFace * scale;
  const auto add_farthest = [&](const std::vector<Eigen::Vector3d>& directions, auto distance_of) {
    Vertex best;
    double best_distance = -1.0;
    for (const auto& d : directions) {
      const Vertex v = support_vertex(a, b, d);
      if (distance_of(v.w) > best_distance) {
        best_distance = distance_of(v.w);
        best = v;
      }
    }
    if (!(best_distance > tiny)) return false;
    points.push_back(best);
    return true;
  };
  if (points.size() == 4) {
    const Eigen::Vector3d p0 = points[0].w;
    const double volume = (points[1].w - p0).cross(points[2].w - p0).dot(points[3].w - p0);
    if (std::abs(volume) > tiny * scale * scale) return true;
    points.pop_back();
  }
  if (points.size() == 1) {
    const Eigen::Vector3d p0 = points[0].w;
    std::vector<Eigen::Vector3d> axes;
    for (int i = 0; i < 3; ++i) axes.insert(axes.end(), {Eigen::Vector3d::Unit(i), -Eigen::Vector3d::Unit(i)});
    if (!add_farthest(axes, [&](const Eigen::Vector3d& w) { return (w - p0).norm(); })) return false;
  }
  if (points.size() == 2) {
    const Eigen::Vector3d p0 = points[0].w, line = (points[1].w - p0).normalized();
    Eigen::Index smallest = 0;
    line.cwiseAbs().minCoeff(&smallest);
    const Eigen::Vector3d t1 = line.cross(Eigen::Vector3d::Unit(smallest)).normalized(), t2 = line.cross(t1);
    if (!add_farthest({t1, -t1, t2, -t2}, [&](const Eigen::Vector3d& w) {
          const Eigen::Vector3d r = w - p0;
          return (r - line * line.dot(r)).norm();
        }))
      return false;
  }
  const Eigen::Vector3d p0 = points[0].w;
  const Eigen::Vector3d normal = (points[1].w - p0).cross(points[2].w - p0).normalized();
  return add_farthest({normal, -normal}, [&](const Eigen::Vector3d& w) { return std::abs(normal.dot(w - p0)); });
}

struct Face {
  std::array<int, 3> v{};
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // outward from D
  double distance = 0.0;                             // of its plane from the origin
};

std::optional<Face> make_face(const std::vector<Vertex>& points, int i, int j, int k) {
  const Eigen::Vector3d n = (points[j].w - points[i].w).cross(points[k].w - points[i].w);
  const double length = n.norm();
  if (!(length > 0.0)) return std::nullopt;
  Face f{{i, j, k}, n / length, 0.0};
  f.distance = f.normal.dot(points[i].w);
  return f;
}

// The four outward faces of the tetrahedron points[0..3].
std::vector<Face> tetrahedron_faces(std::vector<Vertex>& points) {
  const Eigen::Vector3d p0 = points[0].w;
  if ((points[1].w - p0).cross(points[2].w - p0).dot(points[3].w - p0) > 0.0) std::swap(points[1], points[2]);
  // Now (1 - 0) x (2 - 0) points away from vertex 3: faces listed counter-clockwise seen from outside.
  std::vector<Face> faces;
  for (const auto& [i, j, k] : {std::array{0, 1, 2}, std::array{0, 3, 1}, std::array{0, 2, 3}, std::array{1, 3, 2}})
    if (const auto f = make_face(points, i, j, k)) faces.push_back(*f);
  return faces;
}

// Replaces the faces that see vertex `m` by the fan from m to their horizon.
bool expand(std::vector<Face>& faces, const std::vector<Vertex>& points, int m) {
  std::vector<std::pair<int, int>> horizon;
  std::vector<Face> kept;
  for (const Face& f : faces) {
    if (f.normal.dot(points[m].w - points[f.v[0]].w) <= 0.0) {
      kept.push_back(f);
      continue;
    }
    for (int e = 0; e < 3; ++e) {
      const std::pair<int, int> edge{f.v[e], f.v[(e + 1) % 3]};
      const auto reverse = std::find(horizon.begin(), horizon.end(), std::pair{edge.second, edge.first});
      if (reverse != horizon.end()) {
        horizon.erase(reverse);
      } else {
        horizon.push_back(edge);
      }
    }
  }
  for (const auto& [i, j] : horizon) {
    const auto f = make_face(points, i, j, m);
    if (!f) return false;
    kept.push_back(*f);
  }
  faces = std::move(kept);
  return !faces.empty();
}

// A candidate normal (from A towards B) with its closest points and their distance along it.
struct Candidate {
  Eigen::Vector3d normal;
  Eigen::Vector3d point_a, point_b;
  double distance = 0.0;
};

Candidate from_weights(const Eigen::Vector3d& normal, const Simplex& s) {
  Candidate c{normal, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.0};
  for (int i = 0; i < s.size; ++i) {
    c.point_a += s.weights[i] * s.vertices[i].a;
    c.point_b += s.weights[i] * s.vertices[i].b;
  }
  c.distance = normal.dot(c.point_b - c.point_a);
  return c;
}

// EPA from GJK's final simplex: the face of D's boundary nearest the origin. None when D is flat or
// the origin is not inside the starting tetrahedron (then the bodies are apart by more than the
// tolerance and GJK's answer stands).
std::optional<Candidate> epa(const PlacedShape& a, const PlacedShape& b, const Simplex& start, double tolerance,
                             int& iterations) {
  const double scale = a.shape->bounding_radius() + b.shape->bounding_radius();
  std::vector<Vertex> points(start.vertices.begin(), start.vertices.begin() + start.size);
  if (!grow_to_tetrahedron(a, b, points, scale)) return std::nullopt;
  std::vector<Face> faces = tetrahedron_faces(points);
  if (faces.size() != 4) return std::nullopt;
  for (const Face& f : faces)
    if (f.distance < -tolerance) return std::nullopt;
  Face nearest = faces.front();
  for (int it = 0; it < kMaxEpaIterations; ++it) {
    ++iterations;
    nearest = *std::min_element(faces.begin(), faces.end(),
                                [](const Face& x, const Face& y) { return x.distance < y.distance; });
    const Vertex w = support_vertex(a, b, nearest.normal);
    // The face is a lower bound of the depth along its normal, h_D(normal) = normal . w an upper one.
    if (nearest.normal.dot(w.w) - nearest.distance <= tolerance) break;
    points.push_back(w);
    if (!expand(faces, points, static_cast<int>(points.size()) - 1)) break;
  }
  std::array<Vertex, 4> triangle{points[nearest.v[0]], points[nearest.v[1]], points[nearest.v[2]], Vertex{}};
  // The origin's projection onto the nearest face lies in it; round-off may put it a hair outside,
  // so the weights are taken unclipped from the affine projection.
  Simplex face;
  face.vertices = triangle;
  face.size = 3;
  const auto weights = affine_weights({triangle[0].w, triangle[1].w, triangle[2].w, Eigen::Vector3d::Zero()}, 3);
  if (!weights) return std::nullopt;
  face.weights = *weights;
  // D = A - B: its outward normal at the boundary point nearest the origin is the direction B
  // must move to separate, i.e. the normal from A towards B.
  return from_weights(nearest.normal, face);
}

double support_along(const PlacedShape& s, const Eigen::Vector3d& direction) {
  return direction.dot(s.position_si) + s.shape->support(s.body_to_inertial.transpose() * direction);
}

const Ellipsoid* as_sphere(const Shape& shape) {
  const auto* ellipsoid = dynamic_cast<const Ellipsoid*>(&shape);
  return ellipsoid && ellipsoid->is_sphere() ? ellipsoid : nullptr;
}

}  // namespace

double separation_along(const PlacedShape& a, const PlacedShape& b, const Eigen::Vector3d& direction) {
  // min over B of u . x minus max over A of u . x.
  return -support_along(b, -direction) - support_along(a, direction);
}

ConvexSeparation sphere_separation(const Eigen::Vector3d& centre_a_si, double radius_a_si,
                                   const Eigen::Vector3d& centre_b_si, double radius_b_si) {
  const Eigen::Vector3d between = centre_b_si - centre_a_si;
  const double length = between.norm();
  ConvexSeparation s;
  s.normal = length > 0.0 ? Eigen::Vector3d(between / length) : Eigen::Vector3d::UnitX();
  s.distance_si = length - radius_a_si - radius_b_si;
  s.point_a_si = centre_a_si + radius_a_si * s.normal;
  s.point_b_si = centre_b_si - radius_b_si * s.normal;
  return s;
}

ConvexSeparation support_separation(const PlacedShape& a, const PlacedShape& b) {
  if (!a.shape || !b.shape) throw std::invalid_argument("convex distance: a shape is missing");
  const double scale = a.shape->bounding_radius() + b.shape->bounding_radius();
  const double tolerance = kRelativeTolerance * scale;
  const GjkResult g = gjk(a, b, tolerance);
  std::vector<Candidate> candidates;
  const Eigen::Vector3d v = g.simplex.point();
  if (!g.origin_inside) candidates.push_back(from_weights(-v.normalized(), g.simplex));
  int iterations = g.iterations;
  if (g.origin_inside || v.norm() < kNearContact * scale)
    if (const auto c = epa(a, b, g.simplex, tolerance, iterations)) candidates.push_back(*c);
  if (candidates.empty()) {
    // D flat or EPA refused: fall back on the line of centres (a lower bound all the same).
    const Eigen::Vector3d between = b.position_si - a.position_si;
    const Eigen::Vector3d n = between.norm() > 0.0 ? Eigen::Vector3d(between.normalized()) : Eigen::Vector3d::UnitX();
    candidates.push_back({n, placed_support_point(a, n), placed_support_point(b, -n), separation_along(a, b, n)});
  }
  // Each normal's separation s(n) is a lower bound of d: the larger one is nearer the truth.
  const Candidate* best = &candidates.front();
  for (const Candidate& c : candidates)
    if (separation_along(a, b, c.normal) > separation_along(a, b, best->normal)) best = &c;
  return {best->distance, best->normal, best->point_a, best->point_b, iterations};
}

ConvexSeparation convex_distance(const PlacedShape& a, const PlacedShape& b) {
  if (!a.shape || !b.shape) throw std::invalid_argument("convex distance: a shape is missing");
  const Ellipsoid* sphere_a = as_sphere(*a.shape);
  const Ellipsoid* sphere_b = as_sphere(*b.shape);
  if (sphere_a && sphere_b)
    return sphere_separation(a.position_si, sphere_a->semi_axes().x(), b.position_si, sphere_b->semi_axes().x());
  return support_separation(a, b);
}

}  // namespace settle::body
