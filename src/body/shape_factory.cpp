#include "body/shape_factory.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/core.h>

#include "body/cuboid.hpp"
#include "body/cylinder.hpp"
#include "body/ellipsoid.hpp"
#include "body/mesh_shape.hpp"
#include "body/superellipsoid.hpp"
#include "common/error.hpp"

namespace settle::body {
namespace {

constexpr double kMinRatio = 1e-3;
constexpr double kMaxRatio = 1e3;
// The lengths of an analytic shape (m): its volume grows as the cube of its size, its second moments
// as the fifth power, and the ellipsoid's surface area takes 1/a^2; with the ratios above up to 1e3
// (a spheroid's polar axis up to 1e3 diameters), sizes within [1e-50, 1e50] m keep all of them
// normal doubles (1e53^5 = 1e265) (a sphere of 1e-160 m made the
// surface area's Carlson integral fail, one of 1e120 m a volume of inf). Meshes have their own
// check (mesh_shape.cpp), of the same powers.
constexpr double kMinLength_m = 1e-50;
constexpr double kMaxLength_m = 1e50;

// The keys each shape takes.
std::vector<std::string_view> keys_of(std::string_view shape) {
  if (shape == "sphere") return {"diameter"};
  if (shape == "spheroid") return {"diameter", "aspect_ratio"};
  if (shape == "ellipsoid") return {"semi_axes"};
  if (shape == "cylinder") return {"diameter", "length"};
  if (shape == "cuboid") return {"size"};
  if (shape == "superellipsoid") return {"semi_axes", "exponents"};
  return {"file", "scale"};  // mesh
}

std::vector<std::string_view> keys_present(const ShapeSpec& spec) {
  std::vector<std::string_view> keys;
  if (spec.diameter) keys.push_back("diameter");
  if (spec.aspect_ratio) keys.push_back("aspect_ratio");
  if (spec.semi_axes) keys.push_back("semi_axes");
  if (spec.exponents) keys.push_back("exponents");
  if (spec.length) keys.push_back("length");
  if (spec.size) keys.push_back("size");
  if (spec.file) keys.push_back("file");
  if (spec.scale) keys.push_back("scale");
  return keys;
}

class Validator {
 public:
  Validator(const ShapeSpec& spec, const ShapeFactoryOptions& options) : spec_(spec), options_(options) {}

  std::string name(std::string_view key) const { return options_.key_name(key); }

  template <class T>
  const T& required(std::string_view key, const std::optional<T>& value) const {
    if (!value) throw InputError(fmt::format("{}: required for shape '{}'", name(key), spec_.shape));
    return *value;
  }
  double positive(std::string_view key, double value, const std::string& where = "") const {
    if (!std::isfinite(value) || value <= 0.0) {
      throw InputError(fmt::format("{}{}: must be finite and > 0, got {}", name(key), where, value));
    }
    return value;
  }
  /// A length of the shape (m): finite, > 0 and within [kMinLength_m, kMaxLength_m].
  double length(std::string_view key, double value, const std::string& where = "") const {
    positive(key, value, where);
    if (value < kMinLength_m || value > kMaxLength_m)
      throw InputError(
          fmt::format("{}{}: {:g} m is too {} for double precision (its volume and moments of inertia, "
                      "the third and fifth powers of the size, would {}); give a length in [{:g}, {:g}] m",
                      name(key), where, value, value < kMinLength_m ? "small" : "large",
                      value < kMinLength_m ? "underflow" : "overflow", kMinLength_m, kMaxLength_m));
    return value;
  }
  Eigen::Vector3d positive3(std::string_view key, const std::array<double, 3>& values) const {
    const Eigen::Vector3d v(values[0], values[1], values[2]);
    for (int i = 0; i < 3; ++i) length(key, v(i), fmt::format(" (value {} of 3)", i + 1));
    ratio(key, v.maxCoeff() / v.minCoeff(), "the largest to the smallest value");
    return v;
  }
  void ratio(std::string_view key, double value, std::string_view what) const {
    if (!(value >= kMinRatio && value <= kMaxRatio)) {
      throw InputError(fmt::format("{}: the ratio of {} must lie in [{}, {}], got {:.6g}", name(key), what, kMinRatio,
                                   kMaxRatio, value));
    }
  }
  void exponent(std::string_view key, double value, int which) const {
    if (!(value >= Superellipsoid::kMinExponent && value <= Superellipsoid::kMaxExponent)) {
      throw InputError(fmt::format("{}: e{} must lie in [{}, {}] (convex superellipsoids), got {}", name(key), which,
                                   Superellipsoid::kMinExponent, Superellipsoid::kMaxExponent, value));
    }
  }

