// What a run's metrics are computed from, accumulated row by row as the run
// goes, so that a run need not keep its rows (a study's metrics-only runs).
//
// NEUROV_WINDOW_SUMS is the one list of the sums: it declares the members of
// WindowSums and the table kWindowSums that the bindings export as
// neurov._core.WINDOW_SUMS; neurov.metrics.WindowSums has exactly these
// fields (a test checks it) and computes every metric from them: the sums
// are made here alone, for a C++ run (run_batch's metrics_only) and for a
// Python Result's rows alike (RunSums::add_rows, bound as neurov._core.RunSums).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <utility>

#include "neurov/core/types.hpp"
#include "neurov/sim/result.hpp"

namespace neurov {

/// One accumulated quantity as the outside world sees it.
struct WindowSumSpec {
  const char* name;  ///< the member's name, and the attribute's in neurov.metrics.WindowSums
  int width;         ///< 1 for a number, 6 for one per degree of freedom
  const char* description;
};

// X(member, type, width, initial value, description). e = eta - eta_d (the
// true pose), tau = tau_demanded, status = controller_status, over the rows
// of the window.
#define NEUROV_WINDOW_SUMS(X)                                                                   \
  X(rows, std::int64_t, 1, 0, "Rows in the window.")                                           \
  X(t_first, double, 1, kNaN, "Time of the window's first row [s].")                           \
  X(t_last, double, 1, kNaN, "Time of the window's last row [s].")                             \
  X(e2, Sums6, 6, 0.0, "Sum of e_i^2 per DOF.")                                                \
  X(abs_e, Sums6, 6, 0.0, "Sum of |e_i| per DOF.")                                             \
  X(max_abs_e, Sums6, 6, -kInf, "Max of |e_i| per DOF (NaN once a NaN is met).")               \
  X(pos2, double, 1, 0.0, "Sum of |e_xyz|^2.")                                                 \
  X(max_pos, double, 1, -kInf, "Max of |e_xyz| (NaN once a NaN is met).")                      \
  X(abs_tau, double, 1, 0.0, "Sum of |tau_i| over every DOF.")                                 \
  X(abs_tau_dof, Sums6, 6, 0.0, "Sum of |tau_i| per DOF.")                                     \
  X(max_abs_tau_dof, Sums6, 6, -kInf, "Max of |tau_i| per DOF (NaN once a NaN is met).")       \
  X(tau_norm, double, 1, 0.0, "Sum of ||tau||.")                                               \
  X(refused, std::int64_t, 1, 0, "Refused controller steps (controller_status != ok).")

inline constexpr WindowSumSpec kWindowSums[] = {
#define NEUROV_WINDOW_SUM_SPEC(member, type, width, init, description) {#member, width, description},
    NEUROV_WINDOW_SUMS(NEUROV_WINDOW_SUM_SPEC)
#undef NEUROV_WINDOW_SUM_SPEC
};

struct WindowSums {
  using Sums6 = Eigen::Matrix<double, 6, 1>;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  static constexpr double kInf = std::numeric_limits<double>::infinity();

#define NEUROV_WINDOW_SUM_MEMBER(member, type, width, init, description) \
  type member = init_value<type>(init);
  NEUROV_WINDOW_SUMS(NEUROV_WINDOW_SUM_MEMBER)
#undef NEUROV_WINDOW_SUM_MEMBER

  /// Adds one row: time t, error e = eta - eta_d, force tau, controller status.
  template <typename Scalar>
  void add(double t, const Vector6<Scalar>& e_in, const Vector6<Scalar>& tau_in,
           std::uint8_t status) noexcept {
    const Sums6 e = e_in.template cast<double>(), tau = tau_in.template cast<double>();
    if (rows == 0) t_first = t;
    t_last = t;
    ++rows;
    const Sums6 ae = e.cwiseAbs(), at = tau.cwiseAbs();
    // |e_xyz| as numpy's norm gives it (the root of the squares), then squared
    // as neurov.metrics does, so that the sums agree to the last bits.
    const double pos = std::sqrt(e(0) * e(0) + e(1) * e(1) + e(2) * e(2));
    for (int i = 0; i < 6; ++i) {
      e2(i) += e(i) * e(i);
      abs_e(i) += ae(i);
      max_abs_e(i) = nan_max(max_abs_e(i), ae(i));
      abs_tau_dof(i) += at(i);
      max_abs_tau_dof(i) = nan_max(max_abs_tau_dof(i), at(i));
    }
    pos2 += pos * pos;
    max_pos = nan_max(max_pos, pos);
    abs_tau += ((at(0) + at(1)) + (at(2) + at(3))) + (at(4) + at(5));
    tau_norm += std::sqrt(tau.squaredNorm());
    if (status != 0) ++refused;
  }

