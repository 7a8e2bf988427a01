// Thrusters: allocation of a demanded wrench tau to n thrusters by a weighted
// pseudo-inverse, saturation, first-order lag and failures.
//   tau = B u,  u = W^-1 B^T (B W^-1 B^T)^-1 tau   (minimum sum of w_i u_i^2)
// With a curve per thruster (model/thruster_curve.hpp) the saturated thrusts
// u go through the curve's inverse to commands (PWM, say), and the plant
// produces curve(command) at the supply voltage, with the curve's own lag and
// slew limit: what a vehicle's allocation and ESCs do. Without curves the
// command is the thrust itself (linear thrusters).
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <vector>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/thrust_allocation.hpp"
#include "neurov/model/thruster_curve.hpp"

namespace neurov {

template <typename Scalar>
struct ThrusterConfig {
  using Matrix = Eigen::Matrix<Scalar, 6, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  Matrix matrix;      ///< B (6 x n): wrench of each thruster per unit thrust
  /// Lower limits [N] (n), <= 0. With curves they may be left empty: the
  /// curves' thrust at their lowest command and the supply voltage.
  Vector min_thrust;
  /// Upper limits [N] (n), >= 0 and > min. With curves: empty (the curves'
  /// thrust at their highest command), or inside what the curve attains.
  Vector max_thrust;
  Vector weights;     ///< allocation weights w_i (n), > 0; empty means all 1
  Saturation saturation = Saturation::scale;
  /// First-order lag [s] of linear thrusters; 0 means none. Must be 0 with
  /// curves, which carry their own lag and slew limit.
  Scalar time_constant = Scalar(0);
  /// Command -> thrust of each thruster (n curves), or empty: linear.
  std::vector<ThrusterCurveConfig<Scalar>> curves;
  /// Supply voltage [V] the curves are scaled to; > 0 with curves.
  Scalar supply_voltage = Scalar(0);
};

/// The layout's fields; Thrusters::create checks them (sizes, limits, rank).
template <typename Scalar>
auto config_fields(const ThrusterConfig<Scalar>*) noexcept {
  using C = ThrusterConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("matrix", &C::matrix, "B (6, n): the wrench of each thruster per unit thrust"),
      field_spec<C>("min_thrust", &C::min_thrust, "N", Check::none, "Lower limits (n,), each <= 0"),
      field_spec<C>("max_thrust", &C::max_thrust, "N", Check::none,
                    "Upper limits (n,), each above its min_thrust"),
      field_spec<C>("weights", &C::weights, "Allocation weights (n,), > 0; empty means all 1"),
      field_spec<C>("saturation", &C::saturation, "A Saturation"),
      field_spec<C>("time_constant", &C::time_constant, "s", Check::non_negative,
                    "First-order lag of linear thrusters (0: none; 0 with curves)"),
      field_spec<C>("curves", &C::curves,
                    "One command-to-thrust curve per thruster, or empty: linear thrusters (a "
                    "tuple; assign a list). With curves, empty limits mean the curves' range"),
      field_spec<C>("supply_voltage", &C::supply_voltage, "V", Check::none,
                    "Supply voltage of the curves (> 0 with curves)"));
}

template <typename Scalar>
class Thrusters {
 public:
  using Matrix = typename ThrusterConfig<Scalar>::Matrix;
  using Vector = typename ThrusterConfig<Scalar>::Vector;

  Thrusters() = default;

  /// Validates (sizes, finite, min < max, B of full rank 6) and precomputes
  /// the pseudo-inverse. Allocates here only.
  static ValidationError create(const ThrusterConfig<Scalar>& c, Thrusters& out) {
    const Eigen::Index n = c.matrix.cols();
    const bool curved = !c.curves.empty();
    std::vector<ThrusterCurve<Scalar>> curves(c.curves.size());
    Vector lowest, highest;  // what the curves attain at the supply voltage
    if (curved) {
      if (static_cast<Eigen::Index>(c.curves.size()) != n)
        return detail::invalid("thrusters.curves", -1, static_cast<double>(c.curves.size()),
                               "one curve per thruster (or none: linear thrusters)");
      if (auto e = detail::check_positive_scalar("thrusters.supply_voltage",
                                                 static_cast<double>(c.supply_voltage)))
        return e;
      if (c.time_constant != Scalar(0))
        return detail::invalid("thrusters.time_constant", -1,
                               static_cast<double>(c.time_constant),
                               "0 with curves (each curve has its own time_constant)");
      lowest.resize(n);
      highest.resize(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        if (auto e = ThrusterCurve<Scalar>::create(c.curves[static_cast<std::size_t>(i)],
                                                   curves[static_cast<std::size_t>(i)]))
          return e;
        lowest(i) = curves[static_cast<std::size_t>(i)].min_thrust(c.supply_voltage);
        highest(i) = curves[static_cast<std::size_t>(i)].max_thrust(c.supply_voltage);
      }
    }
    const Vector min_thrust = curved && c.min_thrust.size() == 0 ? lowest : c.min_thrust;
    const Vector max_thrust = curved && c.max_thrust.size() == 0 ? highest : c.max_thrust;
    Vector w = c.weights.size() == 0 ? Vector::Ones(n) : c.weights;
    if (auto e = detail::validate_thruster_limits(c.matrix, min_thrust, max_thrust, w))
      return e;
    for (Eigen::Index i = 0; curved && i < n; ++i) {
      if (max_thrust(i) > highest(i))
        return detail::invalid("thrusters.max_thrust", static_cast<int>(i),
                               static_cast<double>(max_thrust(i)),
                               "<= the curve's thrust at its highest command and the supply "
                               "voltage");
      if (min_thrust(i) < lowest(i))
        return detail::invalid("thrusters.min_thrust", static_cast<int>(i),
                               static_cast<double>(min_thrust(i)),
                               ">= the curve's thrust at its lowest command and the supply "
                               "voltage");
    }
    if (auto e = detail::check_non_negative_scalar("thrusters.time_constant",
                                                   static_cast<double>(c.time_constant)))
      return e;
    const Vector w_inv = w.cwiseInverse();
    const Matrix6<Scalar> bwb = c.matrix * w_inv.asDiagonal() * c.matrix.transpose();
    Eigen::FullPivLU<Matrix6<Scalar>> lu(bwb);
    if (lu.rank() < 6)
      return detail::invalid("thrusters.matrix", -1, static_cast<double>(lu.rank()),
                             "rank 6 (the thrusters must act in all 6 DOF)");
    out.config_ = c;
    out.config_.weights = w;
    out.config_.min_thrust = min_thrust;
    out.config_.max_thrust = max_thrust;
    out.pinv_ = w_inv.asDiagonal() * c.matrix.transpose() * lu.inverse();
    out.curves_ = std::move(curves);
    out.efficiency_ = Vector::Ones(n);
    out.thrust_ = Vector::Zero(n);
    out.command_ = Vector::Zero(n);
    out.actuator_command_ = Vector::Zero(n);
    out.reset();
    return {};
  }

