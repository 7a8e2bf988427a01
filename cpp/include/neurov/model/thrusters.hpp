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
#include "neurov/model/thrust_allocation.hpp"

namespace neurov {

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
    Vector w = c.weights.size() == 0 ? Vector::Ones(n) : c.weights;
    if (auto e = detail::validate_thruster_limits(c.matrix, c.min_thrust, c.max_thrust, w))
      return e;
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
    detail::allocate_saturated(pinv_, tau, config_.min_thrust, config_.max_thrust,
                               config_.saturation, command_);
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
  ThrusterConfig<Scalar> config_{};
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6> pinv_{};
  Vector efficiency_{};
  Vector thrust_{};
  Vector command_{};
};

}  // namespace neurov
