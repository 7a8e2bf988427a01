// PID controller in the earth frame with anti-windup:
//   tau = -J^T(eta) (K_p eta_tilde + K_i z + K_d eta_tilde_dot),  z_dot = eta_tilde
// The integral term of each DOF is limited to |K_i z| <= integral_limit, and
// a DOF stops integrating while its term sits at that limit and the error
// would push it further (conditional integration), so a long saturation does
// not wind the integrator up.
#pragma once

#include <algorithm>
#include <cmath>

#include "neurov/core/config.hpp"
#include "neurov/control/desired_state.hpp"
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
struct PIDConfig {
  Vector6<Scalar> kp = Vector6<Scalar>::Zero();  ///< K_p (>= 0)
  Vector6<Scalar> ki = Vector6<Scalar>::Zero();  ///< K_i (>= 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();  ///< K_d (>= 0)
  /// Largest |K_i z| per DOF [N or N m] (> 0).
  Vector6<Scalar> integral_limit = Vector6<Scalar>::Constant(Scalar(50));
  Scalar dt = Scalar(0.2);  ///< control period [s]
};

template <typename Scalar>
inline ValidationError validate(const PIDConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_non_negative("kp", c.kp)) return e;
  if (auto e = detail::check_non_negative("ki", c.ki)) return e;
  if (auto e = detail::check_non_negative("kd", c.kd)) return e;
  if (auto e = detail::check_positive("integral_limit", c.integral_limit)) return e;
  if (auto e = detail::check_positive_scalar("dt", static_cast<double>(c.dt))) return e;
  return {};
}

template <typename ScalarT>
class PIDController {
 public:
  using Scalar = ScalarT;
  using Vec6 = Vector6<Scalar>;
  using Config = PIDConfig<Scalar>;

  PIDController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit PIDController(const Config& config) {
    if (const ValidationError e = create(config, *this)) {
      char buf[256];
      e.format(buf, sizeof buf);
      throw std::invalid_argument(std::string("PID controller: ") + buf);
    }
  }
#endif

  static ValidationError create(const Config& config, PIDController& out) noexcept {
    if (auto e = validate(config)) return e;
    out.config_ = config;
    out.configured_ = true;
    out.reset();
    return {};
  }

  /// tau from the errors, then one step of the integrator. On any status but
  /// ok, tau = 0 and the integrator is exactly as before.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    if (!configured_) return refuse(Status::invalid_argument, tau);
    TrackingError<Scalar> e;
    // Lambda only shapes s, which the PID law does not use; any positive value.
    const Status ts =
        compute_tracking_error(eta, nu, eta_d, eta_d_dot, eta_d_ddot, Vec6::Ones().eval(), e);
    if (ts != Status::ok) return refuse(ts, tau);
    const Vec6 integral_term = config_.ki.cwiseProduct(integral_);
    const Vec6 tau_new = -e.kinematics.apply_transpose(config_.kp.cwiseProduct(e.eta_tilde) +
                                                        integral_term +
                                                        config_.kd.cwiseProduct(e.eta_tilde_dot));
    Vec6 next = integral_;
    for (int i = 0; i < 6; ++i) {
      if (config_.ki(i) == Scalar(0)) continue;
      const Scalar limit = config_.integral_limit(i) / config_.ki(i);
      const bool at_limit = std::abs(integral_(i)) >= limit;
      const bool pushing_out = integral_(i) * e.eta_tilde(i) > Scalar(0);
      if (!(at_limit && pushing_out)) next(i) += config_.dt * e.eta_tilde(i);
      next(i) = std::max(-limit, std::min(limit, next(i)));
    }
    if (!(tau_new.allFinite() && next.allFinite())) return refuse(Status::non_finite_output, tau);
    integral_ = next;
    tracking_ = e;
    tau = tau_new;
    status_ = Status::ok;
    return Status::ok;
  }

  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return step(eta, nu, d.eta_d, d.eta_d_dot, d.eta_d_ddot, tau);
  }

  void reset() noexcept {
    integral_.setZero();
    tracking_ = TrackingError<Scalar>{};
    status_ = Status::ok;
  }

  bool configured() const noexcept { return configured_; }
  const Config& config() const noexcept { return config_; }
  /// The integrator state z (the time integral of eta_tilde, limited).
  const Vec6& integral() const noexcept { return integral_; }
  const TrackingError<Scalar>& tracking() const noexcept { return tracking_; }
  Status last_status() const noexcept { return status_; }

 private:
  Status refuse(Status s, Vec6& tau) noexcept {
    tau.setZero();
    status_ = s;
    return s;
  }

  Config config_{};
  Vec6 integral_ = Vec6::Zero();
  TrackingError<Scalar> tracking_{};
  Status status_ = Status::ok;
  bool configured_ = false;
};

}  // namespace neurov
