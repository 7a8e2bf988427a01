// One thruster from command to thrust: a static curve given as a table
// (linearly interpolated), a dead band around the neutral command, scaling
// with the supply voltage, then a first-order lag and a slew-rate limit on
// the thrust; and the inverse of the static curve (thrust -> command) for
// allocation.
//
//   f(c)       = 0 for |c - neutral| <= dead_band, else table(c) (c clamped
//                to the table's range: that is the saturation)
//   target     = f(c) * (V / reference_voltage)^voltage_exponent
//   lag        : y <- target + (y - target) exp(-dt / time_constant)
//   slew limit : |y_new - y_old| <= slew_rate * dt
//
// Forward and reverse thrust differ because the table does: its commands
// below neutral carry the reverse thrusts, those above the forward ones.
// The curve's numbers come from the user (a vehicle file); no
// manufacturer's data is built in (the T200's, with its source, is in
// python/neurov/vehicles/bluerov2_heavy.toml).
#pragma once

#include <array>
#include <cmath>
#include <tuple>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

/// Rows a curve table can hold: room for a manufacturer's PWM table
/// (1100 to 1900 us) at a few microseconds per row.
inline constexpr int kThrusterCurveCapacity = 256;

template <typename Scalar>
struct ThrusterCurveConfig {
  /// Table commands (any unit: PWM us, or -1..1), strictly increasing.
  std::array<Scalar, kThrusterCurveCapacity> command{};
  /// Thrust [N] at each command at reference_voltage.
  std::array<Scalar, kThrusterCurveCapacity> thrust{};
  /// Rows used, 2..kThrusterCurveCapacity.
  int points = 0;
  /// The command of zero thrust, inside the table's range.
  Scalar neutral = Scalar(0);
  /// Half-width of the dead band around neutral (command units), >= 0.
  Scalar dead_band = Scalar(0);
  /// Supply voltage [V] at which the table was measured, > 0 (no default:
  /// it belongs to the data).
  Scalar reference_voltage = Scalar(0);
  /// Thrust ~ voltage^exponent at a fixed command. 2 is the propeller law
  /// (thrust ~ n^2) with shaft speed ~ voltage at a fixed duty cycle: an
  /// assumption, not a fit; set it from data where they exist.
  Scalar voltage_exponent = Scalar(2);
  /// First-order lag of the thrust [s]; 0: none.
  Scalar time_constant = Scalar(0);
  /// Largest rate of change of the thrust [N/s]; 0: unlimited.
  Scalar slew_rate = Scalar(0);
};

/// The curve's fields; `table` stands for the rows of command and thrust
/// (its member is the command column; the binding reads thrust and points
/// beside it). validate() below checks them.
template <typename Scalar>
auto config_fields(const ThrusterCurveConfig<Scalar>*) noexcept {
  using C = ThrusterCurveConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("table", &C::command,
                    "(n, 2) rows of (command, thrust [N] at reference_voltage), commands strictly "
                    "increasing, 2 <= n <= 256 (a read-only copy; assign a whole table)"),
      field_spec<C>("neutral", &C::neutral, "The command of zero thrust, inside the table"),
      field_spec<C>("dead_band", &C::dead_band, "", Check::non_negative,
                    "Half-width of the dead band around neutral (command units)"),
      field_spec<C>("reference_voltage", &C::reference_voltage, "V", Check::positive,
                    "Supply voltage at which the table was measured"),
      field_spec<C>("voltage_exponent", &C::voltage_exponent, "", Check::non_negative,
                    "Thrust ~ voltage^exponent at a fixed command (2: an assumption)"),
      field_spec<C>("time_constant", &C::time_constant, "s", Check::non_negative,
                    "First-order lag of the thrust (0: none)"),
      field_spec<C>("slew_rate", &C::slew_rate, "N/s", Check::non_negative,
                    "Largest rate of change of the thrust (0: none)"));
}

namespace detail {
/// The table alone, linearly interpolated, clamped to its ends.
template <typename Scalar>
inline Scalar interpolate_curve(const ThrusterCurveConfig<Scalar>& c, Scalar command) noexcept {
  const int n = c.points;
  if (command <= c.command[0]) return c.thrust[0];
  if (command >= c.command[n - 1]) return c.thrust[n - 1];
  int lo = 0, hi = n - 1;  // command[lo] < command <= command[hi]
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (c.command[mid] < command) lo = mid; else hi = mid;
  }
  const Scalar w = (command - c.command[lo]) / (c.command[hi] - c.command[lo]);
  return c.thrust[lo] + w * (c.thrust[hi] - c.thrust[lo]);
}
}  // namespace detail

