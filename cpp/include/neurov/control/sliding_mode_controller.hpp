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
#include "neurov/core/field_spec.hpp"
#include "neurov/model/regressor.hpp"

namespace neurov {

template <typename Scalar>
struct SlidingModeConfig : SlidingGains<Scalar> {
  Vector6<Scalar> k = Vector6<Scalar>::Zero();    ///< switching gain K (>= 0) [N, N m]
  Vector6<Scalar> phi = Vector6<Scalar>::Ones();  ///< boundary-layer width (> 0), units of s
  /// The nominal model's theta (e.g. regressor_parameters of the vehicle file).
  ParameterVector<Scalar> theta = ParameterVector<Scalar>::Zero();
};

template <typename Scalar>
auto config_fields(const SlidingModeConfig<Scalar>*) noexcept {
  using C = SlidingModeConfig<Scalar>;
  return std::tuple_cat(
      detail::sliding_gain_fields<C>(),
      std::make_tuple(
          field_spec<C>("k", &C::k, "N, N m", Check::non_negative, "Switching gain K (6,)"),
          field_spec<C>("phi", &C::phi, "units of s", Check::positive, "Boundary-layer width (6,)"),
          field_spec<C>("theta", &C::theta, "", Check::finite,
                        "The nominal model's theta (24,), e.g. regressor_parameters(vehicle)")));
}

/// Lambda first (named "lambda"), then the fields' rules.
template <typename Scalar>
inline ValidationError validate(const SlidingModeConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_sliding_gains(c)) return e;
  return check_fields(c);
}

template <typename ScalarT>
class SlidingModeController
    : public ModelControllerBase<SlidingModeController<ScalarT>, ScalarT,
                                 SlidingModeConfig<ScalarT>> {
  using Base =
      ModelControllerBase<SlidingModeController<ScalarT>, ScalarT, SlidingModeConfig<ScalarT>>;
  friend ControllerBase<SlidingModeController<ScalarT>, ScalarT, SlidingModeConfig<ScalarT>>;

 public:
  using typename Base::Vec6;

  NEUROV_CONTROLLER_NAMES("smc", "sliding mode", "SlidingModeController")
  static constexpr const char* kDoc =
      "Sliding-mode controller with a boundary layer: tau = Phi theta - J^T (K_d s + K "
      "sat(s / phi)), with theta the nominal model's parameters (regressor).";
  NEUROV_CONTROLLER_CONSTRUCTORS(SlidingModeController, "sliding-mode controller")

 private:
  /// f = Phi theta_nominal, then the switching term on sat(s / phi).
  bool control(const TrackingError<ScalarT>& e, const Vec6& nu, Vec6& tau) noexcept {
    const auto& c = this->config_;
    const Vec6 f_hat = reference_regressor(e, nu) * c.theta;
    Vec6 sat;
    for (int i = 0; i < 6; ++i)
      sat(i) = std::max(ScalarT(-1), std::min(ScalarT(1), e.s(i) / c.phi(i)));
    return this->apply_model(e, f_hat, c.kd.cwiseProduct(e.s) + c.k.cwiseProduct(sat), tau);
  }
};

}  // namespace neurov
