// The configuration of one closed-loop run: timing, the commanded path and
// the reference model, disturbances, current, measurement noise, thrusters
// and the faults injected into a run, with its one validator.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "neurov/control/reference_model.hpp"
#include "neurov/core/field_spec.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/sim/disturbances/gauss_markov_flow.hpp"
#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/disturbances/payload_events.hpp"
#include "neurov/sim/disturbances/sea_waves.hpp"
#include "neurov/sim/disturbances/sinusoids.hpp"
#include "neurov/sim/disturbances/steady_force.hpp"
#include "neurov/sim/disturbances/steady_current.hpp"
#include "neurov/sim/disturbances/tether.hpp"
#include "neurov/sim/disturbances/thruster_failures.hpp"
#include "neurov/sim/flags.hpp"
#include "neurov/sim/gauss_markov_current.hpp"
#include "neurov/sim/payload.hpp"
#include "neurov/sim/sensing.hpp"
#include "neurov/sim/sea_constants.hpp"
#include "neurov/sim/wave_spectrum.hpp"
#include "neurov/sim/waves.hpp"

namespace neurov {

/// A sinusoidal force or moment in one body DOF:
/// amplitude * sin(2 pi frequency (t - start) + phase) for t >= start.
template <typename Scalar>
struct SinusoidalDisturbance {
  int dof = 5;  ///< 0..5: surge, sway, heave, roll, pitch, yaw
  Scalar amplitude = Scalar(0);  ///< [N] or [N m]
  Scalar frequency = Scalar(0);  ///< [Hz]
  Scalar phase = Scalar(0);      ///< [rad]
  Scalar start = Scalar(0);      ///< [s]
};

/// Thruster i works at `efficiency` (0: failed) from `time` on.
template <typename Scalar>
struct ThrusterFailure {
  int index = 0;
  Scalar efficiency = Scalar(0);
  Scalar time = Scalar(0);
};

/// A sensor fault over [start, end): the measurement of eta and/or nu freezes
/// at its last value, drops out (NaN, which the controller refuses), or gets
/// extra white noise of the given standard deviations.
enum class SensorFaultKind : std::uint8_t { freeze = 0, dropout = 1, noise_burst = 2 };

template <typename Scalar>
struct SensorFault {
  SensorFaultKind kind = SensorFaultKind::freeze;
  Scalar start = Scalar(0);
  Scalar end = Scalar(0);
  bool eta = true;  ///< affects the pose measurement
  bool nu = true;   ///< affects the velocity measurement
  Vector6<Scalar> noise_eta = Vector6<Scalar>::Zero();  ///< noise_burst only
  Vector6<Scalar> noise_nu = Vector6<Scalar>::Zero();   ///< noise_burst only
};

/// From `time` on, the mean current is `velocity` (NED): a step in the current.
template <typename Scalar>
struct CurrentStep {
  Scalar time = Scalar(0);
  Vector3<Scalar> velocity = Vector3<Scalar>::Zero();
};

template <typename Scalar>
auto config_fields(const SinusoidalDisturbance<Scalar>*) noexcept {
  using C = SinusoidalDisturbance<Scalar>;
  return std::make_tuple(
      field_spec<C>("dof", &C::dof, "0..5: surge, sway, heave, roll, pitch, yaw."),
      field_spec<C>("amplitude", &C::amplitude, "N or N m", Check::finite, "Amplitude"),
      field_spec<C>("frequency", &C::frequency, "Hz", Check::finite, "Frequency"),
      field_spec<C>("phase", &C::phase, "rad", Check::finite, "Phase"),
      field_spec<C>("start", &C::start, "s", Check::finite, "Start"));
}

template <typename Scalar>
auto config_fields(const ThrusterFailure<Scalar>*) noexcept {
  using C = ThrusterFailure<Scalar>;
  return std::make_tuple(
      field_spec<C>("index", &C::index, "The thruster (a column of the thruster matrix)."),
      field_spec<C>("efficiency", &C::efficiency, "", Check::none, "In [0, 1]"),
      field_spec<C>("time", &C::time, "s", Check::finite, "From when"));
}

template <typename Scalar>
auto config_fields(const SensorFault<Scalar>*) noexcept {
  using C = SensorFault<Scalar>;
  return std::make_tuple(
      field_spec<C>("kind", &C::kind, "A SensorFaultKind."),
      field_spec<C>("start", &C::start, "s", Check::finite, "Start"),
      field_spec<C>("end", &C::end, "s", Check::none, "End, >= start"),
      field_spec<C>("eta", &C::eta, "Affects the pose measurement."),
      field_spec<C>("nu", &C::nu, "Affects the velocity measurement."),
      field_spec<C>("noise_eta", &C::noise_eta, "", Check::non_negative,
                    "Standard deviations (6,); noise_burst only"),
      field_spec<C>("noise_nu", &C::noise_nu, "", Check::non_negative,
                    "Standard deviations (6,); noise_burst only"));
}

template <typename Scalar>
auto config_fields(const CurrentStep<Scalar>*) noexcept {
  using C = CurrentStep<Scalar>;
  return std::make_tuple(field_spec<C>("time", &C::time, "s", Check::none, "From when"),
                         field_spec<C>("velocity", &C::velocity, "m/s", Check::finite,
                                       "The mean current from then on, NED (3,)"));
}

/// What the loop applies when the controller refuses a step (a NaN
/// measurement, the pitch singularity): the zero force the controller writes,
/// or the last force it accepted.
enum class RefusedStepPolicy : std::uint8_t { zero = 0, hold = 1 };

/// Commanded poses r(t) at increasing times; held before the first and after
/// the last; between them linear or held (piecewise constant).
template <typename Scalar>
struct Command {
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> times;
  Eigen::Matrix<Scalar, Eigen::Dynamic, 6, Eigen::RowMajor> poses;
  bool linear = true;

