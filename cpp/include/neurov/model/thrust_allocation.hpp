// Thrust allocation without a heap, for firmware: a wrench tau to n <= Max
// thrusters by the weighted pseudo-inverse, the saturation law (shared with
// the simulation's Thrusters), then each thruster's command through the
// inverse of its static curve at the supply voltage.
//   u = W^-1 B^T (B W^-1 B^T)^-1 tau   (minimum sum of w_i u_i^2)
// B W^-1 B^T is symmetric positive definite exactly when B has rank 6, so it
// is inverted by neurov's own Cholesky: Eigen's LU would leave malloc
// referenced in an image that must link no allocator.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "neurov/core/status.hpp"
#include "neurov/core/symmetric_matrix.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/thruster_curve.hpp"

namespace neurov {

enum class Saturation : std::uint8_t {
  /// Scale every thruster by one factor so all fit: the wrench keeps its
  /// direction and loses magnitude.
  scale = 0,
  /// Clip each thruster to its limits: full use of every thruster, but the
  /// wrench turns.
  clip = 1,
};

namespace detail {

/// The checks of a thruster layout's numbers, for any n (sizes checked by
/// the caller's types): B finite, limits finite with min <= 0 <= max and
/// min < max, weights positive.
template <typename MatB, typename Vec>
inline ValidationError validate_thruster_limits(const MatB& matrix, const Vec& min_thrust,
                                                const Vec& max_thrust, const Vec& weights) noexcept {
  const Eigen::Index n = matrix.cols();
  if (n < 6)
    return invalid("thrusters.matrix", -1, static_cast<double>(n),
                   "at least 6 thrusters (columns) to act in all 6 DOF");
  if (auto e = check_finite("thrusters.matrix", matrix)) return e;
  if (min_thrust.size() != n)
    return invalid("thrusters.min_thrust", -1, static_cast<double>(min_thrust.size()),
                   "one limit per thruster");
  if (max_thrust.size() != n)
    return invalid("thrusters.max_thrust", -1, static_cast<double>(max_thrust.size()),
                   "one limit per thruster");
  if (auto e = check_finite("thrusters.min_thrust", min_thrust)) return e;
  if (auto e = check_finite("thrusters.max_thrust", max_thrust)) return e;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(max_thrust(i) > min_thrust(i)) || max_thrust(i) < 0 || min_thrust(i) > 0)
      return invalid("thrusters.max_thrust", static_cast<int>(i), static_cast<double>(max_thrust(i)),
                     "min_thrust <= 0 <= max_thrust and min < max");
  if (weights.size() != n)
    return invalid("thrusters.weights", -1, static_cast<double>(weights.size()),
                   "one weight per thruster");
  return check_positive("thrusters.weights", weights);
}

/// u = pinv tau saturated to [lo, hi] (lo <= 0 <= hi) by the law s. A finite
/// tau so large that pinv tau overflows is allocated along its direction
/// (inf - inf in the product would give NaN thrusts); a non-finite tau gives
/// u = 0.
template <typename Pinv, typename Vec, typename Out>
inline void allocate_saturated(const Pinv& pinv, const Vector6<typename Out::Scalar>& tau,
                               const Vec& lo, const Vec& hi, Saturation s, Out& u) noexcept {
  using Scalar = typename Out::Scalar;
  u.noalias() = pinv * tau;
  Scalar size = Scalar(1);
  if (!u.allFinite()) {
    size = tau.allFinite() ? tau.cwiseAbs().maxCoeff() : Scalar(0);
    if (!(size > Scalar(0))) {
      u.setZero();
      return;
    }
    u.noalias() = pinv * (tau / size);
  }
  if (s == Saturation::clip) {
    // size * u may be +-inf, never NaN, and the clip brings it back.
    u = (u * size).cwiseMax(lo).cwiseMin(hi);
    return;
  }
  // How far along u every thruster can follow (at most `size`, the whole tau).
  Scalar reach = size;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    if (u(i) > Scalar(0)) reach = std::min(reach, hi(i) / u(i));
    if (u(i) < Scalar(0)) reach = std::min(reach, lo(i) / u(i));
  }
  // The clamp only undoes rounding: u * (hi / u) can land an ulp beyond hi.
  u = (u * reach).cwiseMax(lo).cwiseMin(hi);
}

}  // namespace detail

/// Allocation for up to Max thrusters in fixed storage: create() computes the
/// pseudo-inverse once; allocate() is noexcept and allocation-free.
template <typename Scalar, int Max>
class ThrustAllocator {
 public:
  static_assert(Max >= 6, "six thrusters at least act in all six DOF");
  using Matrix = Eigen::Matrix<Scalar, 6, Eigen::Dynamic, 0, 6, Max>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1, 0, Max, 1>;
  using Curve = ThrusterCurve<Scalar>;

