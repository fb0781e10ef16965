#pragma once
// Shape factors of a particle from its exact geometry.
#include <Eigen/Dense>

#include "body/shape.hpp"

namespace settle::body {

/// Definitions (d_eq = (6V/pi)^(1/3), A the surface area):
///  - sphericity (Wadell 1935, J. Geol. 43, 250-280, doi:10.1086/624298): pi d_eq^2 / A.
///  - crosswise sphericity (Hoelzer and Sommerfeld 2008, Powder Technol. 184, 361-365,
///    doi:10.1016/j.powtec.2007.08.021): (pi d_eq^2 / 4) / A_perp, with A_perp the shadow of the
///    particle along the flow direction.
///  - lengthwise sphericity (same paper): (pi d_eq^2 / 4) / (A/2 - A_par), with A_par the mean
///    shadow over the directions perpendicular to the flow ("mean projected longitudinal
///    cross-sectional area"). Both equal 1 for a sphere.
///  - principal extents L >= I >= S: the body's widths along its three principal axes of inertia.
///  - Corey shape factor (Corey 1949, MSc thesis, Colorado A&M): S / sqrt(L I).
///  - flatness S/I and elongation I/L (Bagheri and Bonadonna 2016, Powder Technol. 301,
///    526-544, doi:10.1016/j.powtec.2016.06.015).
/// When principal moments coincide the principal axes are not unique; the body's own axes are
/// used when the inertia tensor is diagonal in them (all analytic shapes, axis-aligned meshes),
/// otherwise the extents follow the eigen-solver's choice (see docs/shapes.md).
struct ShapeFactors {
  double volume = 0.0;
  double surface_area = 0.0;
  double equivalent_diameter = 0.0;
  double sphericity = 0.0;
  Eigen::Vector3d flow_direction = Eigen::Vector3d::UnitZ();  ///< unit, body frame
  double projected_area_along_flow = 0.0;                     ///< A_perp
  double mean_projected_area_across_flow = 0.0;               ///< A_par
  double crosswise_sphericity = 0.0;
  double lengthwise_sphericity = 0.0;
  Eigen::Vector3d principal_extents = Eigen::Vector3d::Zero();  ///< (L, I, S), descending
  double corey_shape_factor = 0.0;
  double flatness = 0.0;
  double elongation = 0.0;
};

/// Shape factors for a flow direction given in the body frame (any non-zero vector).
ShapeFactors compute_shape_factors(const Shape& shape, const Eigen::Vector3d& flow_direction);

}  // namespace settle::body