  Vector6<Scalar> at(Scalar t) const noexcept {
    const Eigen::Index n = times.size();
    if (n == 0) return Vector6<Scalar>::Zero();
    if (t <= times(0)) return poses.row(0).transpose();
    if (t >= times(n - 1)) return poses.row(n - 1).transpose();
    Eigen::Index lo = 0, hi = n - 1;  // binary search: times(lo) <= t < times(hi)
    while (hi - lo > 1) {
      const Eigen::Index mid = (lo + hi) / 2;
      (times(mid) <= t ? lo : hi) = mid;
    }
    if (!linear) return poses.row(lo).transpose();
    const Scalar a = (t - times(lo)) / (times(hi) - times(lo));
    return ((Scalar(1) - a) * poses.row(lo) + a * poses.row(hi)).transpose();
  }
};

template <typename Scalar>
auto config_fields(const Command<Scalar>*) noexcept {
  using C = Command<Scalar>;
  return std::make_tuple(
      field_spec<C>("times", &C::times, "s", Check::none, "(K,) strictly increasing"),
      field_spec<C>("poses", &C::poses, "(K, 6) poses eta."),
      field_spec<C>("linear", &C::linear, "Linear between the poses; False: piecewise constant."));
}

/// The longest computation delay a run holds, in control periods: the
/// simulator keeps the forces not yet applied in a fixed ring of this many + 1.
inline constexpr int kMaxControlDelay = 16;
static_assert(kMaxControlDelay == 16, "validate()'s control_delay message names the maximum");

/// The most RK4 substeps a control period takes. At the largest dt
/// (kMaxStep, 10 s) it still gives a 1 ms plant step, and at the paper's
/// 0.2 s a 20 us one, far below any time constant of a vehicle or a thruster
/// (the shipped scenarios use 10). At the limit a control period costs about
/// 2.4 ms (0.24 us an RK4 step of NEROV, docs/reliability.md); 2e9 substeps
/// would take 8 minutes a period, 40 hours for a 60 s run.
inline constexpr int kMaxSubsteps = 10000;
static_assert(kMaxSubsteps == 10000, "validate()'s substeps message names the maximum");

template <typename Scalar>
struct SimulationConfig {
  Scalar dt = Scalar(0.2);  ///< control period [s]
  int substeps = 10;        ///< RK4 steps per control period, 1..kMaxSubsteps
  Scalar duration = Scalar(60);
  Vector6<Scalar> eta0 = Vector6<Scalar>::Zero();
  Vector6<Scalar> nu0 = Vector6<Scalar>::Zero();
  Command<Scalar> command;
  Vector6<Scalar> lambda_d = Vector6<Scalar>::Constant(Scalar(1));  ///< reference damping
  Vector6<Scalar> omega = Vector6<Scalar>::Constant(Scalar(0.25));  ///< reference stiffness
  std::vector<SinusoidalDisturbance<Scalar>> disturbances;
  /// Current in NED: mean + amplitude * sin(2 pi t / period) per axis.
  Vector3<Scalar> current = Vector3<Scalar>::Zero();
  Vector3<Scalar> current_amplitude = Vector3<Scalar>::Zero();
  Scalar current_period = Scalar(0);  ///< [s]; 0 means a constant current
  /// Standard deviations of white Gaussian noise on the measured eta and nu.
  Vector6<Scalar> noise_eta = Vector6<Scalar>::Zero();
  Vector6<Scalar> noise_nu = Vector6<Scalar>::Zero();
  std::uint64_t seed = 0;
  bool use_thrusters = false;
  ThrusterConfig<Scalar> thrusters;
  std::vector<ThrusterFailure<Scalar>> thruster_failures;
  std::vector<SensorFault<Scalar>> sensor_faults;
  std::vector<CurrentStep<Scalar>> current_steps;  ///< in increasing time
  RefusedStepPolicy refused_step_policy = RefusedStepPolicy::zero;
  CurrentModel current_model = CurrentModel::constant;
  /// Used when current_model is gauss_markov; advanced once per control
  /// period on its own random stream (RandomStream::current).
  GaussMarkovCurrentConfig<Scalar> gauss_markov_current;
  /// Linear deep-water waves (RandomStream::waves); empty: a calm sea.
  std::optional<WaveConfig<Scalar>> waves;
  /// Changes of the vehicle the controller is not told about, in
  /// non-decreasing time; each is checked against the vehicle it changes by
  /// Simulator::create (validate_payload).
  std::vector<PayloadEvent<Scalar>> payload;
  /// Control periods between the measurement a force is computed from and
  /// the interval it acts over, 0..kMaxControlDelay: the force demanded at
  /// row k acts over [t_k+n, t_k+n+1); before row n no force acts.
  int control_delay = 0;
  /// The density of the water [kg/m^3], > 0: sea water by default. The
  /// buoyancy of a vehicle given by its displaced volume is
  /// buoyancy_in_water(water_density, volume); a Vehicle built with it is
  /// what the simulator runs (it takes the Vehicle's buoyancy as given).
  Scalar water_density = Scalar(1025);
  /// The sensors; none configured: ideal sensing (the true state with the
  /// white noise of noise_eta and noise_nu).
  SensorsConfig<Scalar> sensors;
  /// What the controller is given from the sensors (used when some are configured).
  EstimatorConfig<Scalar> estimator;
  /// A ROV's umbilical to a surface point (parts::Tether); empty: none.
  std::optional<TetherConfig<Scalar>> tether;
  /// A steady force fixed in the earth frame (parts::SteadyForce); empty: none.
  std::optional<SteadyForceConfig<Scalar>> steady_force;
};

/// SimulationConfig's fields (its validator and the disturbance parts' check them).
template <typename Scalar>
auto config_fields(const SimulationConfig<Scalar>*) noexcept {
  using C = SimulationConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("dt", &C::dt, "s", Check::none, "Control period"),
      field_spec<C>("substeps", &C::substeps, "RK4 steps per control period, 1 to 10000 (MAX_SUBSTEPS)."),
      field_spec<C>("duration", &C::duration, "s", Check::none, "Duration"),
      field_spec<C>("eta0", &C::eta0, "", Check::finite, "Initial pose (6,)"),
      field_spec<C>("nu0", &C::nu0, "", Check::finite, "Initial body velocity (6,)"),
      field_spec<C>("command", &C::command, "The commanded path (a Command)."),
      field_spec<C>("lambda_d", &C::lambda_d, "", Check::positive, "Reference-model damping (6,)"),
      field_spec<C>("omega", &C::omega, "", Check::positive, "Reference-model stiffness (6,)"),
      field_spec<C>("disturbances", &C::disturbances, "Sinusoidal forces (a tuple; assign a list)."),
      field_spec<C>("current", &C::current, "m/s", Check::finite, "Mean current, NED (3,)"),
      field_spec<C>("current_amplitude", &C::current_amplitude, "m/s", Check::finite,
                    "Amplitude of the current's sinusoid per axis (3,)"),
      field_spec<C>("current_period", &C::current_period, "s", Check::non_negative,
                    "0 means a constant current"),
      field_spec<C>("noise_eta", &C::noise_eta, "", Check::non_negative,
                    "Standard deviations of the pose noise (6,)"),
      field_spec<C>("noise_nu", &C::noise_nu, "", Check::non_negative,
                    "Standard deviations of the velocity noise (6,)"),
      field_spec<C>("seed", &C::seed,
                    "Seed of the measurement noise; the current's and the waves' streams are "
                    "derived from it."),
      field_spec<C>("use_thrusters", &C::use_thrusters,
                    "Allocate the force to `thrusters`; False: the force acts directly."),
      field_spec<C>("thrusters", &C::thrusters, "The thruster layout (a ThrusterConfig)."),
      field_spec<C>("thruster_failures", &C::thruster_failures,
                    "Thruster failures (a tuple; assign a list)."),
      field_spec<C>("sensor_faults", &C::sensor_faults, "Sensor faults (a tuple; assign a list)."),
      field_spec<C>("current_steps", &C::current_steps,
                    "Steps of the mean current, in increasing time (a tuple; assign a list)."),
      field_spec<C>("refused_step_policy", &C::refused_step_policy,
                    "The force applied on a refused step (a RefusedStepPolicy)."),
      field_spec<C>("current_model", &C::current_model, "A CurrentModel."),
      field_spec<C>("gauss_markov_current", &C::gauss_markov_current,
                    "The Gauss-Markov current (a GaussMarkovCurrentConfig), used with "
                    "current_model gauss_markov."),
      field_spec<C>("waves", &C::waves, "A WaveConfig, or None for a calm sea."),
      field_spec<C>("payload", &C::payload,
                    "Payload events in non-decreasing time (a tuple; assign a list)."),
      field_spec<C>("control_delay", &C::control_delay,
                    "Control periods between a measurement and the force computed from it "
                    "acting, 0..16 (0: in the same period)."),
      field_spec<C>("water_density", &C::water_density, "kg/m^3", Check::positive,
                    "Sea water by default; a vehicle file's displaced volume gives its buoyancy "
                    "as buoyancy_in_water(water_density, volume)"),
      field_spec<C>("sensors", &C::sensors, "The sensors (a SensorsConfig); none: ideal sensing."),
      field_spec<C>("estimator", &C::estimator, "The estimator (an EstimatorConfig)."),
      field_spec<C>("tether", &C::tether, "A TetherConfig, or None: no tether."),
      field_spec<C>("steady_force", &C::steady_force, "A SteadyForceConfig, or None: no steady force."));
}

