#pragma once
// Classical fourth-order Runge-Kutta step over a generic state (Kutta 1901), so that the
// attitude angles can be integrated alone (kinematics) or together with the body rates and
// the translational state in the same stages (dynamics).

namespace settle::attitude {

/// One classical RK4 step of dy/dt = derivative(t, y) from (t, y) to t + dt.
/// State is any vector-space type with State + State and double * State (Eigen vectors,
/// double). The four stage evaluations are at t, t + dt/2, t + dt/2 and t + dt, so a
/// derivative that interpolates data in time sees the step's start, middle and end.
template <typename State, typename Derivative>
[[nodiscard]] State rk4_step(const State& y, double t, double dt, Derivative&& derivative) {
  const double half = 0.5 * dt;
  const State k1 = derivative(t, y);
  const State k2 = derivative(t + half, State(y + half * k1));
  const State k3 = derivative(t + half, State(y + half * k2));
  const State k4 = derivative(t + dt, State(y + dt * k3));
  return State(y + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4));
}

}  // namespace settle::attitude