  Eigen::Index count() const noexcept { return config_.matrix.cols(); }
  const ThrusterConfig<Scalar>& config() const noexcept { return config_; }

  /// Thrust commands for a demanded wrench, saturated; stored as the command
  /// the lag follows. With curves, each thrust is turned into the command
  /// that gives it at the supply voltage (actuator_commands()).
  void command(const Vector6<Scalar>& tau) noexcept {
    detail::allocate_saturated(pinv_, tau, config_.min_thrust, config_.max_thrust,
                               config_.saturation, command_);
    if (curves_.empty()) {
      actuator_command_ = command_;
      return;
    }
    for (std::size_t i = 0; i < curves_.size(); ++i)
      actuator_command_(static_cast<Eigen::Index>(i)) = curves_[i].command_for(
          command_(static_cast<Eigen::Index>(i)), config_.supply_voltage);
  }

  /// Moves the actual thrusts toward the command over dt, dt in (0, kMaxStep]
  /// (the exact solution of the first-order lag for a held command; with
  /// curves, each curve's lag and slew limit toward curve(command)).
  void advance(Scalar dt) noexcept {
    if (!curves_.empty()) {
      for (std::size_t i = 0; i < curves_.size(); ++i) {
        const auto k = static_cast<Eigen::Index>(i);
        curves_[i].step(actuator_command_(k), config_.supply_voltage, dt);
        thrust_(k) = curves_[i].thrust();
      }
    } else if (config_.time_constant > Scalar(0)) {
      const Scalar a = std::exp(-dt / config_.time_constant);
      thrust_ = a * thrust_ + (Scalar(1) - a) * command_;
    } else if (thrust_ == command_) {
      return;  // without a lag the thrusts move once a period, not every substep
    } else {
      thrust_ = command_;
    }
    update_wrench();
  }

  /// The wrench the thrusters produce now: B (efficiency .* thrust).
  const Vector6<Scalar>& wrench() const noexcept { return wrench_; }

  /// Efficiency of thruster i in [0, 1] (0: failed); false if out of range.
  bool set_efficiency(Eigen::Index i, Scalar e) noexcept {
    if (i < 0 || i >= efficiency_.size() || !(e >= Scalar(0) && e <= Scalar(1))) return false;
    efficiency_(i) = e;
    update_wrench();
    return true;
  }

  void reset() noexcept {
    efficiency_.setOnes();
    thrust_.setZero();
    wrench_.setZero();
    command_.setZero();
    actuator_command_.setZero();
    for (std::size_t i = 0; i < curves_.size(); ++i) {
      curves_[i].reset();
      actuator_command_(static_cast<Eigen::Index>(i)) = curves_[i].config().neutral;
    }
  }

  bool has_curves() const noexcept { return !curves_.empty(); }
  const Vector& thrust() const noexcept { return thrust_; }
  /// The thrusts the allocation asks for (saturated) [N].
  const Vector& commanded() const noexcept { return command_; }
  /// What each thruster is sent: with curves, the curve's command (its
  /// unit, e.g. PWM us) for the commanded thrust; without, that thrust.
  const Vector& actuator_commands() const noexcept { return actuator_command_; }
  /// Thruster i's curve (i < count(), has_curves()).
  const ThrusterCurve<Scalar>& curve(Eigen::Index i) const noexcept {
    return curves_[static_cast<std::size_t>(i)];
  }
  const Vector& efficiency() const noexcept { return efficiency_; }

 private:
  void update_wrench() noexcept {
    // Column by column: Eigen evaluates the expression efficiency .* thrust on
    // the right of a product into a heap temporary, once per call.
    wrench_.setZero();
    for (Eigen::Index i = 0; i < thrust_.size(); ++i)
      wrench_ += config_.matrix.col(i) * (efficiency_(i) * thrust_(i));
  }

  ThrusterConfig<Scalar> config_{};
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6> pinv_{};
  std::vector<ThrusterCurve<Scalar>> curves_{};
  Vector efficiency_{};
  Vector thrust_{};
  Vector command_{};
  Vector actuator_command_{};
  Vector6<Scalar> wrench_ = Vector6<Scalar>::Zero();  ///< B (efficiency .* thrust), kept with them
};

}  // namespace neurov
