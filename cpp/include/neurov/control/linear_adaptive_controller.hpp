// Linearly parameterised adaptive controller of Fossen and Sagatun (eq. 26, 28):
//   tau = Phi theta_hat - J^T(eta) K_d s
//   theta_hat <- theta_hat - dt Gamma Phi^T J^-1(eta) s    (one Euler step)
// It knows the structure of the model (regressor.hpp); only theta is unknown.
#pragma once

#include "neurov/control/controller_base.hpp"
#include "neurov/core/field_spec.hpp"
#include "neurov/model/regressor.hpp"

namespace neurov {

template <typename Scalar>
struct LinearAdaptiveConfig : SlidingGains<Scalar> {
  /// Diagonal of Gamma (>= 0; 0 freezes that parameter).
  ParameterVector<Scalar> gamma = ParameterVector<Scalar>::Constant(Scalar(1));
  Scalar dt = Scalar(0.2);                                          ///< control period [s]
  /// theta_hat(0): zero, or a nominal guess such as regressor_parameters().
  ParameterVector<Scalar> theta0 = ParameterVector<Scalar>::Zero();
};

template <typename Scalar>
auto config_fields(const LinearAdaptiveConfig<Scalar>*) noexcept {
  using C = LinearAdaptiveConfig<Scalar>;
  return std::tuple_cat(
      detail::sliding_gain_fields<C>(),
      std::make_tuple(
          field_spec<C>("gamma", &C::gamma, "", Check::non_negative,
                        "Diagonal of Gamma (24,) (0 freezes that parameter); a number sets every "
                        "entry",
                        kNumberFills),
          field_spec<C>("dt", &C::dt, "s", Check::positive, "Control period"),
          field_spec<C>("theta0", &C::theta0, "", Check::finite,
                        "theta_hat(0) (24,): zero, or a nominal guess such as "
                        "regressor_parameters(vehicle)")));
}

/// Lambda first (named "lambda"), then the fields' rules.
template <typename Scalar>
inline ValidationError validate(const LinearAdaptiveConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_sliding_gains(c)) return e;
  return check_fields(c);
}

template <typename ScalarT>
class LinearAdaptiveController
    : public ModelControllerBase<LinearAdaptiveController<ScalarT>, ScalarT,
                                 LinearAdaptiveConfig<ScalarT>> {
  using Base = ModelControllerBase<LinearAdaptiveController<ScalarT>, ScalarT,
                                   LinearAdaptiveConfig<ScalarT>>;
  friend ControllerBase<LinearAdaptiveController<ScalarT>, ScalarT, LinearAdaptiveConfig<ScalarT>>;
  using Parameters = ParameterVector<ScalarT>;

 public:
  using typename Base::Vec6;

  /// theta_hat is what the closed loop logs per step.
  static constexpr int kLoggedParameters = kRegressorParameters;

  NEUROV_CONTROLLER_NAMES("linear", "linear adaptive", "LinearAdaptiveController")
  static constexpr const char* kDoc =
      "Linearly parameterised adaptive controller (eq. 26, 28; Fossen and Sagatun): tau = Phi "
      "theta_hat - J^T K_d s, theta_hat <- theta_hat - dt Gamma Phi^T J^-1 s. Knows NEROV's "
      "model structure (see regressor), not its parameters.";
  NEUROV_CONTROLLER_CONSTRUCTORS(LinearAdaptiveController, "linear adaptive controller")

  /// Back to theta0 and a zero history.
  void reset() noexcept {
    theta_hat_ = this->config_.theta0;
    Base::reset();
  }

  /// Replaces theta_hat; false (unchanged) on a NaN/Inf.
  bool set_theta(const Parameters& theta) noexcept {
    if (!this->configured_ || !theta.allFinite()) return false;
    theta_hat_ = theta;
    return true;
  }

  /// A snapshot's state put back (ControllerBase::restore) with theta_hat
  /// and the last model output; false, and nothing changed, for non-finite ones.
  bool restore(const TrackingError<ScalarT>& e, Status s, const Parameters& theta,
               const Vec6& model_output) noexcept {
    if (!this->restorable(e, s) || !theta.allFinite() || !model_output.allFinite()) return false;
    theta_hat_ = theta;
    return Base::restore(e, s, model_output);
  }

  const Parameters& theta() const noexcept { return theta_hat_; }
  /// ||theta_hat||.
  ScalarT adaptive_norm() const noexcept { return theta_hat_.norm(); }
  const Parameters& logged_parameters() const noexcept { return theta_hat_; }

 private:
  /// The law on f = Phi theta_hat and one adaptation step, kept only when
  /// tau and theta_hat are finite.
  bool control(const TrackingError<ScalarT>& e, const Vec6& nu, Vec6& tau) noexcept {
    const auto& c = this->config_;
    const RegressorMatrix<ScalarT> phi = reference_regressor(e, nu);
    const Parameters theta_next =
        theta_hat_ -
        c.dt * c.gamma.cwiseProduct(phi.transpose() * e.kinematics.apply_inverse(e.s));
    if (!theta_next.allFinite() ||
        !this->apply_model(e, Vec6(phi * theta_hat_), c.kd.cwiseProduct(e.s), tau))
      return false;
    theta_hat_ = theta_next;
    return true;
  }

  Parameters theta_hat_ = Parameters::Zero();
};

}  // namespace neurov
