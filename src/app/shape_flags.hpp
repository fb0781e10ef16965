#pragma once
// The command-line flags that describe a particle's shape (--shape, --diameter, ... --mesh,
// --scale), shared by `settle shape` and `settle predict`: the one reader of a shape from flags,
// as io::shape_spec is the one reader of a shape from a case file.
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "body/shape_factory.hpp"

namespace settle::app {

/// The shape flags as given; parsed by shape_spec_from_flags so that every message names its flag.
struct ShapeFlags {
  std::optional<std::string> shape, diameter, aspect_ratio, semi_axes, length, size, exponents, mesh, scale;
};

/// Registers the shape flags on `command`. `length_unit` ends the help of the lengths (", m"
/// where they are SI, "" where any unit will do) and `scale_target` names what --scale converts
/// file units to.
void add_shape_flags(CLI::App& command, ShapeFlags& flags, std::string_view length_unit, std::string_view scale_target);

/// The shape flags given, e.g. "--shape, --diameter" (empty when none).
std::string shape_flags_given(const ShapeFlags& flags);

/// The shape the flags describe; settle::InputError naming the flag on a bad value, and when
/// neither --shape nor --mesh is given.
body::ShapeSpec shape_spec_from_flags(const ShapeFlags& flags);

/// Shape-factory options whose messages name the flags instead of the case keys.
body::ShapeFactoryOptions flag_shape_options();

}  // namespace settle::app