/// Checks sizes, finiteness, strictly increasing commands, neutral and dead
/// band inside the table, non-negative rates, and a curve that rises
/// strictly wherever it lies outside the dead band, below zero under it and
/// above zero over it (so the inverse exists there).
template <typename Scalar>
inline ValidationError validate(const ThrusterCurveConfig<Scalar>& c) noexcept {
  using detail::invalid;
  const int n = c.points;
  if (!(n >= 2 && n <= kThrusterCurveCapacity))
    return invalid("thruster_curve.points", -1, n, "2 to 256 rows (kThrusterCurveCapacity)");
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(static_cast<double>(c.command[i])))
      return invalid("thruster_curve.command", i, c.command[i], "finite");
    if (!std::isfinite(static_cast<double>(c.thrust[i])))
      return invalid("thruster_curve.thrust", i, c.thrust[i], "finite");
    if (i > 0 && !(c.command[i] > c.command[i - 1]))
      return invalid("thruster_curve.command", i, c.command[i], "strictly increasing");
  }
  if (!(std::isfinite(static_cast<double>(c.neutral)) && c.neutral >= c.command[0] &&
        c.neutral <= c.command[n - 1]))
    return invalid("thruster_curve.neutral", -1, c.neutral, "inside the table's command range");
  if (auto e = detail::check_non_negative_scalar("thruster_curve.dead_band", c.dead_band)) return e;
  if (auto e = detail::check_positive_scalar("thruster_curve.reference_voltage",
                                             c.reference_voltage))
    return e;
  if (auto e = detail::check_non_negative_scalar("thruster_curve.voltage_exponent",
                                                 c.voltage_exponent))
    return e;
  if (auto e = detail::check_non_negative_scalar("thruster_curve.time_constant", c.time_constant))
    return e;
  if (auto e = detail::check_non_negative_scalar("thruster_curve.slew_rate", c.slew_rate)) return e;
  const Scalar lo = c.neutral - c.dead_band, hi = c.neutral + c.dead_band;
  for (int i = 1; i < n; ++i) {
    const bool outside = c.command[i] > hi || c.command[i - 1] < lo;
    if (outside && !(c.thrust[i] > c.thrust[i - 1]))
      return invalid("thruster_curve.thrust", i, c.thrust[i],
                     "strictly increasing with command outside the dead band");
  }
  // With the rise above, the signs at the edges give the signs beyond them.
  if (const Scalar t = detail::interpolate_curve(c, lo); t > Scalar(0))
    return invalid("thruster_curve.thrust", -1, t,
                   "<= 0 at the lower dead-band edge, neutral - dead_band (value is the "
                   "table's thrust there)");
  if (const Scalar t = detail::interpolate_curve(c, hi); t < Scalar(0))
    return invalid("thruster_curve.thrust", -1, t,
                   ">= 0 at the upper dead-band edge, neutral + dead_band (value is the "
                   "table's thrust there)");
  return {};
}

