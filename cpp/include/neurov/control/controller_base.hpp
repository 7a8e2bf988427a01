// The skeleton every controller follows (CRTP), so that what is the same in
// all of them is written once: the refused step (tau = 0, state unchanged),
// the DesiredState overload of step(), the shared tracking-error call, the
// bookkeeping of an accepted step, create() for a controller that is its
// configuration, reset(), and the diagnostics the closed loop logs.
//
// A controller Derived derives from ControllerBase<Derived, Scalar, Config>
// and supplies
//   Status step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau) noexcept;
// plus, when it has state of its own, reset() (calling reset_common()),
// adaptive_norm() and logged_parameters() with kLoggedParameters. It brings
// the base's step overload in with `using Base::step;`.
#pragma once

#include <Eigen/Core>

#include "neurov/control/desired_state.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/config.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

#if NEUROV_HAS_EXCEPTIONS
#include <stdexcept>
#include <string>
#endif

namespace neurov {

namespace detail {

#if NEUROV_HAS_EXCEPTIONS
/// The throwing constructors' one check: std::invalid_argument "what: message".
inline void throw_if_invalid(const ValidationError& e, const char* what) {
  if (!e) return;
  char buf[256];
  e.format(buf, sizeof buf);
  throw std::invalid_argument(std::string(what) + ": " + buf);
}
#endif

}  // namespace detail

template <typename Derived, typename ScalarT, typename ConfigT>
class ControllerBase {
 public:
  using Scalar = ScalarT;
  using Vec6 = Vector6<Scalar>;
  using Config = ConfigT;
  /// How many adaptive parameters the closed loop logs per step (the columns
  /// of SimulationResult::theta): none unless the controller says otherwise.
  static constexpr int kLoggedParameters = 0;
  using LoggedParameters = Eigen::Matrix<Scalar, kLoggedParameters, 1>;

  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return derived().step(eta, nu, d.eta_d, d.eta_d_dot, d.eta_d_ddot, tau);
  }

  /// Back to the initial state and a zero history.
  void reset() noexcept { reset_common(); }

  /// Puts back the tracking error and last status a snapshot recorded (a
  /// copy made elsewhere, e.g. by Python's pickle): false, and nothing
  /// changed, for an unconfigured controller, a non-finite error or an
  /// unknown status.
  bool restore(const TrackingError<Scalar>& e, Status s) noexcept {
    if (!restorable(e, s)) return false;
    tracking_ = e;
    status_ = s;
    return true;
  }

  bool configured() const noexcept { return configured_; }
  const Config& config() const noexcept { return config_; }
  /// Tracking error and virtual reference of the last accepted step.
  const TrackingError<Scalar>& tracking() const noexcept { return tracking_; }
  Status last_status() const noexcept { return status_; }

  /// How far the controller's memory has moved, for logs: 0 for a
  /// controller without one.
  Scalar adaptive_norm() const noexcept { return Scalar(0); }
  /// The adaptive parameters logged per step: none by default.
  LoggedParameters logged_parameters() const noexcept { return LoggedParameters(); }

 protected:
  ControllerBase() = default;

  /// create() of a controller that is its configuration: validate, copy,
  /// reset. `out` is untouched on failure.
  static ValidationError configure(const Config& config, Derived& out) noexcept {
    if (auto e = validate(config)) return e;
    out.config_ = config;
    out.configured_ = true;
    out.reset();
    return {};
  }

  /// The check of restore(), for the derived controllers' restore().
  bool restorable(const TrackingError<Scalar>& e, Status s) const noexcept {
    return configured_ && static_cast<int>(s) <= static_cast<int>(Status::non_finite_output) &&
           detail::all_finite(e.eta_tilde, e.eta_tilde_dot, e.s, e.eta_r_dot, e.eta_r_ddot,
                              e.nu_r, e.nu_r_dot);
  }

  /// The first part of every step: refuses an unconfigured controller and
  /// fills `e` from the measurements; on any status but ok tau = 0 and the
  /// status is recorded.
  Status track(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
               const Vec6& eta_d_ddot, const Vec6& lambda, TrackingError<Scalar>& e,
               Vec6& tau) noexcept {
    if (!configured_) return refuse(Status::invalid_argument, tau);
    const Status ts = compute_tracking_error(eta, nu, eta_d, eta_d_dot, eta_d_ddot, lambda, e);
    if (ts != Status::ok) return refuse(ts, tau);
    return Status::ok;
  }

  /// A refused step: tau = 0, nothing else changes but the status.
  Status refuse(Status s, Vec6& tau) noexcept {
    tau.setZero();
    status_ = s;
    return s;
  }

  /// The last part of an accepted step.
  Status accept(const TrackingError<Scalar>& e, const Vec6& tau_new, Vec6& tau) noexcept {
    tracking_ = e;
    tau = tau_new;
    status_ = Status::ok;
    return Status::ok;
  }

  void reset_common() noexcept {
    tracking_ = TrackingError<Scalar>{};
    status_ = Status::ok;
  }

  Derived& derived() noexcept { return static_cast<Derived&>(*this); }

  Config config_{};
  TrackingError<Scalar> tracking_{};
  Status status_ = Status::ok;
  bool configured_ = false;
};

}  // namespace neurov