/// The disturbance parts of a run (sim/disturbances/part.hpp), each hook
/// called on them in this order; a new source of force or flow is a part
/// here and its fields in SimulationConfig.
template <typename Scalar>
using DisturbanceParts =
    parts::PartList<Scalar, parts::Sinusoids, parts::SteadyCurrent, parts::GaussMarkovFlow,
                    parts::SeaWaves, parts::PayloadEvents, parts::ThrusterFailures,
                    parts::Tether, parts::SteadyForce>;

/// B = rho g V [N]: the buoyancy of `displaced_volume` [m^3] in water of
/// `water_density` [kg/m^3] (g = standard_gravity). Both must be > 0 and
/// finite (the error names the field); `buoyancy` is untouched on error.
template <typename Scalar>
inline ValidationError buoyancy_in_water(Scalar water_density, Scalar displaced_volume,
                                         Scalar& buoyancy) noexcept {
  if (auto e = detail::check_positive_scalar("water_density", static_cast<double>(water_density)))
    return e;
  if (auto e = detail::check_positive_scalar("displaced_volume",
                                             static_cast<double>(displaced_volume)))
    return e;
  buoyancy = water_density * static_cast<Scalar>(standard_gravity) * displaced_volume;
  return {};
}

/// Checks every field a run needs (allocates: the thrusters' pseudo-inverse is
/// computed to know that it exists); the first error names the field.
template <typename Scalar>
inline ValidationError validate(const SimulationConfig<Scalar>& c) {
  if (auto e = detail::check_step("dt", static_cast<double>(c.dt))) return e;
  if (c.substeps < 1 || c.substeps > kMaxSubsteps)
    return detail::invalid("substeps", -1, static_cast<double>(c.substeps),
                           "a whole number in 1..10000 (neurov::kMaxSubsteps)");
  if (auto e = detail::check_positive_scalar("duration", static_cast<double>(c.duration))) return e;
  // A run has at most 1e8 control steps. The field named is the one that can
  // be fixed: dt (raise it) unless no step up to kMaxStep brings the duration
  // within the limit (a dt of 5e-324 is dt's fault, not a 250 s duration's).
  if (c.duration / c.dt > Scalar(1e8)) {
    if (static_cast<double>(c.duration) > 1e8 * kMaxStep)
      return detail::invalid("duration", -1, static_cast<double>(c.duration),
                             "at most 1e9 s (1e8 control steps of the largest dt, 10 s)");
    return detail::invalid("dt", -1, static_cast<double>(c.dt),
                           ">= duration / 1e8 (a run has at most 1e8 control steps)");
  }
  if (c.control_delay < 0 || c.control_delay > kMaxControlDelay)
    return detail::invalid("control_delay", -1, static_cast<double>(c.control_delay),
                           "a whole number of control periods in 0..16");
  if (auto e = detail::check_positive_scalar("water_density", static_cast<double>(c.water_density)))
    return e;
  if (auto e = detail::check_finite("eta0", c.eta0)) return e;
  if (auto e = detail::check_finite("nu0", c.nu0)) return e;
  if (c.command.times.size() < 1)
    return detail::invalid("command.times", -1, 0.0, "at least one commanded pose");
  if (c.command.poses.rows() != c.command.times.size())
    return detail::invalid("command.poses", -1, static_cast<double>(c.command.poses.rows()),
                           "one pose per time");
  if (auto e = detail::check_finite("command.times", c.command.times)) return e;
  if (auto e = detail::check_finite("command.poses", c.command.poses)) return e;
  for (Eigen::Index i = 1; i < c.command.times.size(); ++i)
    if (!(c.command.times(i) > c.command.times(i - 1)))
      return detail::invalid("command.times", static_cast<int>(i),
                             static_cast<double>(c.command.times(i)), "strictly increasing");
  if (auto e = detail::check_positive("lambda_d", c.lambda_d)) return e;
  if (auto e = detail::check_positive("omega", c.omega)) return e;
  if (auto e = DisturbanceParts<Scalar>::validate(c)) return e;
  if (auto e = detail::check_non_negative("noise_eta", c.noise_eta)) return e;
  if (auto e = detail::check_non_negative("noise_nu", c.noise_nu)) return e;
  if (auto e = Sensing<Scalar>::validate(c.sensors, c.estimator)) return e;
  if (c.sensors.any() && !(c.noise_eta.isZero(Scalar(0)) && c.noise_nu.isZero(Scalar(0))))
    return detail::invalid("noise_eta", -1, static_cast<double>(c.noise_eta.norm() + c.noise_nu.norm()),
                           "zero noise_eta and noise_nu with sensors (their own noise replaces it)");
  for (std::size_t i = 0; i < c.sensor_faults.size(); ++i) {
    const auto& f = c.sensor_faults[i];
    if (!(std::isfinite(f.start) && std::isfinite(f.end) && f.end >= f.start))
      return detail::invalid("sensor_faults.end", static_cast<int>(i), static_cast<double>(f.end),
                             "finite start <= end");
    if (static_cast<int>(f.kind) > 2)
      return detail::invalid("sensor_faults.kind", static_cast<int>(i),
                             static_cast<double>(f.kind), "freeze, dropout or noise_burst");
    if (auto e = detail::check_non_negative("sensor_faults.noise_eta", f.noise_eta)) return e;
    if (auto e = detail::check_non_negative("sensor_faults.noise_nu", f.noise_nu)) return e;
  }
  // The reference model's and the thrusters' own rules, so that a
  // configuration that passes here is one a Simulator can be created from.
  ReferenceModel<Scalar> reference;
  if (auto e = ReferenceModel<Scalar>::create(c.lambda_d, c.omega, c.eta0, reference)) return e;
  if (c.use_thrusters) {
    Thrusters<Scalar> thrusters;
    if (auto e = Thrusters<Scalar>::create(c.thrusters, thrusters)) return e;
  }
  return {};
}

