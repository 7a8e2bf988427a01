// PID controller in the earth frame with anti-windup:
//   tau = -J^T(eta) (K_p eta_tilde + K_i z + K_d eta_tilde_dot),  z_dot = eta_tilde
// The integral term of each DOF is limited to |K_i z| <= integral_limit, and
// a DOF stops integrating while its term sits at that limit and the error
// would push it further (conditional integration), so a long saturation does
// not wind the integrator up.
#pragma once

#include <algorithm>
#include <cmath>

#include "neurov/control/controller_base.hpp"
#include "neurov/core/field_spec.hpp"

namespace neurov {

template <typename Scalar>
struct PIDConfig {
  Vector6<Scalar> kp = Vector6<Scalar>::Zero();  ///< K_p (>= 0)
  Vector6<Scalar> ki = Vector6<Scalar>::Zero();  ///< K_i (>= 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();  ///< K_d (>= 0)
  /// Largest |K_i z| per DOF [N or N m] (> 0).
  Vector6<Scalar> integral_limit = Vector6<Scalar>::Constant(Scalar(50));
  Scalar dt = Scalar(0.2);  ///< control period [s]
};

template <typename Scalar>
auto config_fields(const PIDConfig<Scalar>*) noexcept {
  using C = PIDConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("kp", &C::kp, "", Check::non_negative, "K_p, diagonal (6,)"),
      field_spec<C>("ki", &C::ki, "", Check::non_negative, "K_i, diagonal (6,)"),
      field_spec<C>("kd", &C::kd, "", Check::non_negative, "K_d, diagonal (6,)"),
      field_spec<C>("integral_limit", &C::integral_limit, "N, N m", Check::positive,
                    "Largest |K_i z| per DOF (6,)"),
      field_spec<C>("dt", &C::dt, "s", Check::positive, "Control period"));
}

template <typename Scalar>
inline ValidationError validate(const PIDConfig<Scalar>& c) noexcept {
  return check_fields(c);
}

template <typename ScalarT>
class PIDController
    : public VectorStateControllerBase<PIDController<ScalarT>, ScalarT, PIDConfig<ScalarT>> {
  using Base = VectorStateControllerBase<PIDController<ScalarT>, ScalarT, PIDConfig<ScalarT>>;
  friend ControllerBase<PIDController<ScalarT>, ScalarT, PIDConfig<ScalarT>>;

 public:
  using typename Base::Scalar;
  using typename Base::Vec6;

  NEUROV_CONTROLLER_NAMES("pid", "PID", "PIDController")
  static constexpr const char* kDoc =
      "PID baseline in the earth frame with anti-windup: tau = -J^T (K_p eta_tilde + K_i z + "
      "K_d eta_tilde_dot), z the integral of eta_tilde, |K_i z| <= integral_limit per DOF and "
      "no integration further into the limit.";
  static constexpr const char* kStateName = "integral";
  static constexpr const char* kStateDoc =
      "The integrator state z (6,), the limited time integral of eta_tilde.";
  NEUROV_CONTROLLER_CONSTRUCTORS(PIDController, "PID controller")

  /// The integrator state z (the time integral of eta_tilde, limited).
  const Vec6& integral() const noexcept { return this->state_; }
  /// The integrator is the PID's only memory: ||z||.
  Scalar adaptive_norm() const noexcept { return this->state_.norm(); }

 private:
  /// tau from the errors, then one step of the integrator, kept only when
  /// both are finite.
  bool control(const TrackingError<Scalar>& e, const Vec6&, Vec6& tau) noexcept {
    const auto& c = this->config_;
    Vec6& z = this->state_;
    const Vec6 integral_term = c.ki.cwiseProduct(z);
    tau = -e.kinematics.apply_transpose(c.kp.cwiseProduct(e.eta_tilde) + integral_term +
                                        c.kd.cwiseProduct(e.eta_tilde_dot));
    Vec6 next = z;
    for (int i = 0; i < 6; ++i) {
      if (c.ki(i) == Scalar(0)) continue;
      const Scalar limit = c.integral_limit(i) / c.ki(i);
      const bool at_limit = std::abs(z(i)) >= limit;
      const bool pushing_out = z(i) * e.eta_tilde(i) > Scalar(0);
      if (!(at_limit && pushing_out)) next(i) += c.dt * e.eta_tilde(i);
      next(i) = std::max(-limit, std::min(limit, next(i)));
    }
    if (!(tau.allFinite() && next.allFinite())) return false;
    z = next;
    return true;
  }
};

}  // namespace neurov
