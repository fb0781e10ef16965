#include "io/window_advice.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/core.h>

namespace settle::io {
namespace {

// The smallest clearance of each kind at which the studies' towed sphere (10 cells per diameter,
// recursive regularised collision, momentum exchange) had a drag within 1% of the largest
// window's (16 d wide, 8 d ahead, 24 d behind): sides 8 d apart (+0.91%, +0.61%, +0.64% at Re =
// 20, 100, 300), 5 d ahead of the centre (+0.36%, +0.27%, +0.37%), 6 d behind (+0.22%, +0.26%,
// +0.31%); the next smaller ones tried (6 d apart, 3 d ahead, 4 d behind) added 1.2-2.8%.
// docs/validation.md, "How large a window", has every run.
struct MeasuredClearance {
  double reynolds;
  WindowClearance clearance;
};
constexpr std::array<MeasuredClearance, 3> kMeasured{{
    {20.0, {4.0, 5.0, 6.0}},
    {100.0, {4.0, 5.0, 6.0}},
    {300.0, {4.0, 5.0, 6.0}},
}};

constexpr double kFar = std::numeric_limits<double>::infinity();

}  // namespace

Eigen::Vector3d travel_direction(body::MotionKind motion, const Eigen::Vector3d& towing_velocity,
                                 const Eigen::Vector3d& inflow_velocity, const Eigen::Vector3d& gravity,
                                 bool lighter_than_fluid) {
  switch (motion) {
    case body::MotionKind::towed:
      return towing_velocity.normalized();
    case body::MotionKind::fixed:
      return -inflow_velocity.normalized();
    case body::MotionKind::free:
      break;
  }
  return (lighter_than_fluid ? -1.0 : 1.0) * gravity.normalized();
}

WindowClearance needed_clearance(double reynolds) {
  if (!(reynolds > kMeasured.front().reynolds)) return kMeasured.front().clearance;
  if (reynolds >= kMeasured.back().reynolds) return kMeasured.back().clearance;
  std::size_t i = 1;
  while (kMeasured[i].reynolds < reynolds) ++i;
  const MeasuredClearance& a = kMeasured[i - 1];
  const MeasuredClearance& b = kMeasured[i];
  const double w = std::log(reynolds / a.reynolds) / std::log(b.reynolds / a.reynolds);
  const auto mix = [w](double x, double y) { return x + w * (y - x); };
  return {mix(a.clearance.side_d, b.clearance.side_d), mix(a.clearance.ahead_d, b.clearance.ahead_d),
          mix(a.clearance.behind_d, b.clearance.behind_d)};
}

std::optional<WindowClearance> case_clearance(const coupling::SimulationSetup& s, double d_eq_si) {
  const Eigen::Vector3d travel = travel_direction(s.motion, s.initial.velocity_si, s.inflow_velocity_si, s.gravity_si,
                                                  s.particle_density_si < s.fluid_density_si);
  if (!travel.allFinite()) return std::nullopt;
  int axis = 0;
  travel.cwiseAbs().maxCoeff(&axis);
  if (std::abs(travel[axis]) < 1.0 - 1e-9) return std::nullopt;
  const Eigen::Vector3d p = s.initial.position_si;
  const Eigen::Vector3d size = s.domain_size_si;
  WindowClearance c{kFar, kFar, kFar};
  for (int a = 0; a < 3; ++a) {
    if (a == axis) continue;
    const lbm::Boundary wall = s.boundaries[static_cast<std::size_t>(a)];
    // A periodic side has no face: the neighbour is the body's image one period away, so the room
    // is half the period wherever the body sits (a periodic box is translation-invariant).
    if (wall == lbm::Boundary::periodic)
      c.side_d = std::min(c.side_d, 0.5 * size[a] / d_eq_si);
    else if (s.follow_particle || wall != lbm::Boundary::no_slip)
      c.side_d = std::min({c.side_d, p[a] / d_eq_si, (size[a] - p[a]) / d_eq_si});
  }
  const bool stream = (s.inflow && s.inflow->axis == axis) || (s.outflow && s.outflow->axis == axis);
  if (s.follow_particle || stream) {
    const double to_top = (size[axis] - p[axis]) / d_eq_si, to_bottom = p[axis] / d_eq_si;
    c.ahead_d = travel[axis] > 0.0 ? to_top : to_bottom;
    c.behind_d = travel[axis] > 0.0 ? to_bottom : to_top;
  }
  return c;
}

std::optional<std::string> window_advice(const coupling::SimulationSetup& s, double d_eq_si, double reynolds) {
  const std::optional<WindowClearance> have = case_clearance(s, d_eq_si);
  if (!have) return std::nullopt;
  const WindowClearance need = needed_clearance(reynolds);
  std::vector<std::string> short_of;
  // A body set a fraction of a cell off the window's centre (a seed of symmetry breaking) is not
  // short of room: only a shortfall of a twentieth of a diameter or more counts.
  const auto check = [&](const char* what, double h, double n) {
    if (h < n - 0.05) short_of.push_back(fmt::format("{} {:.1f} d_eq (needed {:.1f})", what, h, n));
  };
  check("sides", have->side_d, need.side_d);
  check("ahead", have->ahead_d, need.ahead_d);
  check("behind", have->behind_d, need.behind_d);
  if (short_of.empty()) return std::nullopt;
  std::string list;
  for (const std::string& item : short_of) list += (list.empty() ? "" : ", ") + item;
  return fmt::format(
      "domain.size: the window's faces are nearer the body than a towed sphere at Re = {:.0f} needed for its "
      "drag to change by less than 1% (docs/validation.md, \"How large a window\"): from its centre, {}; "
      "enlarge domain.size (and move particle.position) unless the faces are part of the problem",
      reynolds, list);
}

}  // namespace settle::io