 private:
  const ShapeSpec& spec_;
  const ShapeFactoryOptions& options_;
};

std::unique_ptr<Shape> build(const ShapeSpec& spec, const ShapeFactoryOptions& options) {
  const Validator check(spec, options);
  const std::string& shape = spec.shape;
  if (shape == "sphere") {
    return std::make_unique<Ellipsoid>(
        Ellipsoid::sphere(check.length("diameter", check.required("diameter", spec.diameter))));
  }
  if (shape == "spheroid") {
    const double diameter = check.length("diameter", check.required("diameter", spec.diameter));
    const double aspect = check.positive("aspect_ratio", check.required("aspect_ratio", spec.aspect_ratio));
    check.ratio("aspect_ratio", aspect, "polar to equatorial diameter");
    return std::make_unique<Ellipsoid>(Ellipsoid::spheroid(diameter, aspect));
  }
  if (shape == "ellipsoid") {
    return std::make_unique<Ellipsoid>(check.positive3("semi_axes", check.required("semi_axes", spec.semi_axes)));
  }
  if (shape == "cylinder") {
    const double diameter = check.length("diameter", check.required("diameter", spec.diameter));
    const double length = check.length("length", check.required("length", spec.length));
    check.ratio("length", length / diameter, "length to diameter");
    return std::make_unique<Cylinder>(diameter, length);
  }
  if (shape == "cuboid") return std::make_unique<Cuboid>(check.positive3("size", check.required("size", spec.size)));
  if (shape == "superellipsoid") {
    const Eigen::Vector3d axes = check.positive3("semi_axes", check.required("semi_axes", spec.semi_axes));
    const auto& e = check.required("exponents", spec.exponents);
    check.exponent("exponents", e[0], 1);
    check.exponent("exponents", e[1], 2);
    return std::make_unique<Superellipsoid>(axes, e[0], e[1]);
  }
  // mesh
  const std::string& file = check.required("file", spec.file);
  if (file.empty()) throw InputError(fmt::format("{}: must name an STL file", check.name("file")));
  const double scale = spec.scale ? check.positive("scale", *spec.scale) : 1.0;
  std::filesystem::path path(file);
  if (path.is_relative() && !options.base_directory.empty()) path = options.base_directory / path;
  return load_mesh_shape(path, scale);
}

}  // namespace

const std::array<std::string_view, 7>& shape_names() {
  static const std::array<std::string_view, 7> names{"sphere", "spheroid",       "ellipsoid", "cylinder",
                                                     "cuboid", "superellipsoid", "mesh"};
  return names;
}

std::unique_ptr<Shape> make_shape(const ShapeSpec& spec, const ShapeFactoryOptions& options) {
  if (std::find(shape_names().begin(), shape_names().end(), spec.shape) == shape_names().end()) {
    std::string allowed;
    for (std::string_view n : shape_names()) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
    throw InputError(
        fmt::format("{}: unknown shape '{}' (allowed: {})", options.key_name("shape"), spec.shape, allowed));
  }
  if (options.reject_unused_keys) {
    const std::vector<std::string_view> used = keys_of(spec.shape);
    for (std::string_view key : keys_present(spec)) {
      if (std::find(used.begin(), used.end(), key) == used.end()) {
        std::string takes;
        for (std::string_view k : used) takes += (takes.empty() ? "" : ", ") + options.key_name(k);
        throw InputError(
            fmt::format("{}: not used by shape '{}' (it takes {})", options.key_name(key), spec.shape, takes));
      }
    }
  }
  return build(spec, options);
}

}  // namespace settle::body
