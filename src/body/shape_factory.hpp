#pragma once
// Building a shape from the case file's [particle] keys (docs/architecture.md, "Case file"): shape,
// diameter, aspect_ratio, semi_axes, exponents, length, size, file, scale.
#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "body/shape.hpp"

namespace settle::body {

/// The shape keys of [particle], unparsed from any format. Absent keys are empty.
struct ShapeSpec {
  std::string shape;                   ///< sphere | spheroid | ellipsoid | cylinder | cuboid | superellipsoid | mesh
  std::optional<double> diameter;      ///< sphere, spheroid (equatorial), cylinder
  std::optional<double> aspect_ratio;  ///< spheroid: polar / equatorial
  std::optional<std::array<double, 3>> semi_axes;  ///< ellipsoid, superellipsoid
  std::optional<std::array<double, 2>> exponents;  ///< superellipsoid (e1, e2), Barr convention
  std::optional<double> length;                    ///< cylinder
  std::optional<std::array<double, 3>> size;       ///< cuboid edge lengths
  std::optional<std::string> file;                 ///< mesh: STL path
  std::optional<double> scale;                     ///< mesh: file units to metres (default 1)
};

struct ShapeFactoryOptions {
  /// Relative mesh paths are taken relative to this directory (the case file's).
  std::filesystem::path base_directory;
  /// How error messages name a key: "particle.<key>" for case files; the command line maps
  /// keys to its flags.
  std::function<std::string(std::string_view key)> key_name = [](std::string_view key) {
    return "particle." + std::string(key);
  };
  /// Refuse keys that the chosen shape does not use (e.g. aspect_ratio for a cylinder): they
  /// are almost always a mistake in the case.
  bool reject_unused_keys = true;
};

/// Validated ranges (settle::InputError naming the key otherwise): every length finite and > 0;
/// aspect_ratio, length/diameter and the ratio of the largest to the smallest semi-axis or edge
/// within [1e-3, 1e3] (beyond that the body is a needle or a sheet that no grid resolves);
/// exponents in [0.1, 2] (Superellipsoid); scale finite and > 0.
std::unique_ptr<Shape> make_shape(const ShapeSpec& spec, const ShapeFactoryOptions& options = {});

/// The shape names make_shape accepts.
const std::array<std::string_view, 7>& shape_names();

}  // namespace settle::body
