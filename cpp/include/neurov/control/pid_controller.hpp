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
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

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
class PIDController
    : public ControllerBase<PIDController<ScalarT>, ScalarT, PIDConfig<ScalarT>> {
  using Base = ControllerBase<PIDController<ScalarT>, ScalarT, PIDConfig<ScalarT>>;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Base::step;

  PIDController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit PIDController(const Config& config) {
    detail::throw_if_invalid(create(config, *this), "PID controller");
  }
#endif

  static ValidationError create(const Config& config, PIDController& out) noexcept {
    return Base::configure(config, out);
  }

  /// tau from the errors, then one step of the integrator. On any status but
  /// ok, tau = 0 and the integrator is exactly as before.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    TrackingError<Scalar> e;
    // Lambda only shapes s, which the PID law does not use; any positive value.
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot,
                                      Vec6::Ones().eval(), e, tau);
        ts != Status::ok)
      return ts;
    const Config& c = this->config_;
    const Vec6 integral_term = c.ki.cwiseProduct(integral_);
    const Vec6 tau_new = -e.kinematics.apply_transpose(c.kp.cwiseProduct(e.eta_tilde) +
                                                        integral_term +
                                                        c.kd.cwiseProduct(e.eta_tilde_dot));
    Vec6 next = integral_;
    for (int i = 0; i < 6; ++i) {
      if (c.ki(i) == Scalar(0)) continue;
      const Scalar limit = c.integral_limit(i) / c.ki(i);
      const bool at_limit = std::abs(integral_(i)) >= limit;
      const bool pushing_out = integral_(i) * e.eta_tilde(i) > Scalar(0);
      if (!(at_limit && pushing_out)) next(i) += c.dt * e.eta_tilde(i);
      next(i) = std::max(-limit, std::min(limit, next(i)));
    }
    if (!(tau_new.allFinite() && next.allFinite()))
      return this->refuse(Status::non_finite_output, tau);
    integral_ = next;
    return this->accept(e, tau_new, tau);
  }

  void reset() noexcept {
    integral_.setZero();
    this->reset_common();
  }

  /// A snapshot's state put back (ControllerBase::restore) with the
  /// integrator z; false, and nothing changed, for a non-finite one.
  bool restore(const TrackingError<Scalar>& e, Status s, const Vec6& integral) noexcept {
    if (!this->restorable(e, s) || !integral.allFinite()) return false;
    integral_ = integral;
    return Base::restore(e, s);
  }

  /// The integrator state z (the time integral of eta_tilde, limited).
  const Vec6& integral() const noexcept { return integral_; }
  /// The integrator is the PID's only memory: ||z||.
  Scalar adaptive_norm() const noexcept { return integral_.norm(); }

 private:
  Vec6 integral_ = Vec6::Zero();
};

}  // namespace neurov