  /// Calls f(spec, member) on every sum, in the table's order.
  template <typename F>
  void visit(F&& f) const {
    std::size_t i = 0;
#define NEUROV_WINDOW_SUM_VISIT(member, ...) f(kWindowSums[i++], member);
    NEUROV_WINDOW_SUMS(NEUROV_WINDOW_SUM_VISIT)
#undef NEUROV_WINDOW_SUM_VISIT
  }

 private:
  template <typename T>
  static T init_value(double v) {
    if constexpr (std::is_same_v<T, Sums6>)
      return Sums6::Constant(v);
    else
      return static_cast<T>(v);
  }
  /// numpy's maximum: a NaN on either side gives NaN.
  static double nan_max(double a, double b) noexcept {
    return (std::isnan(a) || std::isnan(b)) ? kNaN : (b > a ? b : a);
  }
};

/// A whole run's metric sums: the rows before `after` and from it on (the
/// window), and what the metrics read over every row. What
/// neurov.metrics.MetricsWindow accumulates from a run's rows.
struct RunSums {
  double after = 0.0;  ///< rows with t >= after are in the window
  WindowSums before, window;
  double final_adaptive_norm = WindowSums::kNaN;  ///< adaptive_norm at the last row
  double max_adaptive_norm = -WindowSums::kInf;   ///< its max (NaN once a NaN is met)
  bool diverged = false;
  /// The first refused controller step: its time and status (status 0: none).
  double first_refused_t = WindowSums::kNaN;
  std::uint8_t first_refused_status = 0;

  /// Adds the first `rows` rows of `r`, in time order after those added before.
  template <typename Scalar>
  void add(const SimulationResult<Scalar>& r, Eigen::Index rows) noexcept {
    add_rows(r.t, r.eta, r.eta_d, r.tau_demanded, r.controller_status, r.adaptive_norm, rows, r.diverged);
  }

  /// Adds `rows` rows given as columns (row k: t(k), eta.row(k), eta_d.row(k),
  /// tau.row(k), status(k), adaptive_norm(k)), in time order after those added
  /// before, of a run that has diverged or not: a SimulationResult's series,
  /// or a Python Result's arrays (neurov.metrics.MetricsWindow).
  template <typename T, typename Eta, typename EtaD, typename Tau, typename Status, typename Norm>
  void add_rows(const T& t_in, const Eta& eta, const EtaD& eta_d, const Tau& tau_in, const Status& status_in,
                const Norm& adaptive_norm, Eigen::Index rows, bool run_diverged) noexcept {
    using Scalar = typename Eta::Scalar;
    for (Eigen::Index k = 0; k < rows; ++k) {
      const double t = static_cast<double>(t_in(k));
      const auto status = static_cast<std::uint8_t>(status_in(k));
      if (status != 0 && first_refused_status == 0) {
        first_refused_t = t;
        first_refused_status = status;
      }
      const Vector6<Scalar> e = (eta.row(k) - eta_d.row(k)).transpose();
      const Vector6<Scalar> tau = tau_in.row(k).transpose();
      (t >= after ? window : before).add(t, e, tau, status);
      const double norm = static_cast<double>(adaptive_norm(k));
      final_adaptive_norm = norm;
      max_adaptive_norm = (std::isnan(max_adaptive_norm) || std::isnan(norm))
                              ? WindowSums::kNaN
                              : std::max(max_adaptive_norm, norm);
    }
    diverged = diverged || run_diverged;
  }

  /// Calls f(name, value) on what the sums are to the outside world, in
  /// order: after, before and window (WindowSums), final_adaptive_norm,
  /// max_adaptive_norm, diverged and first_refused, the first refused step's
  /// (time, status) or none.
  template <typename F>
  void visit(F&& f) const {
    f("after", after);
    f("before", before);
    f("window", window);
    f("final_adaptive_norm", final_adaptive_norm);
    f("max_adaptive_norm", max_adaptive_norm);
    f("diverged", diverged);
    f("first_refused", first_refused_status ? std::optional(std::pair(first_refused_t, int(first_refused_status)))
                                            : std::nullopt);
  }
};

}  // namespace neurov
