// Computed-torque (inverse-dynamics) controller on a nominal model, on the
// same sliding variable s = eta_tilde_dot + Lambda eta_tilde as the adaptive
// controllers:
//   tau = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) - J^T(eta) K_d s
// M, C, D and g are the nominal vehicle's own (model/vehicle.hpp), so any
// vehicle file works, in either Coriolis form. On the exact model the body
// error nu - nu_r = J^-1 s obeys
//   M (nu_dot - nu_r_dot) + (C(nu) + D(nu)) (nu - nu_r) = -J^T K_d s
// and s decays (Slotine and Li); a model error leaves a tracking error that
// the adaptive controllers remove.
#pragma once

#include "neurov/control/controller_base.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

template <typename Scalar>
struct ComputedTorqueConfig {
  Vector6<Scalar> lambda = Vector6<Scalar>::Constant(Scalar(0.5));  ///< Lambda (> 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();                     ///< K_d (>= 0)
  /// The nominal model (e.g. the parameters of the vehicle file).
  VehicleParameters<Scalar> vehicle{};
};

template <typename Scalar>
inline ValidationError validate(const ComputedTorqueConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_positive("lambda", c.lambda)) return e;
  if (auto e = detail::check_non_negative("kd", c.kd)) return e;
  return validate(c.vehicle);
}

template <typename ScalarT>
class ComputedTorqueController
    : public ControllerBase<ComputedTorqueController<ScalarT>, ScalarT,
                            ComputedTorqueConfig<ScalarT>> {
  using Base =
      ControllerBase<ComputedTorqueController<ScalarT>, ScalarT, ComputedTorqueConfig<ScalarT>>;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Base::step;

  ComputedTorqueController() = default;

#if NEUROV_HAS_EXCEPTIONS
  explicit ComputedTorqueController(const Config& config) {
    detail::throw_if_invalid(create(config, *this), "computed-torque controller");
  }
#endif

  /// Validates the gains and the nominal vehicle and builds its M once.
  /// `out` is untouched on failure.
  static ValidationError create(const Config& config, ComputedTorqueController& out) noexcept {
    Vehicle<Scalar> model;
    if (auto e = validate(config)) return e;
    if (auto e = Vehicle<Scalar>::create(config.vehicle, model)) return e;
    out.model_ = model;
    return Base::configure(config, out);
  }

  /// tau from the nominal model and s; on any status but ok, tau = 0.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    const Config& c = this->config_;
    TrackingError<Scalar> e;
    if (const Status ts = this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, c.lambda, e, tau);
        ts != Status::ok)
      return ts;
    const auto& trig = e.kinematics.trig;
    const Vec6 f = model_.mass_matrix() * e.nu_r_dot + model_.coriolis(nu) * e.nu_r +
                   model_.damping_diagonal(nu).cwiseProduct(e.nu_r) +
                   model_.restoring(trig.sin_phi, trig.cos_phi, trig.sin_theta, trig.cos_theta);
    const Vec6 tau_new = f - e.kinematics.apply_transpose(c.kd.cwiseProduct(e.s));
    if (!tau_new.allFinite()) return this->refuse(Status::non_finite_output, tau);
    f_ = f;
    return this->accept(e, tau_new, tau);
  }

  void reset() noexcept {
    f_.setZero();
    this->reset_common();
  }

  /// A snapshot's state put back (ControllerBase::restore) with the last
  /// model output; false, and nothing changed, for a non-finite one.
  bool restore(const TrackingError<Scalar>& e, Status s, const Vec6& model_output) noexcept {
    if (!this->restorable(e, s) || !model_output.allFinite()) return false;
    f_ = model_output;
    return Base::restore(e, s);
  }

  /// The nominal vehicle the law inverts.
  const Vehicle<Scalar>& model() const noexcept { return model_; }
  /// M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) of the last step, shape (6,).
  const Vec6& model_output() const noexcept { return f_; }

 private:
  Vehicle<Scalar> model_{};
  Vec6 f_ = Vec6::Zero();
};

}  // namespace neurov
