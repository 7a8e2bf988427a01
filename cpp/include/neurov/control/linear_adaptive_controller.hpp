// Linearly parameterised adaptive controller of Fossen and Sagatun (eq. 26, 28):
//   tau = Phi theta_hat - J^T(eta) K_d s
//   theta_hat <- theta_hat - dt Gamma Phi^T J^-1(eta) s    (one Euler step)
// It knows the structure of the model (regressor.hpp); only theta is unknown.
#pragma once

#include <cmath>

#include "neurov/core/config.hpp"
#include "neurov/control/desired_state.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/core/status.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

#if NEUROV_HAS_EXCEPTIONS
#include <stdexcept>
#include <string>
#endif

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
class LinearAdaptiveController {
 public:
  using Scalar = ScalarT;
  using Vec6 = Vector6<Scalar>;
  using Config = LinearAdaptiveConfig<Scalar>;

  LinearAdaptiveController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit LinearAdaptiveController(const Config& config) {
    if (const ValidationError e = create(config, *this)) {
      char buf[256];
      e.format(buf, sizeof buf);
      throw std::invalid_argument(std::string("linear adaptive controller: ") + buf);
    }
  }
#endif

  static ValidationError create(const Config& config, LinearAdaptiveController& out) noexcept {
    if (auto e = validate(config)) return e;
    out.config_ = config;
    out.configured_ = true;
    out.reset();
    return {};
  }

  /// Control law and one adaptation step. On any status but ok, tau = 0 and
  /// theta_hat is exactly as before.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    if (!configured_) return refuse(Status::invalid_argument, tau);
    TrackingError<Scalar> e;
    const Status ts = compute_tracking_error(eta, nu, eta_d, eta_d_dot, eta_d_ddot,
                                             config_.lambda, e);
    if (ts != Status::ok) return refuse(ts, tau);
    const auto& trig = e.kinematics.trig;
    const RegressorMatrix<Scalar> phi =
        regressor<Scalar>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi, trig.sin_theta,
                          trig.cos_theta);
    const Vec6 f_hat = phi * theta_hat_;
    const Vec6 tau_new = f_hat - e.kinematics.apply_transpose(config_.kd.cwiseProduct(e.s));
    const ParameterVector<Scalar> theta_next =
        theta_hat_ - config_.dt * config_.gamma.cwiseProduct(
                                      phi.transpose() * e.kinematics.apply_inverse(e.s));
    if (!(tau_new.allFinite() && theta_next.allFinite()))
      return refuse(Status::non_finite_output, tau);
    theta_hat_ = theta_next;
    tracking_ = e;
    f_hat_ = f_hat;
    tau = tau_new;
    status_ = Status::ok;
    return Status::ok;
  }

  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return step(eta, nu, d.eta_d, d.eta_d_dot, d.eta_d_ddot, tau);
  }

  /// Back to theta0 and a zero history.
  void reset() noexcept {
    theta_hat_ = config_.theta0;
    tracking_ = TrackingError<Scalar>{};
    f_hat_.setZero();
    status_ = Status::ok;
  }

  /// Replaces theta_hat; false (unchanged) on a NaN/Inf.
  bool set_theta(const ParameterVector<Scalar>& theta) noexcept {
    if (!configured_ || !theta.allFinite()) return false;
    theta_hat_ = theta;
    return true;
  }

  bool configured() const noexcept { return configured_; }
  const Config& config() const noexcept { return config_; }
  const ParameterVector<Scalar>& theta() const noexcept { return theta_hat_; }
  const TrackingError<Scalar>& tracking() const noexcept { return tracking_; }
  /// Phi theta_hat of the last accepted step: the model's estimate of f.
  const Vec6& model_output() const noexcept { return f_hat_; }
  Status last_status() const noexcept { return status_; }

 private:
  Status refuse(Status s, Vec6& tau) noexcept {
    tau.setZero();
    status_ = s;
    return s;
  }

  Config config_{};
  ParameterVector<Scalar> theta_hat_ = ParameterVector<Scalar>::Zero();
  TrackingError<Scalar> tracking_{};
  Vec6 f_hat_ = Vec6::Zero();
  Status status_ = Status::ok;
  bool configured_ = false;
};

}  // namespace neurov
