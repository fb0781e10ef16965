#pragma once
// How far the faces of a window that stands for unbounded fluid must lie from the body: measured
// by the window studies (studies/window_width.toml, window_ahead.toml, window_behind.toml; the
// figures in docs/validation.md, "How large a window"), a towed sphere at Re = 20, 100 and 300 whose
// drag changed by less than 1% between the clearance given here and the largest window tried.
// The preflight tells a case whose window is tighter (io/preflight.hpp).
#include <optional>
#include <string>

#include "coupling/setup.hpp"

namespace settle::io {

/// Distances from the body's centre, in equivalent diameters.
struct WindowClearance {
  double side_d = 0.0;    ///< to the nearest face across the direction of travel
  double ahead_d = 0.0;   ///< to the face the body travels towards
  double behind_d = 0.0;  ///< to the face behind it: the wake's room
};

/// The direction a body travels relative to the fluid: its towing direction, against a fixed body's
/// inflow, along gravity for a free body heavier than the fluid and against it for a lighter one.
/// The zero vector when the vector it follows is zero.
Eigen::Vector3d travel_direction(body::MotionKind motion, const Eigen::Vector3d& towing_velocity,
                                 const Eigen::Vector3d& inflow_velocity, const Eigen::Vector3d& gravity,
                                 bool lighter_than_fluid);

/// What the studies found enough at this Reynolds number: their clearance at Re = 20, 100 or 300,
/// linear in log Re between, and the nearest end's outside (below Re = 20 the sides' influence
/// decays more slowly still, so more room is needed there than this says).
WindowClearance needed_clearance(double reynolds);

/// The case's clearances, for a body that travels along a grid axis in a window whose faces stand
/// for unbounded fluid: sides that are free-slip or periodic or follow the body, ends that follow
/// the body or let the stream in and out. A face of a physical container (a no-slip tank that
/// stays put) counts as infinitely far; a periodic side as half the period away (the body's image
/// is a period away, wherever the body sits). nullopt when the travel is not along an axis.
std::optional<WindowClearance> case_clearance(const coupling::SimulationSetup& setup, double equivalent_diameter_si);

/// The advisory for a case tighter than needed_clearance, naming domain.size; nullopt otherwise.
std::optional<std::string> window_advice(const coupling::SimulationSetup& setup, double equivalent_diameter_si,
                                         double reynolds);

}  // namespace settle::io
