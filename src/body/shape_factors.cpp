#include "body/shape_factors.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace settle::body {

ShapeFactors compute_shape_factors(const Shape& shape, const Eigen::Vector3d& flow_direction) {
  ShapeFactors f;
  f.flow_direction = unit_direction(flow_direction, "flow direction");
  f.volume = shape.volume();
  f.surface_area = shape.surface_area();
  f.equivalent_diameter = shape.equivalent_diameter();
  const double sphere_section = 0.25 * std::numbers::pi * f.equivalent_diameter * f.equivalent_diameter;
  f.sphericity = 4.0 * sphere_section / f.surface_area;
  f.projected_area_along_flow = shape.projected_area(f.flow_direction);
  f.mean_projected_area_across_flow = shape.mean_projected_area_perpendicular(f.flow_direction);
  f.crosswise_sphericity = sphere_section / f.projected_area_along_flow;
  f.lengthwise_sphericity = sphere_section / (0.5 * f.surface_area - f.mean_projected_area_across_flow);

  const Eigen::Matrix3d axes = shape.mass_properties(1.0).principal.axes;
  for (int i = 0; i < 3; ++i) f.principal_extents(i) = shape.width(axes.col(i));
  std::sort(f.principal_extents.data(), f.principal_extents.data() + 3, std::greater<>());
  const double longest = f.principal_extents(0), intermediate = f.principal_extents(1);
  const double shortest = f.principal_extents(2);
  f.corey_shape_factor = shortest / std::sqrt(longest * intermediate);
  f.flatness = shortest / intermediate;
  f.elongation = intermediate / longest;
  return f;
}

}  // namespace settle::body
