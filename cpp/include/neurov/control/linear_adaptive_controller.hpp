// Linearly parameterised adaptive controller of Fossen and Sagatun (eq. 26, 28):
//   tau = Phi theta_hat - J^T(eta) K_d s
//   theta_hat <- theta_hat - dt Gamma Phi^T J^-1(eta) s    (one Euler step)
// It knows the structure of the model (regressor.hpp); only theta is unknown.
#pragma once

#include <cmath>

#include "neurov/control/controller_base.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/regressor.hpp"

namespace neurov {

template <typename Scalar>
struct LinearAdaptiveConfig {
  Vector6<Scalar> lambda = Vector6<Scalar>::Constant(Scalar(0.5));  ///< Lambda (> 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();                     ///< K_d (>= 0)
  /// Diagonal of Gamma (>= 0; 0 freezes that parameter).
  ParameterVector<Scalar> gamma = ParameterVector<Scalar>::Constant(Scalar(1));
  Scalar dt = Scalar(0.2);                                          ///< control period [s]
  /// theta_hat(0): zero, or a nominal guess such as regressor_parameters().
  ParameterVector<Scalar> theta0 = ParameterVector<Scalar>::Zero();
};

template <typename Scalar>
inline ValidationError validate(const LinearAdaptiveConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_positive("lambda", c.lambda)) return e;
  if (auto e = detail::check_non_negative("kd", c.kd)) return e;
  if (auto e = detail::check_non_negative("gamma", c.gamma)) return e;
  if (auto e = detail::check_positive_scalar("dt", static_cast<double>(c.dt))) return e;
  if (auto e = detail::check_finite("theta0", c.theta0)) return e;
  return {};
}

template <typename ScalarT>
class LinearAdaptiveController
    : public ControllerBase<LinearAdaptiveController<ScalarT>, ScalarT,
                            LinearAdaptiveConfig<ScalarT>> {
  using Base =
      ControllerBase<LinearAdaptiveController<ScalarT>, ScalarT, LinearAdaptiveConfig<ScalarT>>;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Base::step;
  /// theta_hat is what the closed loop logs per step.
  static constexpr int kLoggedParameters = kRegressorParameters;

  LinearAdaptiveController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit LinearAdaptiveController(const Config& config) {
    detail::throw_if_invalid(create(config, *this), "linear adaptive controller");
  }
#endif

  static ValidationError create(const Config& config, LinearAdaptiveController& out) noexcept {
    return Base::configure(config, out);
  }

  /// Control law and one adaptation step. On any status but ok, tau = 0 and
  /// theta_hat is exactly as before.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    const Config& c = this->config_;
    TrackingError<Scalar> e;
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, c.lambda, e, tau);
        ts != Status::ok)
      return ts;
    const auto& trig = e.kinematics.trig;
    const RegressorMatrix<Scalar> phi =
        regressor<Scalar>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi, trig.sin_theta,
                          trig.cos_theta);
    const Vec6 f_hat = phi * theta_hat_;
    const Vec6 tau_new = f_hat - e.kinematics.apply_transpose(c.kd.cwiseProduct(e.s));
    const ParameterVector<Scalar> theta_next =
        theta_hat_ -
        c.dt * c.gamma.cwiseProduct(phi.transpose() * e.kinematics.apply_inverse(e.s));
    if (!(tau_new.allFinite() && theta_next.allFinite()))
      return this->refuse(Status::non_finite_output, tau);
    theta_hat_ = theta_next;
    f_hat_ = f_hat;
    return this->accept(e, tau_new, tau);
  }

  /// Back to theta0 and a zero history.
  void reset() noexcept {
    theta_hat_ = this->config_.theta0;
    f_hat_.setZero();
    this->reset_common();
  }

  /// Replaces theta_hat; false (unchanged) on a NaN/Inf.
  bool set_theta(const ParameterVector<Scalar>& theta) noexcept {
    if (!this->configured_ || !theta.allFinite()) return false;
    theta_hat_ = theta;
    return true;
  }

  /// A snapshot's state put back (ControllerBase::restore) with theta_hat
  /// and the last model output; false, and nothing changed, for non-finite ones.
  bool restore(const TrackingError<Scalar>& e, Status s, const ParameterVector<Scalar>& theta,
               const Vec6& model_output) noexcept {
    if (!this->restorable(e, s) || !theta.allFinite() || !model_output.allFinite()) return false;
    theta_hat_ = theta;
    f_hat_ = model_output;
    return Base::restore(e, s);
  }

  const ParameterVector<Scalar>& theta() const noexcept { return theta_hat_; }
  /// Phi theta_hat of the last accepted step: the model's estimate of f.
  const Vec6& model_output() const noexcept { return f_hat_; }
  /// ||theta_hat||.
  Scalar adaptive_norm() const noexcept { return theta_hat_.norm(); }
  const ParameterVector<Scalar>& logged_parameters() const noexcept { return theta_hat_; }

 private:
  ParameterVector<Scalar> theta_hat_ = ParameterVector<Scalar>::Zero();
  Vec6 f_hat_ = Vec6::Zero();
};

}  // namespace neurov
