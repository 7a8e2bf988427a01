// The classical fourth-order Runge-Kutta step, written once for the plant
// (model/integrator.hpp) and the reference model (control/reference_model.hpp).
// Both integrate a state held as two 6-vectors (a pose and a velocity).
#pragma once

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"

namespace neurov::detail {

/// Where an RK4 step stopped: `stage` 1..4 is the stage whose status the
/// caller could not use (`status` is that stage's), 0 when all four ran and
/// `status` is the worst of their statuses.
struct Rk4Outcome {
  Status status = Status::ok;
  int stage = 0;
};

/// One RK4 step of x = (a, b) over dt:
///   k1 = f(x), k2 = f(x + dt/2 k1), k3 = f(x + dt/2 k2), k4 = f(x + dt k3),
///   x_next = x + dt/6 (k1 + 2 (k2 + k3) + k4).
/// `rhs(a, b, a_dot, b_dot)` evaluates f and returns a Status; the step ends
/// at the first stage whose status `usable(status)` rejects, with
/// (a_next, b_next) then unspecified. The result is not checked for finiteness.
template <typename Scalar, typename Rhs, typename Usable>
inline Rk4Outcome rk4(const Vector6<Scalar>& a, const Vector6<Scalar>& b, Scalar dt, Rhs&& rhs,
                      Usable&& usable, Vector6<Scalar>& a_next,
                      Vector6<Scalar>& b_next) noexcept {
  Vector6<Scalar> k1a, k1b, k2a, k2b, k3a, k3b, k4a, k4b;
  const Scalar h2 = Scalar(0.5) * dt;
  Status flag = rhs(a, b, k1a, k1b);
  if (!usable(flag)) return {flag, 1};
  Status s = rhs(a + h2 * k1a, b + h2 * k1b, k2a, k2b);
  if (!usable(s)) return {s, 2};
  flag = worst(flag, s);
  s = rhs(a + h2 * k2a, b + h2 * k2b, k3a, k3b);
  if (!usable(s)) return {s, 3};
  flag = worst(flag, s);
  s = rhs(a + dt * k3a, b + dt * k3b, k4a, k4b);
  if (!usable(s)) return {s, 4};
  flag = worst(flag, s);
  const Scalar h6 = dt / Scalar(6);
  a_next = a + h6 * (k1a + Scalar(2) * (k2a + k3a) + k4a);
  b_next = b + h6 * (k1b + Scalar(2) * (k2b + k3b) + k4b);
  return {flag, 0};
}

}  // namespace neurov::detail
