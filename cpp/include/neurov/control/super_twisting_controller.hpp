// Super-twisting (second-order sliding-mode) controller on the same sliding
// variable s = eta_tilde_dot + Lambda eta_tilde as the sliding-mode controller,
// with a continuous control and no boundary layer. In continuous time, per DOF,
// in units of s per second (M_i the nominal inertia of the DOF):
//   tau = Phi theta_nominal - J^T(eta) M (c s + alpha |s|^(1/2) sgn(s) + v),
//   v_dot = beta sgn(s),   c = K_d / M.
// At the 5 Hz control period an explicit Euler step of this law chatters
// (sgn(s_k) flips every period around s = 0). The step here is the implicit
// Euler discretisation of Brogliato, Polyakov and Efimov (IEEE TAC 65(8),
// 2020): the law is evaluated at the s_{k+1} it predicts for the nominal error
// dynamics s_dot = -(c s + alpha |s|^(1/2) sgn(s) + v), and sgn is the set
// [-1, 1] at 0. With w = s_k - h v_k and a = 1 + h c, s_{k+1} solves
//   a s_{k+1} + (h alpha |s_{k+1}|^(1/2) + h^2 beta) Sgn(s_{k+1}) ∋ w,
// in closed form: s_{k+1} = 0 and sgn = w / (h^2 beta) when |w| <= h^2 beta,
// else s_{k+1} = sgn(w) r^2 with r the positive root of
// a r^2 + h alpha r + h^2 beta = |w|. Near the surface the control is then
// the nominal equivalent control (no switching), far from it the law.
// Anti-windup: the sliding terms' force is limited per DOF to force_limit
// (what the thrusters can give), the integral term v stays within it, and v
// does not integrate further while the limit is active in its direction
// (conditional integration, as in the PID).
#pragma once

#include <algorithm>
#include <cmath>
#include <tuple>

#include "neurov/control/controller_base.hpp"
#include "neurov/core/field_spec.hpp"
#include "neurov/model/regressor.hpp"

namespace neurov {

template <typename Scalar>
struct SuperTwistingConfig : SlidingGains<Scalar> {
  /// alpha, the gain of |s|^(1/2) sgn(s) (> 0) [(units of s)^(1/2) / s].
  Vector6<Scalar> alpha = Vector6<Scalar>::Ones();
  /// beta, the integral gain (> 0) [units of s / s^2].
  Vector6<Scalar> beta = Vector6<Scalar>::Constant(Scalar(0.5));
  /// Largest force of the sliding terms per DOF (> 0) [N, N m]: anti-windup.
  Vector6<Scalar> force_limit = Vector6<Scalar>::Constant(Scalar(1000));
  Scalar dt = Scalar(0.2);  ///< control period [s], the implicit step's h
  /// The nominal model's theta (regressor_parameters of the vehicle file): its
  /// f and, from its inertia and added mass, the M of each DOF.
  ParameterVector<Scalar> theta = ParameterVector<Scalar>::Zero();
};

namespace detail {

/// The nominal inertia of each DOF from theta: m + (-X_udot), ..., I_z + (-N_rdot).
template <typename Scalar>
Vector6<Scalar> nominal_inertia(const ParameterVector<Scalar>& theta) noexcept {
  Vector6<Scalar> m;
  for (int i = 0; i < 6; ++i) m(i) = theta(i < 3 ? 0 : i - 2) + theta(4 + i);
  return m;
}

}  // namespace detail

template <typename Scalar>
inline ValidationError validate(const SuperTwistingConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_sliding_gains(c)) return e;
  if (auto e = detail::check_positive("alpha", c.alpha)) return e;
  if (auto e = detail::check_positive("beta", c.beta)) return e;
  if (auto e = detail::check_positive("force_limit", c.force_limit)) return e;
  if (auto e = detail::check_step("dt", static_cast<double>(c.dt))) return e;
  if (auto e = detail::check_finite("theta", c.theta)) return e;
  const Vector6<Scalar> m = detail::nominal_inertia(c.theta);
  for (int i = 0; i < 6; ++i)
    if (!(m(i) > Scalar(0)))
      return detail::invalid("theta", i < 3 ? 0 : i - 2, static_cast<double>(c.theta(i < 3 ? 0 : i - 2)),
                             "a nominal model whose inertia plus added mass (theta[0..3] + "
                             "theta[4..9]) is > 0 in every DOF, e.g. regressor_parameters(vehicle)");
  return {};
}

