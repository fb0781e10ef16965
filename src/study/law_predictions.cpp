#include "study/law_predictions.hpp"

#include "analysis/correlations.hpp"
#include "attitude/euler.hpp"
#include "body/shape_factors.hpp"
#include "body/shape_factory.hpp"
#include "io/case.hpp"
#include "study/derived_inputs.hpp"

namespace settle::study {
namespace {

Eigen::Vector3d vector3(const io::CaseValues& values, std::string_view key) {
  const std::vector<double>& v = values.reals(key);
  return {v[0], v[1], v[2]};
}

// The direction of the relative flow in the inertial frame (its sign does not matter to the
// shadows the sphericities need).
std::optional<Eigen::Vector3d> flow_direction(const io::CaseValues& values) {
  const char* key = relative_flow_key(values);
  if (key == nullptr || !values.has(key)) return std::nullopt;
  const Eigen::Vector3d v = vector3(values, key);
  if (v.norm() <= 0.0) return std::nullopt;
  return v.normalized();
}

}  // namespace

std::optional<double> holzer_sommerfeld_drag_of_case(const std::filesystem::path& case_file, double reynolds) {
  const io::CaseValues values = io::load_case(case_file, {});
  const std::optional<Eigen::Vector3d> flow = flow_direction(values);
  if (!flow || !(reynolds > 0.0)) return std::nullopt;
  body::ShapeFactoryOptions options;
  options.base_directory = case_file.parent_path();
  const auto shape = body::make_shape(io::shape_spec(values), options);
  const Eigen::Matrix3d body_to_inertial = attitude::set1_body_to_inertial(vector3(values, "particle.euler"));
  const body::ShapeFactors f = body::compute_shape_factors(*shape, body_to_inertial.transpose() * *flow);
  return analysis::holzer_sommerfeld_drag(reynolds, f.sphericity, f.crosswise_sphericity, f.lengthwise_sphericity);
}

}  // namespace settle::study
