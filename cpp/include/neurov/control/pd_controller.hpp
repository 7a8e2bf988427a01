// PD controller in the earth frame, the simplest baseline:
//   tau = -J^T(eta) (K_p eta_tilde + K_d eta_tilde_dot)
// It knows nothing of the vehicle, so restoring forces and damping leave a
// steady-state error that the adaptive controllers remove.
#pragma once

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
struct PDConfig {
  Vector6<Scalar> kp = Vector6<Scalar>::Zero();  ///< K_p (>= 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();  ///< K_d (>= 0)
};

template <typename Scalar>
inline ValidationError validate(const PDConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_non_negative("kp", c.kp)) return e;
  if (auto e = detail::check_non_negative("kd", c.kd)) return e;
  return {};
}

template <typename ScalarT>
class PDController {
 public:
  using Scalar = ScalarT;
  using Vec6 = Vector6<Scalar>;
  using Config = PDConfig<Scalar>;

  PDController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit PDController(const Config& config) {
    if (const ValidationError e = create(config, *this)) {
      char buf[256];
      e.format(buf, sizeof buf);
      throw std::invalid_argument(std::string("PD controller: ") + buf);
    }
  }
#endif

  static ValidationError create(const Config& config, PDController& out) noexcept {
    if (auto e = validate(config)) return e;
    out.config_ = config;
    out.configured_ = true;
    out.reset();
    return {};
  }

  /// tau from the errors; on any status but ok, tau = 0.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    if (!configured_) return refuse(Status::invalid_argument, tau);
    TrackingError<Scalar> e;
    // Lambda only shapes s, which the PD law does not use; any positive value.
    const Status ts =
        compute_tracking_error(eta, nu, eta_d, eta_d_dot, eta_d_ddot, Vec6::Ones().eval(), e);
    if (ts != Status::ok) return refuse(ts, tau);
    const Vec6 tau_new = -e.kinematics.apply_transpose(config_.kp.cwiseProduct(e.eta_tilde) +
                                                        config_.kd.cwiseProduct(e.eta_tilde_dot));
    if (!tau_new.allFinite()) return refuse(Status::non_finite_output, tau);
    tracking_ = e;
    tau = tau_new;
    status_ = Status::ok;
    return Status::ok;
  }

  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return step(eta, nu, d.eta_d, d.eta_d_dot, d.eta_d_ddot, tau);
  }

  void reset() noexcept {
    tracking_ = TrackingError<Scalar>{};
    status_ = Status::ok;
  }

  bool configured() const noexcept { return configured_; }
  const Config& config() const noexcept { return config_; }
  const TrackingError<Scalar>& tracking() const noexcept { return tracking_; }
  Status last_status() const noexcept { return status_; }

 private:
  Status refuse(Status s, Vec6& tau) noexcept {
    tau.setZero();
    status_ = s;
    return s;
  }

  Config config_{};
  TrackingError<Scalar> tracking_{};
  Status status_ = Status::ok;
  bool configured_ = false;
};

}  // namespace neurov