/// The configuration's fields, for the bindings and scenario files.
template <typename Scalar>
auto config_fields(const SuperTwistingConfig<Scalar>*) noexcept {
  using C = SuperTwistingConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("lambda_", &C::lambda,
                    "Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,), > 0."),
      field_spec<C>("kd", &C::kd, "K_d, diagonal (6,), >= 0 [N, N m per unit of s]."),
      field_spec<C>("alpha", &C::alpha,
                    "alpha, gain of |s|^(1/2) sgn(s) per unit inertia (6,), > 0."),
      field_spec<C>("beta", &C::beta, "beta, integral gain per unit inertia (6,), > 0."),
      field_spec<C>("force_limit", &C::force_limit,
                    "Largest force of the sliding terms per DOF (6,), > 0 [N, N m] "
                    "(anti-windup of the integral term)."),
      field_spec<C>("theta", &C::theta,
                    "The nominal model's theta (24,), e.g. regressor_parameters(vehicle)."),
      field_spec<C>("dt", &C::dt, "Control period [s], > 0: the implicit step."));
}

template <typename ScalarT>
class SuperTwistingController
    : public VectorStateControllerBase<SuperTwistingController<ScalarT>, ScalarT,
                                       SuperTwistingConfig<ScalarT>> {
  using Base = VectorStateControllerBase<SuperTwistingController<ScalarT>, ScalarT,
                                         SuperTwistingConfig<ScalarT>>;
  friend ControllerBase<SuperTwistingController<ScalarT>, ScalarT, SuperTwistingConfig<ScalarT>>;

 public:
  using typename Base::Scalar;
  using typename Base::Vec6;

  NEUROV_CONTROLLER_NAMES("super_twisting", "super-twisting", "SuperTwistingController")
  NEUROV_CONTROLLER_CONSTRUCTORS(SuperTwistingController, "super-twisting controller")
  static constexpr const char* kDoc =
      "Super-twisting sliding-mode controller, implicit (chattering-free) discretisation: "
      "tau = Phi theta - J^T M (c s + alpha |s|^(1/2) sgn(s) + v), v_dot = beta sgn(s), "
      "c = K_d / M, evaluated at the s of the next step that it predicts (Brogliato, "
      "Polyakov and Efimov 2020); the sliding terms are limited to force_limit and v does "
      "not wind up.";
  static constexpr const char* kStateName = "integral";
  static constexpr const char* kStateDoc =
      "The integral term v (6,), in units of s per second.";

  /// The integral term v is the controller's memory: ||v||.
  Scalar adaptive_norm() const noexcept { return this->state_.norm(); }

 private:
  /// f = Phi theta_nominal, then the implicit super-twisting step per DOF.
  bool control(const TrackingError<Scalar>& e, const Vec6& nu, Vec6& tau) noexcept {
    const auto& c = this->config_;
    const Vec6 f_hat = reference_regressor(e, nu) * c.theta;
    const Vec6 m = detail::nominal_inertia(c.theta);
    const Scalar h = c.dt;
    Vec6 force, v_next;
    for (int i = 0; i < 6; ++i) {
      const Scalar v = this->state_(i);
      const Scalar damping = c.kd(i) / m(i);
      const Scalar a = Scalar(1) + h * damping;
      const Scalar w = e.s(i) - h * v;
      const Scalar g = h * h * c.beta(i);
      Scalar sigma, r;  // sgn(s_{k+1}) and |s_{k+1}|^(1/2)
      if (std::abs(w) <= g) {
        sigma = w / g;
        r = Scalar(0);
      } else {
        sigma = w > Scalar(0) ? Scalar(1) : Scalar(-1);
        const Scalar ha = h * c.alpha(i);
        r = (std::sqrt(ha * ha + Scalar(4) * a * (std::abs(w) - g)) - ha) / (Scalar(2) * a);
      }
      const Scalar integrated = v + h * c.beta(i) * sigma;
      const Scalar u = damping * sigma * r * r + c.alpha(i) * sigma * r + integrated;
      const Scalar limit = c.force_limit(i);
      Scalar f = m(i) * u;
      Scalar v_i = integrated;
      if (std::abs(f) > limit) {
        f = f > Scalar(0) ? limit : -limit;
        // Saturated: v moves only back out of the limit's direction.
        if ((integrated - v) * f > Scalar(0)) v_i = v;
      }
      const Scalar v_max = limit / m(i);
      v_next(i) = std::max(-v_max, std::min(v_max, v_i));
      force(i) = f;
    }
    tau = f_hat - e.kinematics.apply_transpose(force);
    if (!(tau.allFinite() && v_next.allFinite())) return false;
    this->state_ = v_next;
    return true;
  }
};

}  // namespace neurov
