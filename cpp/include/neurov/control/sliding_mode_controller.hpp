// Sliding-mode controller with a boundary layer, on the same sliding variable
// s = eta_tilde_dot + Lambda eta_tilde as the adaptive controllers:
//   tau = Phi theta_nominal - J^T(eta) (K_d s + K sat(s / phi))
// Phi theta_nominal is the nominal model's M nu_r_dot + C nu_r + D nu_r + g
// (regressor.hpp); the switching term K sat(s / phi) covers a bounded model
// error, and the boundary layer phi trades the chattering of sign(s) for a
// tracking error of order phi.
#pragma once

#include <algorithm>
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
struct SlidingModeConfig {
  Vector6<Scalar> lambda = Vector6<Scalar>::Constant(Scalar(0.5));  ///< Lambda (> 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();                     ///< K_d (>= 0)
  Vector6<Scalar> k = Vector6<Scalar>::Zero();    ///< switching gain K (>= 0) [N, N m]
  Vector6<Scalar> phi = Vector6<Scalar>::Ones();  ///< boundary-layer width (> 0), units of s
  /// The nominal model's theta (e.g. regressor_parameters of the vehicle file).
  ParameterVector<Scalar> theta = ParameterVector<Scalar>::Zero();
};

template <typename Scalar>
inline ValidationError validate(const SlidingModeConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_positive("lambda", c.lambda)) return e;
  if (auto e = detail::check_non_negative("kd", c.kd)) return e;
  if (auto e = detail::check_non_negative("k", c.k)) return e;
  if (auto e = detail::check_positive("phi", c.phi)) return e;
  if (auto e = detail::check_finite("theta", c.theta)) return e;
  return {};
}

template <typename ScalarT>
class SlidingModeController {
 public:
  using Scalar = ScalarT;
  using Vec6 = Vector6<Scalar>;
  using Config = SlidingModeConfig<Scalar>;

  SlidingModeController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit SlidingModeController(const Config& config) {
    if (const ValidationError e = create(config, *this)) {
      char buf[256];
      e.format(buf, sizeof buf);
      throw std::invalid_argument(std::string("sliding-mode controller: ") + buf);
    }
  }
#endif

  static ValidationError create(const Config& config, SlidingModeController& out) noexcept {
    if (auto e = validate(config)) return e;
    out.config_ = config;
    out.configured_ = true;
    out.reset();
    return {};
  }

  /// tau from the model and s; on any status but ok, tau = 0.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    if (!configured_) return refuse(Status::invalid_argument, tau);
    TrackingError<Scalar> e;
    const Status ts = compute_tracking_error(eta, nu, eta_d, eta_d_dot, eta_d_ddot,
                                             config_.lambda, e);
    if (ts != Status::ok) return refuse(ts, tau);
    const auto& trig = e.kinematics.trig;
    const Vec6 f_hat = regressor<Scalar>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi,
                                         trig.sin_theta, trig.cos_theta) *
                       config_.theta;
    Vec6 sat;
    for (int i = 0; i < 6; ++i)
      sat(i) = std::max(Scalar(-1), std::min(Scalar(1), e.s(i) / config_.phi(i)));
    const Vec6 tau_new = f_hat - e.kinematics.apply_transpose(config_.kd.cwiseProduct(e.s) +
                                                               config_.k.cwiseProduct(sat));
    if (!tau_new.allFinite()) return refuse(Status::non_finite_output, tau);
    tracking_ = e;
    f_hat_ = f_hat;
    tau = tau_new;
    status_ = Status::ok;
    return Status::ok;
  }

  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return step(eta, nu, d.eta_d, d.eta_d_dot, d.eta_d_ddot, tau);
  }

  void reset() noexcept {
    tracking_ = TrackingError<Scalar>{};
    f_hat_.setZero();
    status_ = Status::ok;
  }

  bool configured() const noexcept { return configured_; }
  const Config& config() const noexcept { return config_; }
  const TrackingError<Scalar>& tracking() const noexcept { return tracking_; }
  /// The nominal model's f of the last step, shape (6,).
  const Vec6& model_output() const noexcept { return f_hat_; }
  Status last_status() const noexcept { return status_; }

 private:
  Status refuse(Status s, Vec6& tau) noexcept {
    tau.setZero();
    status_ = s;
    return s;
  }

  Config config_{};
  TrackingError<Scalar> tracking_{};
  Vec6 f_hat_ = Vec6::Zero();
  Status status_ = Status::ok;
  bool configured_ = false;
};

}  // namespace neurov
