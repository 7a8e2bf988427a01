// The plant in a non-uniform flow (waves on a current): the hydrodynamic
// terms act on the velocity relative to the water, nu_w = nu - nu_f (named
// apart from nu_r, the controllers' reference velocity), and the water's
// linear acceleration a_f adds the Froude-Krylov and added-mass force
// (rho V [I; 0] + M_A [I; 0]) a_f, each once (docs/disturbances.md):
//
//   M_RB nu_dot + C_RB(nu) nu + M_A nu_dot + C_A(nu_w) nu_w + D(nu_w) nu_w + g(eta)
//       = tau + rho V [a_b; r_b x a_b] + M_A [a_b; 0],     a_b = R^T a_f,
//
// the Froude-Krylov force of the pressure gradient acting at the centre of
// buoyancy. Written as Vehicle::derivative's relative form, whose current
// term already carries -w x v_f: with M nu_w_dot + C(nu_w) nu_w + D nu_w + g
// = tau + F and nu_dot = nu_w_dot + [a_b - w x v_f; 0], the form above needs
//   F = rho V [a_b; r_b x a_b] - M_RB [a_b; 0],
// since M_RB nu_dot + C_RB(nu) nu = M_RB nu_w_dot + C_RB(nu_w) nu_w +
// M_RB [a_b; 0] (Fossen 2011, Property 8.1, with the water's acceleration).
// A neutrally buoyant body with rho V = m and r_b = r_g feels F = 0 and is
// carried by the water: nu_w stays 0.
#pragma once

#include "neurov/core/rk4.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

/// The water at the vehicle: its velocity (current plus orbital) and linear
/// acceleration in NED, and the displaced mass rho V = B / g.
template <typename Scalar>
struct FluidFlow {
  Vector3<Scalar> velocity = Vector3<Scalar>::Zero();      ///< NED [m/s]
  Vector3<Scalar> acceleration = Vector3<Scalar>::Zero();  ///< NED [m/s^2]
  Scalar displaced_mass = Scalar(0);                       ///< rho V [kg]
};

/// eta_dot and nu_dot of the plant in the flow `f` (see the top of the
/// file); statuses as Vehicle::derivative.
template <typename Scalar>
inline Status derivative_in_flow(const Vehicle<Scalar>& vehicle, const Vector6<Scalar>& eta,
                                 const Vector6<Scalar>& nu, const Vector6<Scalar>& tau,
                                 const FluidFlow<Scalar>& f, Vector6<Scalar>& eta_dot,
                                 Vector6<Scalar>& nu_dot) noexcept {
  using Vec3 = Vector3<Scalar>;
  if (!detail::all_finite(eta, f.acceleration)) {
    eta_dot.setZero();
    nu_dot.setZero();
    return Status::non_finite_input;
  }
  const VehicleParameters<Scalar>& p = vehicle.parameters();
  const EulerTrig<Scalar> trig = EulerTrig<Scalar>::from_pose(eta);
  const Vec3 a_b = rotation(trig).transpose() * f.acceleration;
  Vector6<Scalar> force = tau;
  force.template head<3>() += (f.displaced_mass - p.mass) * a_b;
  force.template tail<3>() += f.displaced_mass * p.centre_of_buoyancy.cross(a_b) -
                              p.mass * p.centre_of_gravity.cross(a_b);
  const Status s = vehicle.derivative(trig, eta, nu, force, f.velocity, eta_dot, nu_dot);
  if (s != Status::ok && s != Status::near_singularity) return s;
  nu_dot.template head<3>() += a_b;
  if (!detail::all_finite(nu_dot)) {
    eta_dot.setZero();
    nu_dot.setZero();
    return Status::non_finite_output;
  }
  return s;
}

/// One RK4 step of the plant in a flow known at the step's start (`start`)
/// and end (`end`): at each stage time s the velocity is the cubic Hermite
/// interpolation of the end velocities and accelerations, and the
/// acceleration its derivative, so the flow the plant meets is exact to
/// O(h^4) in time whatever the stage (the position is where `start` and
/// `end` were taken). The displaced mass is start's. Statuses and state on
/// failure as rk4_step.
template <typename Scalar>
inline Status rk4_step_in_flow(const Vehicle<Scalar>& vehicle, Vector6<Scalar>& eta,
                               Vector6<Scalar>& nu, const Vector6<Scalar>& tau, Scalar dt,
                               const FluidFlow<Scalar>& start,
                               const FluidFlow<Scalar>& end) noexcept {
  if (detail::check_step("dt", static_cast<double>(dt))) return Status::invalid_argument;
  const Vector3<Scalar> &v0 = start.velocity, &v1 = end.velocity;
  const Vector3<Scalar> &a0 = start.acceleration, &a1 = end.acceleration;
  // The midpoint of the Hermite cubic: (v0 + v1)/2 + h (a0 - a1)/8 and its
  // slope 3 (v1 - v0) / (2 h) - (a0 + a1)/4; the ends are the data.
  FluidFlow<Scalar> mid = start;
  mid.velocity = Scalar(0.5) * (v0 + v1) + (dt / Scalar(8)) * (a0 - a1);
  mid.acceleration = (Scalar(1.5) / dt) * (v1 - v0) - Scalar(0.25) * (a0 + a1);
  return rk4_step_in_flow(vehicle, eta, nu, tau, dt, start, mid, end);
}

/// The same with the flow at the step's middle given too (a caller that
/// knows the flow along the vehicle's path: the Hermite midpoint above
/// treats the local acceleration as the rate along the path, which a
/// moving vehicle's is not).
template <typename Scalar>
inline Status rk4_step_in_flow(const Vehicle<Scalar>& vehicle, Vector6<Scalar>& eta,
                               Vector6<Scalar>& nu, const Vector6<Scalar>& tau, Scalar dt,
                               const FluidFlow<Scalar>& start, const FluidFlow<Scalar>& middle,
                               const FluidFlow<Scalar>& end) noexcept {
  if (detail::check_step("dt", static_cast<double>(dt))) return Status::invalid_argument;
  using V6 = Vector6<Scalar>;
  FluidFlow<Scalar> mid = middle;
  mid.displaced_mass = start.displaced_mass;
  FluidFlow<Scalar> last = end;
  last.displaced_mass = start.displaced_mass;
  const FluidFlow<Scalar>* stages[4] = {&start, &mid, &mid, &last};
  int stage = 0;
  V6 eta_next, nu_next;
  const detail::Rk4Outcome r = detail::rk4(
      eta, nu, dt,
      [&](const V6& e, const V6& n, V6& e_dot, V6& n_dot) noexcept {
        return derivative_in_flow(vehicle, e, n, tau, *stages[stage++], e_dot, n_dot);
      },
      [](Status s) noexcept { return s == Status::ok || s == Status::near_singularity; },
      eta_next, nu_next);
  if (r.stage == 1) return r.status;
  if (r.stage > 1) return Status::non_finite_output;
  if (!detail::all_finite(eta_next, nu_next)) return Status::non_finite_output;
  eta = eta_next;
  nu = nu_next;
  return r.status;
}

}  // namespace neurov
