// PD controller in the earth frame, the simplest baseline:
//   tau = -J^T(eta) (K_p eta_tilde + K_d eta_tilde_dot)
// It knows nothing of the vehicle, so restoring forces and damping leave a
// steady-state error that the adaptive controllers remove.
#pragma once

#include <cmath>

#include "neurov/control/controller_base.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

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
class PDController : public ControllerBase<PDController<ScalarT>, ScalarT, PDConfig<ScalarT>> {
  using Base = ControllerBase<PDController<ScalarT>, ScalarT, PDConfig<ScalarT>>;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Base::step;

  PDController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit PDController(const Config& config) {
    detail::throw_if_invalid(create(config, *this), "PD controller");
  }
#endif

  static ValidationError create(const Config& config, PDController& out) noexcept {
    return Base::configure(config, out);
  }

  /// tau from the errors; on any status but ok, tau = 0.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    TrackingError<Scalar> e;
    // Lambda only shapes s, which the PD law does not use; any positive value.
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot,
                                      Vec6::Ones().eval(), e, tau);
        ts != Status::ok)
      return ts;
    const Config& c = this->config_;
    const Vec6 tau_new = -e.kinematics.apply_transpose(c.kp.cwiseProduct(e.eta_tilde) +
                                                        c.kd.cwiseProduct(e.eta_tilde_dot));
    if (!tau_new.allFinite()) return this->refuse(Status::non_finite_output, tau);
    return this->accept(e, tau_new, tau);
  }
};

}  // namespace neurov
