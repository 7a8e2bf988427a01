// PD controller in the earth frame, the simplest baseline:
//   tau = -J^T(eta) (K_p eta_tilde + K_d eta_tilde_dot)
// It knows nothing of the vehicle, so restoring forces and damping leave a
// steady-state error that the adaptive controllers remove.
#pragma once

#include "neurov/control/controller_base.hpp"
#include "neurov/core/field_spec.hpp"

namespace neurov {

template <typename Scalar>
struct PDConfig {
  Vector6<Scalar> kp = Vector6<Scalar>::Zero();  ///< K_p (>= 0)
  Vector6<Scalar> kd = Vector6<Scalar>::Zero();  ///< K_d (>= 0)
};

template <typename Scalar>
auto config_fields(const PDConfig<Scalar>*) noexcept {
  using C = PDConfig<Scalar>;
  return std::make_tuple(field_spec<C>("kp", &C::kp, "", Check::non_negative, "K_p, diagonal (6,)"),
                         field_spec<C>("kd", &C::kd, "", Check::non_negative, "K_d, diagonal (6,)"));
}

template <typename Scalar>
inline ValidationError validate(const PDConfig<Scalar>& c) noexcept {
  return check_fields(c);
}

template <typename ScalarT>
class PDController : public ControllerBase<PDController<ScalarT>, ScalarT, PDConfig<ScalarT>> {
  using Base = ControllerBase<PDController<ScalarT>, ScalarT, PDConfig<ScalarT>>;
  friend Base;

 public:
  NEUROV_CONTROLLER_NAMES("pd", "PD", "PDController")
  static constexpr const char* kDoc =
      "PD baseline in the earth frame: tau = -J^T (K_p eta_tilde + K_d eta_tilde_dot).";
  NEUROV_CONTROLLER_CONSTRUCTORS(PDController, "PD controller")

 private:
  bool control(const TrackingError<ScalarT>& e, const Vector6<ScalarT>&,
               Vector6<ScalarT>& tau) const noexcept {
    const auto& c = this->config_;
    tau = -e.kinematics.apply_transpose(c.kp.cwiseProduct(e.eta_tilde) +
                                        c.kd.cwiseProduct(e.eta_tilde_dot));
    return tau.allFinite();
  }
};

}  // namespace neurov
