// What a closed-loop run logs: one row per control step t_k = k dt.
//
// NEUROV_RESULT_SERIES is the one list of the logged series: it declares the
// members of SimulationResult, the table kResultSeries (each series' name,
// width, column labels, unit and meaning) that the bindings export as
// neurov._core.RESULT_SERIES, and the loop of allocate/clear/truncate. The
// Python result, its CSV, NPZ, Parquet and pandas columns are derived from
// that table, so a new series is its line here and the line in
// Simulator::step that fills it.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace neurov {

/// What a series' numbers are: real values, neurov::Status codes (written
/// by name in tables), or the bits of fault_bits.
enum class SeriesKind : std::uint8_t { real = 0, status = 1, bits = 2 };

/// A series whose columns vary from run to run: one per thruster, or one per
/// logged controller parameter (the regressor's theta, THETA_NAMES).
inline constexpr int kPerThruster = -1;
inline constexpr int kPerParameter = -2;

/// One logged series as the outside world sees it.
struct SeriesSpec {
  const char* name;         ///< the member's name and the array's in Python
  int width;                ///< columns: 1 for a column, kPerThruster or kPerParameter
  const char* labels;       ///< space-separated column labels; "" for one column or varying ones
  const char* unit;         ///< SI units of the columns
  SeriesKind kind;
  const char* description;  ///< one sentence, for the docs and the Python docstrings
};

// X(member, type, width, labels, unit, kind, description); `type` is one of
// SimulationResult's table types below. Rows are at t_k = k dt.
#define NEUROV_POSE_LABELS "x y z phi theta psi"
#define NEUROV_BODY_LABELS "u v w p q r"
#define NEUROV_FORCE_LABELS "X Y Z K M N"
#define NEUROV_NED_LABELS "N E D"
#define NEUROV_RESULT_SERIES(X)                                                                  \
  X(t, Column, 1, "", "s", real, "Time t_k = k dt.")                                            \
  X(eta, Rows6, 6, NEUROV_POSE_LABELS, "m, rad", real,                                          \
    "The true pose (NED position, roll, pitch, yaw).")                                           \
  X(nu, Rows6, 6, NEUROV_BODY_LABELS, "m/s, rad/s", real, "The true body velocity.")            \
  X(eta_d, Rows6, 6, NEUROV_POSE_LABELS, "m, rad", real, "The desired pose.")                   \
  X(eta_d_dot, Rows6, 6, NEUROV_POSE_LABELS, "m/s, rad/s", real,                                \
    "The desired pose's time derivative.")                                                       \
  X(tau_demanded, Rows6, 6, NEUROV_FORCE_LABELS, "N, N m", real,                                \
    "The generalised force the controller demanded (after the force limits).")                   \
  X(tau_applied, Rows6, 6, NEUROV_FORCE_LABELS, "N, N m", real,                                 \
    "The force the thrusters applied, mean over [t_k, t_k+1).")                                  \
  X(disturbance, Rows6, 6, NEUROV_FORCE_LABELS, "N, N m", real,                                 \
    "The sinusoidal disturbance force at t_k.")                                                  \
  X(s, Rows6, 6, NEUROV_POSE_LABELS, "m/s, rad/s", real,                                        \
    "The controller's sliding variable s = e_dot + Lambda e.")                                   \
  X(eta_estimate, Rows6, 6, NEUROV_POSE_LABELS, "m, rad", real,                                 \
    "The pose the controller was given: the measurement, the sensors' or the estimate; NaN in "  \
    "a dropout.")                                                                                \
  X(nu_estimate, Rows6, 6, NEUROV_BODY_LABELS, "m/s, rad/s", real,                              \
    "The body velocity the controller was given.")                                               \
  X(thrusts, RowsX, kPerThruster, "", "N", real,                                                \
    "The thrust each thruster produced, mean over the interval (numbered from 0).")              \
  X(theta, RowsX, kPerParameter, "", "", real,                                                  \
    "The linear adaptive controller's theta_hat (THETA_NAMES); no columns for the others.")      \
  X(adaptive_norm, Column, 1, "", "", real, "||W||_F of the NN or ||theta_hat||.")              \
  X(controller_status, Codes, 1, "", "", status, "The controller step's neurov.Status.")         \
  X(plant_status, Codes, 1, "", "", status, "The plant step's neurov.Status.")                   \
  X(faults, Codes, 1, "", "", bits,                                                              \
    "Faults active in the step: bit 1 sensor freeze, 2 dropout, 4 noise burst, 8 a thruster "    \
    "below full efficiency, 16 the row's eta_d came from a pitch-limited reference step, 32 "    \
    "the vehicle above the wave model's minimum depth.")                                         \
  X(current, Rows3, 3, NEUROV_NED_LABELS, "m/s", real,                                          \
    "The current's NED velocity at the vehicle (the one acting over [t_k, t_k+1) for the "       \
    "Gauss-Markov model).")                                                                      \
  X(wave_velocity, Rows3, 3, NEUROV_NED_LABELS, "m/s", real,                                    \
    "The waves' NED orbital velocity at the vehicle (zeros in a calm sea).")                     \
  X(wave_elevation, Column, 1, "", "m", real, "The surface elevation above the vehicle.")       \
  X(payload_mass, Column, 1, "", "kg", real,                                                    \
    "The payload mass in effect: the sum of the events' mass so far.")

#define NEUROV_SERIES_SPEC(member, type, width, labels, unit, kind, description) \
  SeriesSpec{#member, width, labels, unit, SeriesKind::kind, description},
/// The logged series, in the order of the CSV's columns.
inline constexpr SeriesSpec kResultSeries[] = {NEUROV_RESULT_SERIES(NEUROV_SERIES_SPEC)};
#undef NEUROV_SERIES_SPEC

template <typename Scalar>
struct SimulationResult {
  using Column = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Rows6 = Eigen::Matrix<Scalar, Eigen::Dynamic, 6, Eigen::RowMajor>;
  using Rows3 = Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowsX = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  using Codes = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>;

#define NEUROV_SERIES_MEMBER(member, type, ...) type member;
  NEUROV_RESULT_SERIES(NEUROV_SERIES_MEMBER)
#undef NEUROV_SERIES_MEMBER
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

  /// Calls f(spec, series) on every logged series, in the table's order.
  template <typename F>
  void visit(F&& f) {
    std::size_t i = 0;
#define NEUROV_SERIES_VISIT(member, ...) f(kResultSeries[i++], member);
    NEUROV_RESULT_SERIES(NEUROV_SERIES_VISIT)
#undef NEUROV_SERIES_VISIT
  }

 private:
  /// Calls f(series, columns) on every logged series.
  template <typename F>
  void for_each_series(Eigen::Index thrusters, Eigen::Index parameters, F&& f) {
    visit([&](const SeriesSpec& spec, auto& series) {
      f(series, spec.width == kPerThruster    ? thrusters
                : spec.width == kPerParameter ? parameters
                                              : Eigen::Index(spec.width));
    });
  }
};

}  // namespace neurov
