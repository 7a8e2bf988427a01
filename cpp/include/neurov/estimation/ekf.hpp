// An extended Kalman filter for a 6-DOF vehicle: 15 states, the 12 of
// (eta, nu) and the gyro bias b_g.
//
//   x = [p (NED, 3), Theta = (phi, theta, psi), v (body, 3), omega (body, 3), b_g (3)]
//
// Prediction is kinematic, not the vehicle model: the velocities are a
// random walk driven by white acceleration, so the filter needs neither tau
// nor the hydrodynamic coefficients (an estimator that believes the model
// would inherit its errors, which is what the adaptive controllers are for).
//   p_dot = R(Theta) v,  Theta_dot = T(Theta) omega,
//   v_dot = w_v,  omega_dot = w_omega,  b_g_dot = w_b,
// with spectral densities linear_acceleration_noise^2,
// angular_acceleration_noise^2 and gyro_bias_walk^2. The discrete step is
// x+ = x + dt f(x), F = I + dt A, and Q = Qc dt + (A Qc + Qc A^T) dt^2/2
// + A Qc A^T dt^3/3 (exact for a linear constant-velocity model).
//
// Measurements (each its own update, whenever the sensor delivers):
//   attitude  z = Theta + n          (innovation wrapped to (-pi, pi])
//   gyro      z = omega + b_g + n
//   DVL       z = v + n
//   depth     z = p_z + n
//   position  z = p - age R(Theta) v + n: a fix taken `age` seconds ago,
//             brought to now under constant velocity (the USBL's latency).
// Updates use the Joseph form; a rejected step (non-finite input, an
// innovation covariance that is not positive definite, a non-finite result)
// leaves the state and covariance as they were.
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "neurov/core/status.hpp"
#include "neurov/core/symmetric_matrix.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/kinematics.hpp"

namespace neurov {

inline constexpr int kEkfStates = 15;

template <typename Scalar>
struct EkfConfig {
  using StateVector = Eigen::Matrix<Scalar, kEkfStates, 1>;
  Scalar linear_acceleration_noise = Scalar(0);   ///< sqrt of PSD of w_v [m/s^2/sqrt(Hz)], >= 0
  Scalar angular_acceleration_noise = Scalar(0);  ///< sqrt of PSD of w_omega [rad/s^2/sqrt(Hz)], >= 0
  Scalar gyro_bias_walk = Scalar(0);              ///< [rad/s/sqrt(s)], >= 0
  Scalar attitude_noise = Scalar(0);  ///< std of the attitude measurement [rad], > 0
  Scalar gyro_noise = Scalar(0);      ///< std of the gyro [rad/s], > 0
  Scalar dvl_noise = Scalar(0);       ///< std of the DVL per axis [m/s], > 0
  Scalar depth_noise = Scalar(0);     ///< std of the depth [m], > 0
  Scalar position_noise = Scalar(0);  ///< std of an acoustic fix per axis [m], > 0
  /// Standard deviations of the initial estimate, > 0 (order of x).
  StateVector initial_std = StateVector::Zero();
};

template <typename Scalar>
inline ValidationError validate(const EkfConfig<Scalar>& c) noexcept {
  using detail::check_non_negative_scalar;
  using detail::check_positive_scalar;
  if (auto e = check_non_negative_scalar("estimator.linear_acceleration_noise",
                                         c.linear_acceleration_noise))
    return e;
  if (auto e = check_non_negative_scalar("estimator.angular_acceleration_noise",
                                         c.angular_acceleration_noise))
    return e;
  if (auto e = check_non_negative_scalar("estimator.gyro_bias_walk", c.gyro_bias_walk)) return e;
  if (auto e = check_positive_scalar("estimator.attitude_noise", c.attitude_noise)) return e;
  if (auto e = check_positive_scalar("estimator.gyro_noise", c.gyro_noise)) return e;
  if (auto e = check_positive_scalar("estimator.dvl_noise", c.dvl_noise)) return e;
  if (auto e = check_positive_scalar("estimator.depth_noise", c.depth_noise)) return e;
  if (auto e = check_positive_scalar("estimator.position_noise", c.position_noise)) return e;
  if (auto e = detail::check_positive("estimator.initial_std", c.initial_std)) return e;
  return {};
}

template <typename Scalar>
class Ekf {
 public:
  static constexpr int N = kEkfStates;
  using StateVector = Eigen::Matrix<Scalar, N, 1>;
  using StateMatrix = Eigen::Matrix<Scalar, N, N>;
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;

