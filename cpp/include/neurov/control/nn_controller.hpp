// Direct adaptive RBF neural-network controller (eq. 35 and 37):
//   x   = [nu_r_dot; nu_r; nu; eta]                      (24 inputs)
//   tau = W g(x) - J^T(eta) K_d s
//   W  <- W - dt (J^-1 s) g(x)^T Gamma_w                  (one Euler step of eq. 37)
// tau uses the weights from before the update. Optional robust modifications
// (none by default, as in the paper) keep W bounded when the approximation
// error or a disturbance is not negligible.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "neurov/control/controller_base.hpp"
#include "neurov/control/rbf_kernels.hpp"
#include "neurov/control/rbf_network.hpp"
#include "neurov/core/field_spec.hpp"

namespace neurov {

enum class RobustModification : std::uint8_t {
  none = 0,            ///< the paper's pure gradient law
  sigma = 1,           ///< W_dot += -sigma_m * W * Gamma_w
  e_modification = 2,  ///< W_dot += -kappa * ||J^-1 s|| * W * Gamma_w
  projection = 3,      ///< after each update, scale W back onto ||W||_F <= w_max
};

constexpr const char* to_string(RobustModification m) noexcept {
  switch (m) {
    case RobustModification::none:
      return "none";
    case RobustModification::sigma:
      return "sigma";
    case RobustModification::e_modification:
      return "e_modification";
    case RobustModification::projection:
      return "projection";
  }
  return "unknown";
}

template <typename Scalar>
struct NNAdaptiveConfig : SlidingGains<Scalar> {
  /// Gamma_w = gamma * I (the paper: 0.3); per-centre values via set_learning_rates().
  Scalar gamma = Scalar(0.3);
  /// Control period [s] (the paper: 0.2 s, 5 Hz).
  Scalar dt = Scalar(0.2);
  RobustModification modification = RobustModification::none;
  Scalar sigma_m = Scalar(0);   ///< leakage of the sigma-modification (> 0 when used)
  Scalar kappa = Scalar(0);     ///< gain of the e-modification (> 0 when used)
  Scalar w_max = Scalar(0);     ///< Frobenius bound of the projection (> 0 when used)
  /// Adaptation stops while ||s|| < dead_zone (0 disables; any modification).
  Scalar dead_zone = Scalar(0);
};

/// The configuration's fields (the robust modifications' gains are checked
/// with the modification that uses them, by validate).
template <typename Scalar>
auto config_fields(const NNAdaptiveConfig<Scalar>*) noexcept {
  using C = NNAdaptiveConfig<Scalar>;
  return std::tuple_cat(
      detail::sliding_gain_fields<C>(),
      std::make_tuple(
          field_spec<C>("gamma", &C::gamma, "", Check::non_negative, "Gamma_w = gamma I (the paper: 0.3)"),
          field_spec<C>("dt", &C::dt, "s", Check::positive, "Control period (the paper: 0.2)"),
          field_spec<C>("modification", &C::modification, "", Check::none,
                        "The robust modification: a RobustModification or its name.", kKeywordOnly),
          field_spec<C>("sigma_m", &C::sigma_m, "", Check::non_negative,
                        "Leakage of the sigma-modification (> 0 when used)", kKeywordOnly),
          field_spec<C>("kappa", &C::kappa, "", Check::non_negative,
                        "Gain of the e-modification (> 0 when used)", kKeywordOnly),
          field_spec<C>("w_max", &C::w_max, "", Check::non_negative,
                        "Frobenius bound of the projection (> 0 when used)", kKeywordOnly),
          field_spec<C>("dead_zone", &C::dead_zone, "", Check::non_negative,
                        "No adaptation while ||s|| < dead_zone (0 disables)", kKeywordOnly)));
}

template <typename Scalar>
inline ValidationError validate(const NNAdaptiveConfig<Scalar>& c) noexcept {
  if (auto e = detail::check_sliding_gains(c)) return e;
  if (auto e = detail::check_non_negative_scalar("gamma", static_cast<double>(c.gamma))) return e;
  if (auto e = detail::check_positive_scalar("dt", static_cast<double>(c.dt))) return e;
  struct Gain {
    const char* name;
    Scalar value;
    RobustModification needed_by;  ///< the modification that needs it > 0
    const char* expected;
  };
  const Gain gains[] = {
      {"sigma_m", c.sigma_m, RobustModification::sigma, "> 0 with modification 'sigma'"},
      {"kappa", c.kappa, RobustModification::e_modification,
       "> 0 with modification 'e_modification'"},
      {"w_max", c.w_max, RobustModification::projection, "> 0 with modification 'projection'"},
      {"dead_zone", c.dead_zone, RobustModification::none, nullptr},
  };
  for (const Gain& g : gains)
    if (auto e = detail::check_non_negative_scalar(g.name, static_cast<double>(g.value)))
      return e;
  if (static_cast<int>(c.modification) > static_cast<int>(RobustModification::projection))
    return detail::invalid("modification", -1, static_cast<double>(c.modification),
                           "none, sigma, e_modification or projection");
  for (const Gain& g : gains)
    if (g.expected && c.modification == g.needed_by && !(g.value > Scalar(0)))
      return detail::invalid(g.name, -1, static_cast<double>(g.value), g.expected);
  return {};
}

/// The network input of eq. 35: x = [nu_r_dot; nu_r; nu; eta].
constexpr int kNNInputs = 24;

template <typename ScalarT, int CentresT = Eigen::Dynamic>
class NNAdaptiveController
    : public ControllerBase<NNAdaptiveController<ScalarT, CentresT>, ScalarT,
                            NNAdaptiveConfig<ScalarT>> {
  using Base =
      ControllerBase<NNAdaptiveController<ScalarT, CentresT>, ScalarT, NNAdaptiveConfig<ScalarT>>;
  using Base::config_;
  using Base::configured_;
  using Base::refuse;
  using Base::status_;
  using Base::tracking_;

 public:
  using typename Base::Config;
  using typename Base::Scalar;
  using typename Base::Vec6;
  using Network = RbfNetwork<Scalar, kNNInputs, CentresT, 6>;
  using InputVector = typename Network::InputVector;
  using BasisVector = typename Network::BasisVector;
  using WeightMatrix = typename Network::WeightMatrix;

  NEUROV_CONTROLLER_NAMES("nn", "NN adaptive", "NNAdaptiveController")
  static constexpr const char* kDoc =
      "Direct adaptive RBF-network controller (eq. 35, 37): tau = W g(x) - J^T K_d s with "
      "x = [nu_r_dot; nu_r; nu; eta] (24 inputs), then W <- W - dt (J^-1 s) g(x)^T Gamma_w. "
      "tau uses the weights from before the update.";
  /// The prefix of its validator's messages.
  static constexpr const char* kWhat = "NN controller";
  NNAdaptiveController() = default;

#if NEUROV_HAS_EXCEPTIONS
  NNAdaptiveController(const Network& network, const Config& config) {
    throw_if_invalid(create(network, config, *this), "NN controller");
  }
#endif

  /// Copies the network (its weights are the initial Ŵ) and checks the
  /// configuration. Allocates here (dynamic N) and never again.
  static ValidationError create(const Network& network, const Config& config,
                                NNAdaptiveController& out) {
    if (!network.configured())
      return detail::invalid("network", -1, 0.0, "a configured RBF network");
    if (auto e = validate(config)) return e;
    out.network_ = network;
    out.config_ = config;
    out.learning_rates_ = BasisVector::Constant(network.centres_count(), config.gamma);
    out.learning_rates_norm_ = out.learning_rates_.norm();
    out.basis_ = BasisVector::Zero(network.centres_count());
    if constexpr (kDynamicCentres) out.scratch_basis_ = BasisVector::Zero(network.centres_count());
    out.initial_weights_ = network.weights();
    out.weight_norm_ = network.weights().norm();
    out.tracking_ = TrackingError<Scalar>{};
    out.f_hat_.setZero();
    out.status_ = Status::ok;
    out.adapted_ = false;
    out.configured_ = true;
    return {};
  }

  /// As above from the network's parts (zero initial weights), built inside
  /// `out`: with a fixed N, firmware then needs no second whole network on its
  /// stack or in static memory just to copy it in. `out` is untouched on failure.
  static ValidationError create(const typename Network::CentreMatrix& centres,
                                const BasisVector& widths, const InputVector& input_offset,
                                const InputVector& input_scale, const Config& config,
                                NNAdaptiveController& out) {
    if (auto e = validate(config)) return e;
    if (auto e = Network::create(centres, widths, input_offset, input_scale, out.network_))
      return e;
    // Delegating keeps one place that initialises the rest of the state; the
    // network's copy onto itself is a no-op.
    return create(out.network_, config, out);
  }

  /// The step on a DesiredState (the reference model's output). Written out
  /// rather than brought in with `using Base::step`, which would also bring
  /// the base's six-argument step that this class's own step replaces.
  Status step(const Vec6& eta, const Vec6& nu, const DesiredState<Scalar>& d, Vec6& tau) noexcept {
    return Base::step(eta, nu, d, tau);
  }

  /// The control law and one step of the adaptive law. Writes tau; on any
  /// status but ok (or near_singularity refused) tau = 0 and the weights and
  /// every other piece of state are exactly as before the call.
  Status step(const Vec6& eta, const Vec6& nu, const Vec6& eta_d, const Vec6& eta_d_dot,
              const Vec6& eta_d_ddot, Vec6& tau) noexcept {
    TrackingError<Scalar> e;
    if (const Status ts =
            this->track(eta, nu, eta_d, eta_d_dot, eta_d_ddot, config_.lambda, e, tau);
        ts != Status::ok)
      return ts;

    InputVector x;
    x << e.nu_r_dot, e.nu_r, nu, eta;
    // Everything but W g and the update's overflow bound is known before the
    // network runs, so the path is chosen first.
    const Vec6 kd_s = e.kinematics.apply_transpose(config_.kd.cwiseProduct(e.s));
    // a = dt J^-1 s: the error signal of eq. 37.
    const Vec6 a = config_.dt * e.kinematics.apply_inverse(e.s);
    const bool adapt = !(config_.dead_zone > Scalar(0) && e.s.norm() < config_.dead_zone);
    const Scalar leak = leakage(a);

    Vec6 f_hat;
    if (adapt && update_cannot_overflow(a, kd_s)) {
      // Nothing below can be refused, so g goes straight into basis_ and W g,
      // the update and ||W|| share one pass over W (W g still from the
      // weights before the update).
      network_.basis(x, basis_);
      apply_update(basis_, a, leak, f_hat);
    } else {
      // This step can still be refused once g is known (an overflowing
      // W g - J^T K_d s or update), and a refused step must leave basis() at
      // the last accepted step's g: g goes into scratch storage and is
      // published only when the step is accepted.
      const Status cs = with_scratch_basis([&](BasisVector& g) noexcept {
        return checked_step(x, g, a, kd_s, adapt, leak, f_hat);
      });
      if (cs != Status::ok) return refuse(cs, tau);
    }
    adapted_ = adapt;
    f_hat_ = f_hat;
    return this->accept(e, Vec6(f_hat - kd_s), tau);
  }

  /// Per-centre learning rates Gamma_w = diag(rates); false (unchanged) for a
  /// wrong size or a negative or non-finite rate.
  bool set_learning_rates(const BasisVector& rates) noexcept {
    if (!configured_ || rates.size() != learning_rates_.size() || !rates.allFinite() ||
        (rates.array() < Scalar(0)).any())
      return false;
    learning_rates_ = rates;
    learning_rates_norm_ = rates.norm();
    return true;
  }

  /// Replaces the weights (warm start); false (unchanged) on a bad matrix.
  bool set_weights(const WeightMatrix& w) noexcept {
    // Finite weights whose norm overflows would leave weight_norm() infinite
    // and every later update refused by its overflow bound.
    if (!std::isfinite(w.norm())) return false;
    if (!network_.set_weights(w)) return false;
    weight_norm_ = network_.weights().norm();
    return true;
  }

  /// Back to the initial weights and a zero history.
  void reset() noexcept {
    network_.weights() = initial_weights_;
    weight_norm_ = initial_weights_.norm();
    f_hat_.setZero();
    adapted_ = false;
    this->reset_common();
  }

  /// A snapshot's state put back (ControllerBase::restore) with the learnt
  /// weights W and their norm as the updates accumulated it (it may differ
  /// from weights.norm() in the last bit, and the step's overflow test reads
  /// it), the last g(x) and W g(x) and whether that step adapted; false, and
  /// nothing changed, for a wrong size or a non-finite or negative value.
  bool restore(const TrackingError<Scalar>& e, Status s, const WeightMatrix& weights,
               Scalar weight_norm, const BasisVector& basis, const Vec6& network_output,
               bool adapted) noexcept {
    if (!this->restorable(e, s) || basis.size() != basis_.size() || !basis.allFinite() ||
        !network_output.allFinite() || weights.cols() != network_.weights().cols() ||
        !std::isfinite(weights.norm()) || !(weight_norm >= Scalar(0)) ||
        !std::isfinite(weight_norm))
      return false;
    if (!set_weights(weights)) return false;
    weight_norm_ = weight_norm;
    basis_ = basis;
    f_hat_ = network_output;
    adapted_ = adapted;
    return Base::restore(e, s);
  }

  const Network& network() const noexcept { return network_; }
  /// W(0), the weights reset() goes back to.
  const WeightMatrix& initial_weights() const noexcept { return initial_weights_; }
  const WeightMatrix& weights() const noexcept { return network_.weights(); }
  const BasisVector& learning_rates() const noexcept { return learning_rates_; }
  /// Quantities of the last accepted step, for plots and logs.
  const Vec6& network_output() const noexcept { return f_hat_; }
  /// g(x) of the last accepted step (zero before the first): a step refused
  /// after the network ran leaves it as it was, like everything else.
  const BasisVector& basis() const noexcept { return basis_; }
  Scalar weight_norm() const noexcept { return weight_norm_; }
  /// ||W||_F.
  Scalar adaptive_norm() const noexcept { return weight_norm_; }
  bool adapted() const noexcept { return adapted_; }

 private:
  /// The leakage of the sigma- or e-modification (0 for the others).
  Scalar leakage(const Vec6& a) const noexcept {
    if (config_.modification == RobustModification::sigma) return config_.sigma_m;
    if (config_.modification == RobustModification::e_modification)
      return config_.kappa * a.norm() / config_.dt;
    return Scalar(0);
  }

  /// True when the update and tau are sure to be finite, so that the step
  /// cannot be refused once it starts on W: g <= 1 gives
  /// ||gamma .* g|| <= ||gamma||, so ||W_new|| stays below half the overflow
  /// bound the checked path applies; then |W g| <= sqrt(N) ||W|| is far below
  /// the overflow threshold, and so is W g - J^T K_d s for a bounded K_d term.
  bool update_cannot_overflow(const Vec6& a, const Vec6& kd_s) const noexcept {
    const Scalar big = std::numeric_limits<Scalar>::max();
    if (!detail::all_finite(a, kd_s) || !(kd_s.cwiseAbs().maxCoeff() <= big / Scalar(4)))
      return false;
    return weight_norm_ + a.norm() * learning_rates_norm_ < Scalar(0.5) * std::sqrt(big);
  }

  /// The path of a step that may still be refused after the network ran:
  /// g(x) into `g` (scratch), the checks, then the update; on ok g is
  /// published as basis_. A refusal returns before anything is written but
  /// `g` and `f_hat`.
  Status checked_step(const InputVector& x, BasisVector& g, const Vec6& a, const Vec6& kd_s,
                      bool adapt, Scalar leak, Vec6& f_hat) noexcept {
    network_.basis(x, g);
    // The checks come first and a refused step leaves W and basis_ as they were.
    detail::nn_output<Scalar>(network_.weights().data(), g.size(), g.data(), f_hat.data());
    if (!detail::all_finite(Vec6(f_hat - kd_s), a)) return Status::non_finite_output;
    if (adapt) {
      // Refuse an update that could overflow, before touching W.
      const Scalar bound =
          weight_norm_ + a.norm() * (g.array() * learning_rates_.array()).matrix().norm();
      if (!(bound < std::sqrt(std::numeric_limits<Scalar>::max())))
        return Status::non_finite_output;
      Vec6 unused;
      apply_update(g, a, leak, unused);
    }
    publish_basis(g);
    return Status::ok;
  }

  /// Runs f(g) with scratch storage for one g(x): with a fixed N a vector on
  /// the stack (the checked path only; no member, so the object keeps its
  /// size), with a dynamic N the vector allocated once in create().
  template <typename F>
  Status with_scratch_basis(F&& f) noexcept {
    if constexpr (kDynamicCentres) {
      return f(scratch_basis_);
    } else {
      BasisVector g;
      return f(g);
    }
  }

  /// basis_ <- g: a swap of the two heap buffers with a dynamic N (no copy,
  /// no allocation), a copy of N numbers with a fixed N.
  void publish_basis(BasisVector& g) noexcept {
    if constexpr (kDynamicCentres)
      basis_.swap(g);
    else
      basis_ = g;
  }

  /// f_hat = W g with the weights before the update, then
  /// W <- W .* (1 - dt leak gamma_j) - a (gamma .* g)^T, then the projection.
  void apply_update(const BasisVector& g, const Vec6& a, Scalar leak, Vec6& f_hat) noexcept {
    WeightMatrix& w = network_.weights();
    const Scalar norm2 = detail::nn_output_update<Scalar>(w.data(), g.size(), g.data(),
                                                          learning_rates_.data(), a.data(),
                                                          config_.dt * leak, f_hat.data());
    Scalar norm = std::sqrt(norm2);
    if (config_.modification == RobustModification::projection && norm > config_.w_max) {
      w *= config_.w_max / norm;
      norm = config_.w_max;
    }
    weight_norm_ = norm;
  }

  static constexpr bool kDynamicCentres = CentresT == Eigen::Dynamic;
  /// Scratch g(x) of the checked path with a dynamic N; nothing with a fixed N.
  struct NoScratch {};
  using ScratchBasis = std::conditional_t<kDynamicCentres, BasisVector, NoScratch>;

  Network network_{};
  BasisVector learning_rates_{};
  Scalar learning_rates_norm_ = Scalar(0);  ///< ||gamma||, for update_cannot_overflow()
  BasisVector basis_{};
  WeightMatrix initial_weights_{};
  Vec6 f_hat_ = Vec6::Zero();
  Scalar weight_norm_ = Scalar(0);
  bool adapted_ = false;
  ScratchBasis scratch_basis_{};
};

}  // namespace neurov
