// Reference model (eq. 12-13, with the printed J^T in eq. 13 read as J):
//   nu_d_dot  = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d)
//   eta_d_dot =  J(eta_d) nu_d
// A second-order filter in the earth frame that turns a commanded pose r into
// a smooth (eta_d, eta_d_dot, eta_d_ddot). Near eta_d = r with small angles it
// is eta_d_ddot + Lambda_d eta_d_dot + Omega (eta_d - r) = 0 per DOF.
#pragma once

#include <cmath>

#include "neurov/config.hpp"
#include "neurov/desired_state.hpp"
#include "neurov/kinematics.hpp"
#include "neurov/status.hpp"
#include "neurov/types.hpp"
#include "neurov/validation.hpp"

#if NEUROV_HAS_EXCEPTIONS
#include <stdexcept>
#include <string>
#endif

namespace neurov {

template <typename Scalar>
class ReferenceModel {
 public:
  using Vec6 = Vector6<Scalar>;

  /// Unconfigured: step() returns invalid_argument until create() fills it.
  ReferenceModel() = default;

#if NEUROV_HAS_EXCEPTIONS
  /// lambda_d: damping diagonal (> 0); omega: stiffness diagonal (> 0).
  ReferenceModel(const Vec6& lambda_d, const Vec6& omega, const Vec6& eta0 = Vec6::Zero()) {
    if (const ValidationError e = create(lambda_d, omega, eta0, *this)) {
      char buf[256];
      e.format(buf, sizeof buf);
      throw std::invalid_argument(std::string("reference model: ") + buf);
    }
  }
#endif

  /// Validates and builds; `out` is untouched on failure. The model starts at
  /// rest at eta0.
  static ValidationError create(const Vec6& lambda_d, const Vec6& omega, const Vec6& eta0,
                                ReferenceModel& out) noexcept {
    if (auto e = detail::check_positive("lambda_d", lambda_d)) return e;
    if (auto e = detail::check_positive("omega", omega)) return e;
    if (auto e = detail::check_finite("eta0", eta0)) return e;
    if (EulerTrig<Scalar>::from_pose(eta0).status != Status::ok)
      return detail::invalid("eta0", 4, static_cast<double>(eta0(4)),
                             "a pitch away from +-90 deg");
    out.lambda_d_ = lambda_d;
    out.omega_ = omega;
    out.configured_ = true;
    out.reset(eta0);
    return {};
  }

  /// Back to rest at eta0 (nu_d = 0). A non-finite eta0 is refused (false).
  bool reset(const Vec6& eta0, const Vec6& nu_d0 = Vec6::Zero()) noexcept {
    if (!(eta0.allFinite() && nu_d0.allFinite())) return false;
    eta_d_ = eta0;
    nu_d_ = nu_d0;
    fill_desired(eta_d_, nu_d_, Vec6::Zero());
    return true;
  }

  /// Advances by dt with r held (RK4) and writes the new desired state. On
  /// any error status the model's state is unchanged and `out` keeps the
  /// last good desired state.
  Status step(const Vec6& r, Scalar dt, DesiredState<Scalar>& out) noexcept {
    if (!configured_ || !(std::isfinite(dt) && dt > Scalar(0))) {
      out = desired_;
      return Status::invalid_argument;
    }
    if (!r.allFinite()) {
      out = desired_;
      return Status::non_finite_input;
    }
    Vec6 k1e, k1n, k2e, k2n, k3e, k3n, k4e, k4n;
    const Scalar h2 = Scalar(0.5) * dt;
    Status s = derivative(eta_d_, nu_d_, r, k1e, k1n);
    s = worst(s, derivative(eta_d_ + h2 * k1e, nu_d_ + h2 * k1n, r, k2e, k2n));
    s = worst(s, derivative(eta_d_ + h2 * k2e, nu_d_ + h2 * k2n, r, k3e, k3n));
    s = worst(s, derivative(eta_d_ + dt * k3e, nu_d_ + dt * k3n, r, k4e, k4n));
    const Scalar h6 = dt / Scalar(6);
    const Vec6 eta_next = eta_d_ + h6 * (k1e + Scalar(2) * (k2e + k3e) + k4e);
    const Vec6 nu_next = nu_d_ + h6 * (k1n + Scalar(2) * (k2n + k3n) + k4n);
    if (s == Status::ok && !(eta_next.allFinite() && nu_next.allFinite()))
      s = Status::non_finite_output;
    if (s == Status::ok) {
      Vec6 nu_dot;
      Vec6 unused;
      s = derivative(eta_next, nu_next, r, unused, nu_dot);
      if (s == Status::ok) {
        // A finite state can still give a desired velocity or acceleration
        // that overflows (a command of 1e308): refuse it, keep the last good one.
        const DesiredState<Scalar> previous = desired_;
        fill_desired(eta_next, nu_next, nu_dot);
        if (desired_.eta_d_dot.allFinite() && desired_.eta_d_ddot.allFinite()) {
          eta_d_ = eta_next;
          nu_d_ = nu_next;
        } else {
          desired_ = previous;
          s = Status::non_finite_output;
        }
      }
    }
    out = desired_;
    return s;
  }

  const Vec6& eta_d() const noexcept { return eta_d_; }
  const Vec6& nu_d() const noexcept { return nu_d_; }
  const DesiredState<Scalar>& desired() const noexcept { return desired_; }
  const Vec6& lambda_d() const noexcept { return lambda_d_; }
  const Vec6& omega() const noexcept { return omega_; }

 private:
  Status derivative(const Vec6& eta_d, const Vec6& nu_d, const Vec6& r, Vec6& eta_d_dot,
                    Vec6& nu_d_dot) const noexcept {
    const auto k = EulerKinematics<Scalar>::from_pose(eta_d);
    eta_d_dot = k.apply(nu_d);
    nu_d_dot = -lambda_d_.cwiseProduct(nu_d) + k.apply_transpose(omega_.cwiseProduct(r - eta_d));
    return k.status();
  }

  void fill_desired(const Vec6& eta_d, const Vec6& nu_d, const Vec6& nu_d_dot) noexcept {
    const auto k = EulerKinematics<Scalar>::from_pose(eta_d);
    desired_.eta_d = eta_d;
    desired_.eta_d_dot = k.apply(nu_d);
    // eta_d_ddot = J nu_d_dot + J_dot nu_d.
    desired_.eta_d_ddot = k.apply(nu_d_dot) + k.apply_dot(nu_d, nu_d);
  }

  Vec6 lambda_d_ = Vec6::Ones();
  Vec6 omega_ = Vec6::Ones();
  Vec6 eta_d_ = Vec6::Zero();
  Vec6 nu_d_ = Vec6::Zero();
  DesiredState<Scalar> desired_{};
  bool configured_ = false;
};

}  // namespace neurov