  /// Validates and precomputes; `out` is untouched on error. An empty
  /// `weights` means all 1. B W^-1 B^T must be positive definite with its
  /// smallest eigenvalue above rounding (64 epsilon times its trace).
  static ValidationError create(const Matrix& matrix, const Vector& min_thrust,
                                const Vector& max_thrust, const Vector& weights,
                                Saturation saturation, ThrustAllocator& out) noexcept {
    const Eigen::Index n = matrix.cols();
    const Vector w = weights.size() == 0 ? Vector(Vector::Ones(n)) : weights;
    if (auto e = detail::validate_thruster_limits(matrix, min_thrust, max_thrust, w)) return e;
    if (saturation != Saturation::scale && saturation != Saturation::clip)
      return detail::invalid("thrusters.saturation", -1, static_cast<double>(saturation),
                             "scale or clip");
    const Vector w_inv = w.cwiseInverse();
    Matrix bw = matrix;
    for (Eigen::Index i = 0; i < n; ++i) bw.col(i) *= w_inv(i);
    // lazyProduct: a product of dynamic size would otherwise compile Eigen's
    // blocked GEMM, whose workspace can fall back to malloc.
    const Matrix6<Scalar> bwb = bw.lazyProduct(matrix.transpose());
    Matrix6<Scalar> inv;
    const Scalar floor = Scalar(64) * std::numeric_limits<Scalar>::epsilon() * bwb.trace();
    if (!(detail::min_eigenvalue(bwb) > floor) || !detail::spd_inverse(bwb, inv))
      return detail::invalid("thrusters.matrix", -1, static_cast<double>(detail::min_eigenvalue(bwb)),
                             "rank 6: the thrusters must act in all 6 DOF (value: smallest "
                             "eigenvalue of B W^-1 B^T)");
    out.matrix_ = matrix;
    out.pinv_ = bw.transpose().lazyProduct(inv);
    out.min_ = min_thrust;
    out.max_ = max_thrust;
    out.saturation_ = saturation;
    out.valid_ = true;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  Eigen::Index count() const noexcept { return matrix_.cols(); }
  const Matrix& matrix() const noexcept { return matrix_; }

  /// Thrusts u [N] for tau, each limited to its configured range and, where
  /// curves[i] is given, to what that curve yields at `voltage`; then
  /// commands: curves[i]->command_for(u_i, voltage), or u_i where curves is
  /// null or curves[i] is. On any status but ok, u = 0, every command is
  /// its neutral one (0 without a curve) and nothing else changes:
  /// non_finite_input for a NaN/Inf in tau or (with a curve) the voltage,
  /// invalid_argument for a voltage <= 0 with a curve or an invalid object.
  Status allocate(const Vector6<Scalar>& tau, Scalar voltage, const Curve* const* curves,
                  Vector& u, Vector& command) const noexcept {
    const Eigen::Index n = count();
    u.setZero(n);
    command.setZero(n);
    const bool any_curve = curves != nullptr && std::any_of(curves, curves + n, [](const Curve* c) {
                             return c != nullptr;
                           });
    Status s = Status::ok;
    if (!valid_) s = Status::invalid_argument;
    else if (!tau.allFinite() || (any_curve && !std::isfinite(voltage))) s = Status::non_finite_input;
    else if (any_curve && !(voltage > Scalar(0))) s = Status::invalid_argument;
    if (s != Status::ok) {
      for (Eigen::Index i = 0; i < n; ++i)
        if (curves != nullptr && curves[i] != nullptr) command(i) = curves[i]->config().neutral;
      return s;
    }
    Vector lo = min_, hi = max_;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (curves == nullptr || curves[i] == nullptr) continue;
      lo(i) = std::max(lo(i), std::min(curves[i]->min_thrust(voltage), Scalar(0)));
      hi(i) = std::min(hi(i), std::max(curves[i]->max_thrust(voltage), Scalar(0)));
    }
    detail::allocate_saturated(pinv_, tau, lo, hi, saturation_, u);
    for (Eigen::Index i = 0; i < n; ++i)
      command(i) = curves != nullptr && curves[i] != nullptr ? curves[i]->command_for(u(i), voltage)
                                                             : u(i);
    return Status::ok;
  }

 private:
  Matrix matrix_{};
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6, 0, Max, 6> pinv_{};
  Vector min_{}, max_{};
  Saturation saturation_ = Saturation::scale;
  bool valid_ = false;
};

}  // namespace neurov
