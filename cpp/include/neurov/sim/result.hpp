// What a closed-loop run logs: one row per control step t_k = k dt.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <initializer_list>

namespace neurov {

template <typename Scalar>
struct SimulationResult {
  using Rows6 = Eigen::Matrix<Scalar, Eigen::Dynamic, 6, Eigen::RowMajor>;
  using Rows3 = Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowsX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> t;
  Rows6 eta, nu, eta_d, eta_d_dot, tau_demanded, tau_applied, disturbance, s;
  /// What the controller was given at t_k: the measurement (ideal sensing),
  /// the raw sensor readings or the estimate; NaN in a dropout.
  Rows6 eta_estimate, nu_estimate;
  RowsX thrusts;      ///< produced thrust per thruster (mean over the interval)
  /// The controller's logged parameters per step: theta_hat of the linear
  /// adaptive controller; no columns for the others.
  RowsX theta;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> adaptive_norm;  ///< ||W||_F or ||theta_hat||
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> controller_status;
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> plant_status;
  /// fault_bits active in each step.
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> faults;
  /// The sea at the vehicle at t_k: the current's NED velocity (the one
  /// acting over [t_k, t_k+1) for the Gauss-Markov model), the waves'
  /// orbital velocity (NED) and the surface elevation above the vehicle
  /// (zeros in a calm sea).
  Rows3 current, wave_velocity;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> wave_elevation;
  /// The payload mass in effect at t_k: the sum of the events' `mass` so far [kg].
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> payload_mass;
  /// Rows actually simulated: fewer than planned if the plant diverged.
  Eigen::Index steps = 0;
  bool diverged = false;

  /// `rows` zero rows, with `thrusters` and `parameters` columns where these vary.
  void allocate(Eigen::Index rows, Eigen::Index thrusters, Eigen::Index parameters) {
    t.setZero(rows);
    for (Rows6* m : {&eta, &nu, &eta_d, &eta_d_dot, &tau_demanded, &tau_applied, &disturbance, &s,
                     &eta_estimate, &nu_estimate})
      m->setZero(rows, 6);
    thrusts.setZero(rows, thrusters);
    theta.setZero(rows, parameters);
    adaptive_norm.setZero(rows);
    controller_status.setZero(rows);
    plant_status.setZero(rows);
    faults.setZero(rows);
    current.setZero(rows, 3);
    wave_velocity.setZero(rows, 3);
    wave_elevation.setZero(rows);
    payload_mass.setZero(rows);
    steps = 0;
    diverged = false;
  }

  /// Zeroes every row in place: same sizes, no allocation.
  void clear() noexcept {
    t.setZero();
    for (Rows6* m : {&eta, &nu, &eta_d, &eta_d_dot, &tau_demanded, &tau_applied, &disturbance, &s,
                     &eta_estimate, &nu_estimate})
      m->setZero();
    thrusts.setZero();
    theta.setZero();
    adaptive_norm.setZero();
    controller_status.setZero();
    plant_status.setZero();
    faults.setZero();
    current.setZero();
    wave_velocity.setZero();
    wave_elevation.setZero();
    payload_mass.setZero();
    steps = 0;
    diverged = false;
  }

  /// Only the first `rows` rows (the ones simulated) are kept.
  void truncate(Eigen::Index rows) {
    t.conservativeResize(rows);
    for (Rows6* m : {&eta, &nu, &eta_d, &eta_d_dot, &tau_demanded, &tau_applied, &disturbance, &s,
                     &eta_estimate, &nu_estimate})
      m->conservativeResize(rows, 6);
    thrusts.conservativeResize(rows, thrusts.cols());
    theta.conservativeResize(rows, theta.cols());
    adaptive_norm.conservativeResize(rows);
    controller_status.conservativeResize(rows);
    plant_status.conservativeResize(rows);
    faults.conservativeResize(rows);
    current.conservativeResize(rows, 3);
    wave_velocity.conservativeResize(rows, 3);
    wave_elevation.conservativeResize(rows);
    payload_mass.conservativeResize(rows);
  }
};

}  // namespace neurov