  /// Validates c and starts from (eta0, nu0) with zero gyro bias and
  /// covariance diag(initial_std^2); `out` is untouched on error.
  static ValidationError create(const EkfConfig<Scalar>& c, const Vec6& eta0, const Vec6& nu0,
                                Ekf& out) noexcept {
    if (auto e = validate(c)) return e;
    if (auto e = detail::check_finite("estimator.initial_eta", eta0)) return e;
    if (auto e = detail::check_finite("estimator.initial_nu", nu0)) return e;
    out.c_ = c;
    out.x_.setZero();
    out.x_.template head<6>() = eta0;
    out.x_.template segment<6>(6) = nu0;
    out.x_(5) = wrap(out.x_(5));
    out.p_ = c.initial_std.cwiseAbs2().asDiagonal();
    out.valid_ = true;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  const StateVector& state() const noexcept { return x_; }
  const StateMatrix& covariance() const noexcept { return p_; }
  Vec6 eta() const noexcept { return x_.template head<6>(); }
  Vec6 nu() const noexcept { return x_.template segment<6>(6); }
  Vec3 gyro_bias() const noexcept { return x_.template tail<3>(); }

  /// Propagates over dt in (0, kMaxStep].
  Status predict(Scalar dt) noexcept {
    if (!valid_) return Status::invalid_argument;
    if (!std::isfinite(dt)) return Status::non_finite_input;
    if (!(dt > Scalar(0) && dt <= Scalar(kMaxStep))) return Status::invalid_argument;
    StateMatrix a = StateMatrix::Zero();
    const auto k = EulerKinematics<Scalar>::from_pose(eta());
    const Vec3 v = x_.template segment<3>(6), w = x_.template segment<3>(9);
    a.template block<3, 3>(0, 6) = k.R;
    a.template block<3, 3>(3, 9) = k.T;
    a.template block<3, 3>(0, 3) = rotation_jacobian(v);
    a.template block<3, 3>(3, 3) = transform_jacobian(w);
    StateVector x = x_;
    x.template head<3>() += dt * (k.R * v);
    x.template segment<3>(3) += dt * (k.T * w);
    x(5) = wrap(x(5));
    StateVector qc = StateVector::Zero();
    qc.template segment<3>(6).setConstant(c_.linear_acceleration_noise * c_.linear_acceleration_noise);
    qc.template segment<3>(9).setConstant(c_.angular_acceleration_noise * c_.angular_acceleration_noise);
    qc.template tail<3>().setConstant(c_.gyro_bias_walk * c_.gyro_bias_walk);
    const StateMatrix aq = a * qc.asDiagonal();
    StateMatrix q = StateMatrix(qc.asDiagonal()) * dt;
    q += (aq + aq.transpose()) * (dt * dt / Scalar(2));
    // lazyProduct throughout: at 15 x 15 Eigen would compile its blocked GEMM,
    // which references malloc in a firmware image that must link no allocator.
    q += aq.lazyProduct(a.transpose()) * (dt * dt * dt / Scalar(3));
    const StateMatrix f = StateMatrix::Identity() + dt * a;
    const StateMatrix fp = f.lazyProduct(p_);
    StateMatrix p = fp.lazyProduct(f.transpose()) + q;
    return commit(x, p, k.status());
  }

  /// An attitude measurement [phi, theta, psi] (AHRS).
  Status update_attitude(const Vec3& z) noexcept {
    Eigen::Matrix<Scalar, 3, N> h = Eigen::Matrix<Scalar, 3, N>::Zero();
    h.template block<3, 3>(0, 3).setIdentity();
    Vec3 y = z - x_.template segment<3>(3);
    for (int i = 0; i < 3; ++i) y(i) = wrap(y(i));
    return update<3>(z, y, h, c_.attitude_noise);
  }

  /// A gyro measurement [p, q, r] (with its bias).
  Status update_gyro(const Vec3& z) noexcept {
    Eigen::Matrix<Scalar, 3, N> h = Eigen::Matrix<Scalar, 3, N>::Zero();
    h.template block<3, 3>(0, 9).setIdentity();
    h.template block<3, 3>(0, 12).setIdentity();
    const Vec3 y = z - x_.template segment<3>(9) - x_.template tail<3>();
    return update<3>(z, y, h, c_.gyro_noise);
  }

  /// A DVL measurement of the body velocity over ground [u, v, w].
  Status update_dvl(const Vec3& z) noexcept {
    Eigen::Matrix<Scalar, 3, N> h = Eigen::Matrix<Scalar, 3, N>::Zero();
    h.template block<3, 3>(0, 6).setIdentity();
    const Vec3 y = z - x_.template segment<3>(6);
    return update<3>(z, y, h, c_.dvl_noise);
  }

  /// A depth measurement z (down positive).
  Status update_depth(Scalar z) noexcept {
    Eigen::Matrix<Scalar, 1, N> h = Eigen::Matrix<Scalar, 1, N>::Zero();
    h(0, 2) = Scalar(1);
    Eigen::Matrix<Scalar, 1, 1> zv, y;
    zv(0) = z;
    y(0) = z - x_(2);
    return update<1>(zv, y, h, c_.depth_noise);
  }

  /// An acoustic position fix [x, y, z] (NED) taken `age` >= 0 seconds ago.
  Status update_position(const Vec3& z, Scalar age) noexcept {
    if (!std::isfinite(age)) return Status::non_finite_input;
    if (!(age >= Scalar(0) && age <= Scalar(kMaxStep))) return Status::invalid_argument;
    const auto k = EulerKinematics<Scalar>::from_pose(eta());
    const Vec3 v = x_.template segment<3>(6);
    Eigen::Matrix<Scalar, 3, N> h = Eigen::Matrix<Scalar, 3, N>::Zero();
    h.template block<3, 3>(0, 0).setIdentity();
    h.template block<3, 3>(0, 3) = -age * rotation_jacobian(v);
    h.template block<3, 3>(0, 6) = -age * k.R;
    const Vec3 y = z - (x_.template head<3>() - age * (k.R * v));
    return update<3>(z, y, h, c_.position_noise);
  }

 private:
  static Scalar wrap(Scalar a) noexcept {
    const Scalar pi = Scalar(3.14159265358979323846);
    a = std::remainder(a, Scalar(2) * pi);
    return a <= -pi ? a + Scalar(2) * pi : a;
  }

  /// Central-difference step for the angle Jacobians: cbrt(epsilon)
  /// balances truncation (h^2) against rounding (epsilon / h).
  static Scalar jacobian_step() noexcept {
    return std::cbrt(std::numeric_limits<Scalar>::epsilon());
  }

  /// d(R(Theta) v)/dTheta.
  Matrix3<Scalar> rotation_jacobian(const Vec3& v) const noexcept {
    Matrix3<Scalar> d;
    const Scalar hs = jacobian_step();
    for (int j = 0; j < 3; ++j) {
      Vec3 up = x_.template segment<3>(3), down = up;
      up(j) += hs;
      down(j) -= hs;
      d.col(j) = (rotation(up(0), up(1), up(2)) * v - rotation(down(0), down(1), down(2)) * v) /
                 (Scalar(2) * hs);
    }
    return d;
  }

  /// d(T(Theta) omega)/dTheta (psi does not enter T).
  Matrix3<Scalar> transform_jacobian(const Vec3& w) const noexcept {
    Matrix3<Scalar> d = Matrix3<Scalar>::Zero();
    const Scalar hs = jacobian_step();
    for (int j = 0; j < 2; ++j) {
      Vec3 up = x_.template segment<3>(3), down = up;
      up(j) += hs;
      down(j) -= hs;
      const auto tu = EulerTrig<Scalar>::from_angles(up(0), up(1), up(2));
      const auto td = EulerTrig<Scalar>::from_angles(down(0), down(1), down(2));
      d.col(j) = (attitude_transform(tu) * w - attitude_transform(td) * w) / (Scalar(2) * hs);
    }
    return d;
  }

  template <int M>
  Status update(const Eigen::Matrix<Scalar, M, 1>& z, const Eigen::Matrix<Scalar, M, 1>& y,
                const Eigen::Matrix<Scalar, M, N>& h, Scalar noise_std) noexcept {
    if (!valid_) return Status::invalid_argument;
    if (!detail::all_finite(z)) return Status::non_finite_input;
    using MatM = Eigen::Matrix<Scalar, M, M>;
    const MatM r = MatM::Identity() * (noise_std * noise_std);
    const Eigen::Matrix<Scalar, N, M> pht = p_.lazyProduct(h.transpose());
    MatM s = h.lazyProduct(pht) + r;
    s = (Scalar(0.5) * (s + s.transpose())).eval();
    MatM s_inv;
    if (!detail::spd_inverse(s, s_inv)) return Status::non_finite_output;
    const Eigen::Matrix<Scalar, N, M> gain = pht.lazyProduct(s_inv);
    StateVector x = x_ + gain * y;
    x(5) = wrap(x(5));
    const StateMatrix ikh = StateMatrix::Identity() - gain.lazyProduct(h);
    const StateMatrix ikhp = ikh.lazyProduct(p_);
    const Eigen::Matrix<Scalar, N, M> gr = gain.lazyProduct(r);
    StateMatrix p = ikhp.lazyProduct(ikh.transpose()) + gr.lazyProduct(gain.transpose());
    return commit(x, p, Status::ok);
  }

  Status commit(const StateVector& x, StateMatrix& p, Status status) noexcept {
    p = (Scalar(0.5) * (p + p.transpose())).eval();
    if (!detail::all_finite(x, p)) return Status::non_finite_output;
    x_ = x;
    p_ = p;
    return status;
  }

  EkfConfig<Scalar> c_{};
  StateVector x_ = StateVector::Zero();
  StateMatrix p_ = StateMatrix::Zero();
  bool valid_ = false;
};

}  // namespace neurov
