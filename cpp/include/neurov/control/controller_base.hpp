// The skeleton every controller follows (CRTP), so that what is the same in
// all of them is written once: create() for a controller that is its
// configuration, the step (refuse an unconfigured controller, compute the
// tracking error, run the law, refuse a non-finite force or accept), its
// DesiredState overload, reset(), restore() and the diagnostics the closed
// loop logs. VectorStateControllerBase adds a state of one (6,) vector (the
// PID's integrator); ModelControllerBase makes it the model output f of the
// laws tau = f - J^T K_d s and the like.
//
// A controller Derived derives from one of them, befriends
// ControllerBase<Derived, Scalar, Config> and supplies the law on the
// tracking error, bool control(const TrackingError<Scalar>& e, const Vec6&
// nu, Vec6& tau) noexcept, which writes tau, commits its own state only when
// the step can be accepted and returns false for a non-finite result (the
// step is then refused with non_finite_output). With more state it adds
// reset() (calling its base's), adaptive_norm() and logged_parameters() with
// kLoggedParameters. A controller whose step does more (the NN) writes
// step() itself from track(), refuse() and accept().
#pragma once

#include <Eigen/Core>
#include <tuple>
#include <type_traits>

// What every controller uses, so that a controller's header includes this
// one and what its law needs besides.
#include "neurov/control/desired_state.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/config.hpp"
#include "neurov/core/field_spec.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

/// A controller's two constructors, written once: the default one
/// (unconfigured: every step refuses until create()) and, where exceptions
/// exist, the one that validates the configuration through the controller's
/// create() and throws std::invalid_argument "what: message". A constructor
/// inherited from the base cannot do this: it would run create() before the
/// controller's own members are initialised, which would then overwrite it.
#if NEUROV_HAS_EXCEPTIONS
#define NEUROV_CONTROLLER_CONSTRUCTORS(Controller, what)                  \
  static constexpr const char* kWhat = what;                              \
  Controller() = default;                                                 \
  explicit Controller(const typename Controller::Config& config) {        \
    ::neurov::throw_if_invalid(Controller::create(config, *this), what);  \
  }
#else
#define NEUROV_CONTROLLER_CONSTRUCTORS(Controller, what) \
  static constexpr const char* kWhat = what;             \
  Controller() = default;
#endif

/// A built-in controller's names (control/built_in_controllers.hpp): its
/// `type` in a scenario file, its name in tables and plots, and its Python
/// class (whose configuration class is the same name with Config for
/// Controller).
#define NEUROV_CONTROLLER_NAMES(type_name, title, class_name)  \
  static constexpr const char* kTypeName = type_name;          \
  static constexpr const char* kTitle = title;                 \
  static constexpr const char* kClassName = class_name;

namespace neurov {

/// The gains every law on the filtered error s shares: Lambda in
/// s = eta_tilde_dot + Lambda eta_tilde and the damping K_d of its
/// -J^T(eta) K_d s. The configurations of the sliding-mode, linear adaptive,
/// computed-torque and NN controllers start with them (one default, one
/// validator: detail::check_sliding_gains).
template <typename Scalar>
struct SlidingGains {
  /// Lambda (diagonal, > 0).
  Vector6<Scalar> lambda = Vector6<Scalar>::Constant(Scalar(0.5));
  /// K_d (diagonal, >= 0; for the NN, 0 leaves the network alone in the loop).
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();
};

namespace detail {

/// Lambda > 0 and K_d >= 0: the gains of every law on s.
template <typename Scalar>
inline ValidationError check_sliding_gains(const SlidingGains<Scalar>& c) noexcept {
  if (auto e = check_positive("lambda", c.lambda)) return e;
  return check_non_negative("kd", c.kd);
}

/// The descriptions of Lambda and K_d as fields of Config (a SlidingGains).
template <typename Config>
constexpr auto sliding_gain_fields() noexcept {
  using Gains = SlidingGains<typename decltype(Config::lambda)::Scalar>;
  return std::make_tuple(
      field_spec<Config>("lambda_", &Gains::lambda, "", Check::positive,
                         "Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,)"),
      field_spec<Config>("kd", &Gains::kd, "", Check::non_negative, "K_d, diagonal (6,)"));
}

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

  /// Validates, copies and resets; `out` is untouched on failure.
  static ValidationError create(const Config& config, Derived& out) noexcept {
    return configure(config, out);
  }

  /// tau from the measurements and the desired trajectory. On any status but
  /// ok, tau = 0 and the controller's state is exactly as before.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    TrackingError<Scalar> e;
    if (const Status ts = track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, lambda(), e, tau);
        ts != Status::ok)
      return ts;
    Vec6 tau_new;
    if (!derived().control(e, nu, tau_new)) return refuse(Status::non_finite_output, tau);
    return accept(e, tau_new, tau);
  }

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

  /// The Lambda of s: the configuration's; a law without one (PD, PID) does
  /// not use s, and any positive value does.
  Vec6 lambda() const noexcept {
    if constexpr (std::is_base_of<SlidingGains<Scalar>, Config>::value)
      return config_.lambda;
    else
      return Vec6::Ones();
  }

  Derived& derived() noexcept { return static_cast<Derived&>(*this); }

  Config config_{};
  TrackingError<Scalar> tracking_{};
  Status status_ = Status::ok;
  bool configured_ = false;
};

/// The base of a controller whose own state is one (6,) vector (the PID's
/// integrator, a model's last output): zero after reset(), put back by
/// restore().
template <typename Derived, typename ScalarT, typename ConfigT>
class VectorStateControllerBase : public ControllerBase<Derived, ScalarT, ConfigT> {
  using Base = ControllerBase<Derived, ScalarT, ConfigT>;

 public:
  using typename Base::Vec6;

  void reset() noexcept {
    state_.setZero();
    this->reset_common();
  }

  /// The (6,) state restore() puts back, for snapshots.
  const Vec6& state() const noexcept { return state_; }

  /// A snapshot's state put back (ControllerBase::restore) with the vector;
  /// false, and nothing changed, for a non-finite one.
  bool restore(const TrackingError<ScalarT>& e, Status s, const Vec6& state) noexcept {
    if (!this->restorable(e, s) || !state.allFinite()) return false;
    state_ = state;
    return Base::restore(e, s);
  }

 protected:
  VectorStateControllerBase() = default;

  Vec6 state_ = Vec6::Zero();
};

/// The base of the laws that run a nominal model or an estimate of one, f:
/// their state is f of the last accepted step, for plots and snapshots.
template <typename Derived, typename ScalarT, typename ConfigT>
class ModelControllerBase : public VectorStateControllerBase<Derived, ScalarT, ConfigT> {
 public:
  using Vec6 = Vector6<ScalarT>;

  /// The model's f of the last accepted step, shape (6,).
  const Vec6& model_output() const noexcept { return this->state_; }

 protected:
  ModelControllerBase() = default;

  /// The end of a law tau = f - J^T(eta) k: false for a non-finite tau, else
  /// f kept.
  bool apply_model(const TrackingError<ScalarT>& e, const Vec6& f, const Vec6& k,
                   Vec6& tau) noexcept {
    tau = f - e.kinematics.apply_transpose(k);
    if (!tau.allFinite()) return false;
    this->state_ = f;
    return true;
  }
};

}  // namespace neurov