template <typename Scalar>
class ThrusterCurve {
 public:
  /// Validates c and, if valid, builds `out`; `out` is untouched otherwise.
  static ValidationError create(const ThrusterCurveConfig<Scalar>& c, ThrusterCurve& out) noexcept {
    if (auto e = validate(c)) return e;
    out.c_ = c;
    out.thrust_ = Scalar(0);
    out.valid_ = true;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  const ThrusterCurveConfig<Scalar>& config() const noexcept { return c_; }
  Scalar min_command() const noexcept { return c_.command[0]; }
  Scalar max_command() const noexcept { return c_.command[c_.points - 1]; }

  /// (V / reference_voltage)^exponent; 0 for a non-positive or NaN voltage.
  Scalar voltage_factor(Scalar voltage) const noexcept {
    if (!(voltage > Scalar(0)) || !std::isfinite(voltage)) return Scalar(0);
    return std::pow(voltage / c_.reference_voltage, c_.voltage_exponent);
  }

  /// Steady thrust [N] at a command and supply voltage (the static curve).
  /// A NaN command gives 0.
  Scalar static_thrust(Scalar command, Scalar voltage) const noexcept {
    return table_thrust(command) * voltage_factor(voltage);
  }

  /// The command whose steady thrust is `thrust` at `voltage`, clamped to
  /// the table's range (thrust beyond the attainable gives the end command).
  /// A thrust between 0 and the table's value at a dead-band edge (a curve
  /// that jumps there) is not attainable and gives that edge. 0 and NaN give
  /// the neutral command.
  Scalar command_for(Scalar thrust, Scalar voltage) const noexcept {
    const Scalar k = voltage_factor(voltage);
    if (!(k > Scalar(0)) || !std::isfinite(thrust) || thrust == Scalar(0)) return c_.neutral;
    const Scalar t = thrust / k;
    const int n = c_.points;
    if (t > Scalar(0)) {
      const Scalar edge = std::fmin(c_.neutral + c_.dead_band, c_.command[n - 1]);
      if (t <= raw_thrust(edge)) return edge;
      if (t >= c_.thrust[n - 1]) return c_.command[n - 1];
      // First row with thrust >= t: above the edge, where the curve rises.
      int i = n - 1;
      while (i > 0 && c_.thrust[i - 1] >= t && c_.command[i - 1] > edge) --i;
      return interpolate_command(i, edge, t);
    }
    const Scalar edge = std::fmax(c_.neutral - c_.dead_band, c_.command[0]);
    if (t >= raw_thrust(edge)) return edge;
    if (t <= c_.thrust[0]) return c_.command[0];
    int i = 0;  // last row with thrust <= t, below the edge
    while (i + 1 < n && c_.thrust[i + 1] <= t && c_.command[i + 1] < edge) ++i;
    const Scalar c0 = c_.command[i], t0 = c_.thrust[i];
    const Scalar c1 = i + 1 < n && c_.command[i + 1] < edge ? c_.command[i + 1] : edge;
    const Scalar t1 = raw_thrust(c1);
    return t1 > t0 ? c0 + (c1 - c0) * (t - t0) / (t1 - t0) : c0;
  }

  /// Thrust range at a voltage: [static_thrust(min), static_thrust(max)].
  Scalar min_thrust(Scalar voltage) const noexcept { return static_thrust(min_command(), voltage); }
  Scalar max_thrust(Scalar voltage) const noexcept { return static_thrust(max_command(), voltage); }

  /// Advances the thrust over dt toward the static thrust of `command`:
  /// the exact first-order lag for a held command, then the slew limit.
  /// dt must be in (0, kMaxStep] and voltage finite: otherwise the thrust
  /// stays as it was and the status says why.
  Status step(Scalar command, Scalar voltage, Scalar dt) noexcept {
    if (!valid_) return Status::invalid_argument;
    if (!std::isfinite(command) || !std::isfinite(voltage) || !std::isfinite(dt))
      return Status::non_finite_input;
    if (!(dt > Scalar(0) && dt <= Scalar(kMaxStep))) return Status::invalid_argument;
    const Scalar target = static_thrust(command, voltage);
    Scalar next = target;
    if (c_.time_constant > Scalar(0))
      next = target + (thrust_ - target) * std::exp(-dt / c_.time_constant);
    if (c_.slew_rate > Scalar(0)) {
      const Scalar limit = c_.slew_rate * dt;
      next = std::fmin(std::fmax(next, thrust_ - limit), thrust_ + limit);
    }
    thrust_ = next;
    return Status::ok;
  }

  Scalar thrust() const noexcept { return thrust_; }
  void reset(Scalar thrust = Scalar(0)) noexcept { thrust_ = std::isfinite(thrust) ? thrust : Scalar(0); }

 private:
  /// The table with the dead band, at reference voltage.
  Scalar table_thrust(Scalar command) const noexcept {
    if (std::isnan(command)) return Scalar(0);
    if (std::abs(command - c_.neutral) <= c_.dead_band) return Scalar(0);
    return raw_thrust(command);
  }

  Scalar raw_thrust(Scalar command) const noexcept { return detail::interpolate_curve(c_, command); }

  /// Inverse on the rising segment that ends at row i (its start clipped at
  /// the dead-band edge), for a table thrust t inside it.
  Scalar interpolate_command(int i, Scalar edge, Scalar t) const noexcept {
    const Scalar c0 = c_.command[i - 1] > edge ? c_.command[i - 1] : edge;
    const Scalar t0 = raw_thrust(c0), c1 = c_.command[i], t1 = c_.thrust[i];
    return t1 > t0 ? c0 + (c1 - c0) * (t - t0) / (t1 - t0) : c1;
  }

  ThrusterCurveConfig<Scalar> c_{};
  Scalar thrust_ = Scalar(0);
  bool valid_ = false;
};

}  // namespace neurov
