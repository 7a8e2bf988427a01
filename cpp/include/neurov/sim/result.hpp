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
    for_each_series(thrusters, parameters,
                    [rows](auto& series, Eigen::Index cols) { series.setZero(rows, cols); });
    steps = 0;
    diverged = false;
  }

  /// Zeroes every row in place: same sizes, no allocation.
  void clear() noexcept {
    for_each_series(thrusts.cols(), theta.cols(), [](auto& series, Eigen::Index) {
      series.setZero();
    });
    steps = 0;
    diverged = false;
  }

  /// Only the first `rows` rows (the ones simulated) are kept.
  void truncate(Eigen::Index rows) {
    for_each_series(thrusts.cols(), theta.cols(), [rows](auto& series, Eigen::Index cols) {
      series.conservativeResize(rows, cols);
    });
  }

 private:
  /// Calls f(series, columns) on every logged series: the one list of them,
  /// so that a new series cannot be left out of allocate, clear or truncate.
  template <typename F>
  void for_each_series(Eigen::Index thrusters, Eigen::Index parameters, F&& f) {
    f(t, 1);
    for (Rows6* m : {&eta, &nu, &eta_d, &eta_d_dot, &tau_demanded, &tau_applied, &disturbance, &s,
                     &eta_estimate, &nu_estimate})
      f(*m, 6);
    f(thrusts, thrusters);
    f(theta, parameters);
    f(adaptive_norm, 1);
    f(controller_status, 1);
    f(plant_status, 1);
    f(faults, 1);
    f(current, 3);
    f(wave_velocity, 3);
    f(wave_elevation, 1);
    f(payload_mass, 1);
  }
};

}  // namespace neurov
