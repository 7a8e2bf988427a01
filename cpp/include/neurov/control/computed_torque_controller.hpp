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
#include "neurov/core/field_spec.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

template <typename Scalar>
struct ComputedTorqueConfig : SlidingGains<Scalar> {
  /// The nominal model (e.g. the parameters of the vehicle file).
  VehicleParameters<Scalar> vehicle{};
};

template <typename Scalar>
auto config_fields(const ComputedTorqueConfig<Scalar>*) noexcept {
  using C = ComputedTorqueConfig<Scalar>;
  return std::tuple_cat(detail::sliding_gain_fields<C>(),
                        std::make_tuple(field_spec<C>("vehicle", &C::vehicle,
                                                      "The nominal model, a Vehicle (None until set).")));
}

template <typename Scalar>
inline ValidationError validate(const ComputedTorqueConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_sliding_gains(c)) return e;
  return validate(c.vehicle);
}

template <typename ScalarT>
class ComputedTorqueController
    : public ModelControllerBase<ComputedTorqueController<ScalarT>, ScalarT,
                                 ComputedTorqueConfig<ScalarT>> {
  using Base = ModelControllerBase<ComputedTorqueController<ScalarT>, ScalarT,
                                   ComputedTorqueConfig<ScalarT>>;
  friend ControllerBase<ComputedTorqueController<ScalarT>, ScalarT, ComputedTorqueConfig<ScalarT>>;

 public:
  using typename Base::Vec6;

  NEUROV_CONTROLLER_NAMES("computed_torque", "computed torque", "ComputedTorqueController")
  static constexpr const char* kDoc =
      "Computed-torque (inverse-dynamics) controller on a nominal vehicle: tau = M nu_r_dot + "
      "C(nu) nu_r + D(nu) nu_r + g(eta) - J^T K_d s, with the vehicle's own M, C, D and g.";
  NEUROV_CONTROLLER_CONSTRUCTORS(ComputedTorqueController, "computed-torque controller")

  /// Validates the gains and the nominal vehicle and builds its M once.
  /// `out` is untouched on failure.
  static ValidationError create(const ComputedTorqueConfig<ScalarT>& config,
                                ComputedTorqueController& out) noexcept {
    Vehicle<ScalarT> model;
    if (auto e = validate(config)) return e;
    if (auto e = Vehicle<ScalarT>::create(config.vehicle, model)) return e;
    out.model_ = model;
    return Base::configure(config, out);
  }

  /// The nominal vehicle the law inverts.
  const Vehicle<ScalarT>& model() const noexcept { return model_; }

 private:
  /// f = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) of the nominal model.
  bool control(const TrackingError<ScalarT>& e, const Vec6& nu, Vec6& tau) noexcept {
    const auto& trig = e.kinematics.trig;
    const Vec6 f = model_.mass_matrix() * e.nu_r_dot + model_.coriolis(nu) * e.nu_r +
                   model_.damping_diagonal(nu).cwiseProduct(e.nu_r) +
                   model_.restoring(trig.sin_phi, trig.cos_phi, trig.sin_theta, trig.cos_theta);
    return this->apply_model(e, f, this->config_.kd.cwiseProduct(e.s), tau);
  }

  Vehicle<ScalarT> model_{};
};

}  // namespace neurov