/// Checks the payload events in their order against the vehicle each one
/// changes (the first against `vehicle`); the error names "payload.<field>"
/// and the event's index.
template <typename Scalar>
inline ValidationError validate_payload(const std::vector<PayloadEvent<Scalar>>& events,
                                        const Vehicle<Scalar>& vehicle) noexcept {
  Vehicle<Scalar> v = vehicle;
  for (std::size_t i = 0; i < events.size(); ++i) {
    Vehicle<Scalar> next;
    ValidationError e = apply_payload(events[i], v, next);
    if (e) {
      // The event's own fields get the prefix; the changed vehicle's keep
      // their names (inertia, mass_matrix) with "payload" as the field.
      static constexpr const char* own[][2] = {
          {"time", "payload.time"},
          {"mass", "payload.mass"},
          {"mass_position", "payload.mass_position"},
          {"buoyancy", "payload.buoyancy"},
          {"buoyancy_position", "payload.buoyancy_position"},
          {"damping_scale", "payload.damping_scale"},
          {"added_mass_scale", "payload.added_mass_scale"}};
      // Compared up to the first difference or the end of either name: a
      // fixed-length compare would read past the end of a shorter field name.
      auto same = [](const char* a, const char* b) noexcept {
        while (*a != '\0' && *a == *b) ++a, ++b;
        return *a == *b;
      };
      const char* field = "payload";
      for (const auto& n : own)
        if (same(e.field, n[0])) field = n[1];
      return detail::invalid(field, static_cast<int>(i), e.value, e.expected);
    }
    v = next;
  }
  return {};
}

}  // namespace neurov
