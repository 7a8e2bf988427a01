// Thrusters: allocation of a demanded wrench tau to n thrusters by a weighted
// pseudo-inverse, saturation, first-order lag and failures.
//   tau = B u,  u = W^-1 B^T (B W^-1 B^T)^-1 tau   (minimum sum of w_i u_i^2)
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

enum class Saturation : std::uint8_t {
  /// Scale every thruster by one factor so all fit: the wrench keeps its
  /// direction and loses magnitude.
  scale = 0,
  /// Clip each thruster to its limits: full use of every thruster, but the
  /// wrench turns.
  clip = 1,
};

template <typename Scalar>
struct ThrusterConfig {
  using Matrix = Eigen::Matrix<Scalar, 6, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  Matrix matrix;      ///< B (6 x n): wrench of each thruster per unit thrust
  Vector min_thrust;  ///< lower limits [N] (n), < 0 for a reversible thruster
  Vector max_thrust;  ///< upper limits [N] (n), > min
  Vector weights;     ///< allocation weights w_i (n), > 0; empty means all 1
  Saturation saturation = Saturation::scale;
  Scalar time_constant = Scalar(0);  ///< first-order lag [s]; 0 means none
};

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
    if (n < 6)
      return detail::invalid("thrusters.matrix", -1, static_cast<double>(n),
                             "at least 6 thrusters (columns) to act in all 6 DOF");
    if (auto e = detail::check_finite("thrusters.matrix", c.matrix)) return e;
    if (c.min_thrust.size() != n)
      return detail::invalid("thrusters.min_thrust", -1, static_cast<double>(c.min_thrust.size()),
                             "one limit per thruster");
    if (c.max_thrust.size() != n)
      return detail::invalid("thrusters.max_thrust", -1, static_cast<double>(c.max_thrust.size()),
                             "one limit per thruster");
    if (auto e = detail::check_finite("thrusters.min_thrust", c.min_thrust)) return e;
    if (auto e = detail::check_finite("thrusters.max_thrust", c.max_thrust)) return e;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!(c.max_thrust(i) > c.min_thrust(i)) || c.max_thrust(i) < Scalar(0) ||
          c.min_thrust(i) > Scalar(0))
        return detail::invalid("thrusters.max_thrust", static_cast<int>(i),
                               static_cast<double>(c.max_thrust(i)),
                               "min_thrust <= 0 <= max_thrust and min < max");
    Vector w = c.weights.size() == 0 ? Vector::Ones(n) : c.weights;
    if (w.size() != n)
      return detail::invalid("thrusters.weights", -1, static_cast<double>(w.size()),
                             "one weight per thruster");
    if (auto e = detail::check_positive("thrusters.weights", w)) return e;
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
    out.pinv_ = w_inv.asDiagonal() * c.matrix.transpose() * lu.inverse();
    out.efficiency_ = Vector::Ones(n);
    out.thrust_ = Vector::Zero(n);
    out.command_ = Vector::Zero(n);
    return {};
  }

  Eigen::Index count() const noexcept { return config_.matrix.cols(); }
  const ThrusterConfig<Scalar>& config() const noexcept { return config_; }

  /// Thrust commands for a demanded wrench, saturated; stored as the command
  /// the lag follows.
  void command(const Vector6<Scalar>& tau) noexcept {
    command_.noalias() = pinv_ * tau;
    if (!command_.allFinite()) return command_overflowed(tau);
    if (config_.saturation == Saturation::clip) {
      command_ = command_.cwiseMax(config_.min_thrust).cwiseMin(config_.max_thrust);
      return;
    }
    Scalar factor = Scalar(1);
    for (Eigen::Index i = 0; i < command_.size(); ++i) {
      const Scalar u = command_(i);
      if (u > config_.max_thrust(i)) factor = std::min(factor, config_.max_thrust(i) / u);
      if (u < config_.min_thrust(i)) factor = std::min(factor, config_.min_thrust(i) / u);
    }
    // The clamp only undoes rounding: u * (max / u) can land an ulp beyond max.
    command_ = (command_ * factor).cwiseMax(config_.min_thrust).cwiseMin(config_.max_thrust);
  }

  /// Moves the actual thrusts toward the command over dt (exact solution of
  /// the first-order lag for a held command), then applies the failures.
  void advance(Scalar dt) noexcept {
    if (config_.time_constant > Scalar(0)) {
      const Scalar a = std::exp(-dt / config_.time_constant);
      thrust_ = a * thrust_ + (Scalar(1) - a) * command_;
    } else {
      thrust_ = command_;
    }
  }

  /// The wrench the thrusters produce now: B (efficiency .* thrust).
  Vector6<Scalar> wrench() const noexcept {
    // Column by column: Eigen evaluates the expression efficiency .* thrust on
    // the right of a product into a heap temporary, once per call.
    Vector6<Scalar> w = Vector6<Scalar>::Zero();
    for (Eigen::Index i = 0; i < thrust_.size(); ++i)
      w += config_.matrix.col(i) * (efficiency_(i) * thrust_(i));
    return w;
  }

  /// Efficiency of thruster i in [0, 1] (0: failed); false if out of range.
  bool set_efficiency(Eigen::Index i, Scalar e) noexcept {
    if (i < 0 || i >= efficiency_.size() || !(e >= Scalar(0) && e <= Scalar(1))) return false;
    efficiency_(i) = e;
    return true;
  }

  void reset() noexcept {
    efficiency_.setOnes();
    thrust_.setZero();
    command_.setZero();
  }

  const Vector& thrust() const noexcept { return thrust_; }
  const Vector& commanded() const noexcept { return command_; }
  const Vector& efficiency() const noexcept { return efficiency_; }

 private:
  /// The rare path of command(): a finite tau so large that B^+ tau
  /// overflows, where inf - inf in the product would hand NaN thrusts on. Its
  /// direction is allocated instead and saturated along; a NaN or infinite
  /// tau gives no thrust at all.
  void command_overflowed(const Vector6<Scalar>& tau) noexcept {
    const Scalar size = tau.allFinite() ? tau.cwiseAbs().maxCoeff() : Scalar(0);
    if (!(size > Scalar(0))) {
      command_.setZero();
      return;
    }
    command_.noalias() = pinv_ * (tau / size);
    if (config_.saturation == Saturation::clip) {
      // size * u may be +-inf, never NaN, and the clip brings it back.
      command_ = (command_ * size).cwiseMax(config_.min_thrust).cwiseMin(config_.max_thrust);
      return;
    }
    // How far along the unit allocation u every thruster can follow.
    Scalar reach = size;
    for (Eigen::Index i = 0; i < command_.size(); ++i) {
      const Scalar u = command_(i);
      if (u > Scalar(0)) reach = std::min(reach, config_.max_thrust(i) / u);
      if (u < Scalar(0)) reach = std::min(reach, config_.min_thrust(i) / u);
    }
    command_ = (command_ * reach).cwiseMax(config_.min_thrust).cwiseMin(config_.max_thrust);
  }

  ThrusterConfig<Scalar> config_{};
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6> pinv_{};
  Vector efficiency_{};
  Vector thrust_{};
  Vector command_{};
};

}  // namespace neurov
