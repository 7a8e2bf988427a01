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

#include "neurov/control/controller_base.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/regressor.hpp"

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
class SlidingModeController
    : public ControllerBase<SlidingModeController<ScalarT>, ScalarT, SlidingModeConfig<ScalarT>> {
  using Base = ControllerBase<SlidingModeController<ScalarT>, ScalarT, SlidingModeConfig<ScalarT>>;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Base::step;

  SlidingModeController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit SlidingModeController(const Config& config) {
    detail::throw_if_invalid(create(config, *this), "sliding-mode controller");
  }
#endif

  static ValidationError create(const Config& config, SlidingModeController& out) noexcept {
    return Base::configure(config, out);
  }

  /// tau from the model and s; on any status but ok, tau = 0.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    const Config& c = this->config_;
    TrackingError<Scalar> e;
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, c.lambda, e, tau);
        ts != Status::ok)
      return ts;
    const auto& trig = e.kinematics.trig;
    const Vec6 f_hat = regressor<Scalar>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi,
                                         trig.sin_theta, trig.cos_theta) *
                       c.theta;
    Vec6 sat;
    for (int i = 0; i < 6; ++i)
      sat(i) = std::max(Scalar(-1), std::min(Scalar(1), e.s(i) / c.phi(i)));
    const Vec6 tau_new =
        f_hat - e.kinematics.apply_transpose(c.kd.cwiseProduct(e.s) + c.k.cwiseProduct(sat));
    if (!tau_new.allFinite()) return this->refuse(Status::non_finite_output, tau);
    f_hat_ = f_hat;
    return this->accept(e, tau_new, tau);
  }

  void reset() noexcept {
    f_hat_.setZero();
    this->reset_common();
  }

  /// A snapshot's state put back (ControllerBase::restore) with the last
  /// model output; false, and nothing changed, for a non-finite one.
  bool restore(const TrackingError<Scalar>& e, Status s, const Vec6& model_output) noexcept {
    if (!this->restorable(e, s) || !model_output.allFinite()) return false;
    f_hat_ = model_output;
    return Base::restore(e, s);
  }

  /// The nominal model's f of the last step, shape (6,).
  const Vec6& model_output() const noexcept { return f_hat_; }

 private:
  Vec6 f_hat_ = Vec6::Zero();
};

}  // namespace neurov
