// neurov/sim/config.hpp in Python: SimulationConfig<double> and the structs it
// holds, field by field; validate() is the C++ validator.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "fields.hpp"
#include "numpy_args.hpp"
#include "neurov/sim/config.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

/// A sensor's configuration: its rate and latency, the sensor's own fields
/// to follow.
template <typename T>
Fields<T> sensor_fields(py::module_& m, const char* name, const char* doc,
                        const char* latency_doc = "[s], >= 0.") {
  Fields<T> f(m, name, doc);
  f.value("rate", &T::rate, "[Hz], > 0.").value("latency", &T::latency, latency_doc);
  return f;
}

}  // namespace

void bind_sim_config(py::module_& m) {
  m.attr("MAX_SUBSTEPS") = kMaxSubsteps;
  m.attr("MAX_WAVE_COMPONENTS") = kMaxWaveComponents;
  m.def(
      "buoyancy_in_water",
      [](double water_density, double displaced_volume) {
        double b = 0.0;
        py_args::raise_if_invalid(buoyancy_in_water(water_density, displaced_volume, b),
                                  "buoyancy_in_water");
        return b;
      },
      py::arg("water_density"), py::arg("displaced_volume"),
      "B = rho g V [N]: the buoyancy of displaced_volume [m^3] in water of water_density "
      "[kg/m^3]. ValueError naming an argument that is not > 0 and finite.");
  py::enum_<SensorFaultKind>(m, "SensorFaultKind", "What a sensor fault does to a measurement.")
      .value("freeze", SensorFaultKind::freeze, "Repeats the last measurement delivered.")
      .value("dropout", SensorFaultKind::dropout, "NaN, which the controller refuses.")
      .value("noise_burst", SensorFaultKind::noise_burst, "Extra white noise.");
  py::enum_<RefusedStepPolicy>(m, "RefusedStepPolicy",
                               "The force applied when the controller refuses a step.")
      .value("zero", RefusedStepPolicy::zero, "No force.")
      .value("hold", RefusedStepPolicy::hold, "The last force the controller accepted.");
  py::enum_<CurrentModel>(m, "CurrentModel", "The model of the current a run uses.")
      .value("constant", CurrentModel::constant,
             "Mean + sinusoid + steps (current, current_amplitude, current_period, "
             "current_steps).")
      .value("gauss_markov", CurrentModel::gauss_markov,
             "First-order Gauss-Markov speed and direction (gauss_markov_current).");
  py::enum_<WaveSpectrum>(m, "WaveSpectrum", "The spectrum the waves realise.")
      .value("jonswap", WaveSpectrum::jonswap, "JONSWAP (hs, tp, gamma).")
      .value("pierson_moskowitz", WaveSpectrum::pierson_moskowitz,
             "Two-parameter Pierson-Moskowitz (Bretschneider/ITTC: hs, tp).");

  {
    using T = GaussMarkovCurrentConfig<double>;
    Fields<T>(m, "GaussMarkovCurrentConfig",
              "A current whose speed, direction and vertical angle wander about their means as "
              "first-order Gauss-Markov processes (Fossen 2011, 8.3).")
        .value("speed", &T::speed, "Mean speed [m/s], within [speed_min, speed_max].")
        .value("speed_std", &T::speed_std, "Stationary standard deviation [m/s], >= 0.")
        .value("time_constant", &T::time_constant, "Of all three processes [s], > 0.")
        .value("speed_min", &T::speed_min, "Lower bound of the speed given out [m/s], >= 0.")
        .value("speed_max", &T::speed_max, "Upper bound of the speed given out [m/s].")
        .value("direction", &T::direction,
               "Mean direction the current flows toward [deg from north].")
        .value("direction_std", &T::direction_std, "[deg], >= 0.")
        .value("vertical_angle", &T::vertical_angle,
               "Mean angle below the horizontal plane [deg], positive flowing down.")
        .value("vertical_angle_std", &T::vertical_angle_std, "[deg], >= 0.")
        .finish();
  }
  {
    using T = WaveConfig<double>;
    auto cls = Fields<T>(m, "WaveConfig",
                         "Linear deep-water waves realised from a spectrum as a sum of seeded "
                         "components.")
        .value("spectrum", &T::spectrum, "A WaveSpectrum.")
        .value("hs", &T::hs, "Significant wave height [m], > 0.")
        .value("tp", &T::tp, "Peak period [s], > 0.")
        .value("gamma", &T::gamma, "JONSWAP peak enhancement, >= 1.")
        .value("direction", &T::direction,
               "Direction the waves travel toward [deg from north].")
        .value("spreading", &T::spreading, "n of the cos^n directional spreading; 0: long-crested.")
        .value("components", &T::components, "Number of components, 1 to 512.")
        .finish();
    // The target S(omega) drawn beside a run's realised spectrum: the C++
    // density itself, so the plot cannot drift from what the waves realise.
    cls.def(
        "spectral_density",
        [](const T& c, const py::array_t<double, py::array::c_style | py::array::forcecast>& omega) {
          const SpectralDensity density = SpectralDensity::from(c);
          py::array_t<double> out(omega.request().shape);
          const double* w = omega.data();
          double* s = out.mutable_data();
          for (py::ssize_t i = 0; i < omega.size(); ++i) s[i] = density(w[i]);
          return out;
        },
        py::arg("omega"),
        "S(omega) [m^2 s/rad] of this spectrum at the circular frequencies `omega` [rad/s] "
        "(0 for omega <= 0); JONSWAP normalised so that its m0 is hs^2/16.");
  }
  {
    using T = PayloadEvent<double>;
    Fields<T>(m, "PayloadEvent",
              "A change of the vehicle at `time` that the controller is not told about: mass, "
              "buoyancy, damping and added mass.")
        .value("time", &T::time, "When it happens [s], >= 0.")
        .value("mass", &T::mass, "Mass added [kg] (negative: dropped); weight mass * 9.81.")
        .optional("mass_position", &T::mass_position,
                  "Where the mass sits, body axes [m] (3,); None: the centre of gravity.")
        .value("buoyancy", &T::buoyancy, "Buoyancy added [N] (negative: lost).")
        .optional("buoyancy_position", &T::buoyancy_position,
                  "Where it acts, body axes [m] (3,); None: the centre of buoyancy.")
        .vector("damping_scale", &T::damping_scale,
                "Factors on the linear and quadratic damping per DOF (6,).")
        .value("added_mass_scale", &T::added_mass_scale, "Factor on the added-mass matrix.")
        .finish();
  }

  {
    using T = TetherConfig<double>;
    Fields<T>(m, "TetherConfig",
              "A ROV's umbilical from a surface anchor to the vehicle: a quasi-static straight line "
              "whose normal drag, integrated along it, acts half at the vehicle's attachment point.")
        .value("diameter", &T::diameter, "d [m], > 0.")
        .value("drag_coefficient", &T::drag_coefficient, "C_d of the flow normal to the cable, >= 0.")
        .vector("anchor", &T::anchor, "The surface end, NED [m] (3,).")
        .vector("attachment", &T::attachment, "The vehicle end, body axes [m] (3,).")
        .value("length", &T::length,
               "[m]; 0: the straight distance at t = 0, which it may not be shorter than (slack "
               "is not modelled).")
        .finish();
  }

  py::enum_<EstimatorType>(m, "EstimatorType", "What the controller is given from the sensors.")
      .value("none", EstimatorType::none, "Each sensor's latest reading, as it is.")
      .value("ekf", EstimatorType::ekf, "The extended Kalman filter's estimate.");
  {
    using T = UsblConfig<double>;
    sensor_fields<T>(m, "UsblConfig", "An acoustic position fix (USBL-like): NED position.",
                     "[s], >= 0 (acoustic travel and processing).")
        .value("noise", &T::noise, "Standard deviation per axis [m], >= 0.")
        .vector("bias", &T::bias, "NED [m] (3,).")
        .finish();
  }
  {
    using T = DvlConfig<double>;
    sensor_fields<T>(m, "DvlConfig", "A Doppler velocity log: body velocity over ground.")
        .value("noise", &T::noise, "Standard deviation per axis [m/s], >= 0.")
        .value("dropout_rate", &T::dropout_rate,
               "Probability that a sample has no bottom lock, in [0, 1).")
        .vector("bias", &T::bias, "[m/s] (3,).")
        .finish();
  }
  {
    using T = DepthConfig<double>;
    sensor_fields<T>(m, "DepthConfig", "A pressure depth sensor: z, down positive.")
        .value("noise", &T::noise, "Standard deviation [m], >= 0.")
        .value("bias", &T::bias, "[m].")
        .finish();
  }
  {
    using T = ImuConfig<double>;
    sensor_fields<T>(m, "ImuConfig", "An AHRS/IMU: attitude and gyro rates, the gyro's bias walking.")
        .value("attitude_noise", &T::attitude_noise, "Standard deviation of the angles [rad], >= 0.")
        .value("gyro_noise", &T::gyro_noise, "Standard deviation of the rates [rad/s], >= 0.")
        .value("gyro_bias_walk", &T::gyro_bias_walk, "Bias random walk [rad/s/sqrt(s)], >= 0.")
        .vector("gyro_bias", &T::gyro_bias, "Initial gyro bias [rad/s] (3,).")
        .finish();
  }
  {
    using T = SensorsConfig<double>;
    auto cls = Fields<T>(m, "SensorsConfig",
                         "The sensors of a run, each optional; none configured: ideal sensing.")
        .optional("usbl", &T::usbl, "A UsblConfig, or None.")
        .optional("dvl", &T::dvl, "A DvlConfig, or None.")
        .optional("depth", &T::depth, "A DepthConfig, or None.")
        .optional("imu", &T::imu, "An ImuConfig, or None.")
        .finish();
    cls.def("any", &T::any, "Some sensor is configured.");
  }
  {
    using T = EstimatorConfig<double>;
    Fields<T>(m, "EstimatorConfig",
              "What the controller is given from the sensors; the EKF's measurement noises are the "
              "sensors' own.")
        .value("type", &T::type, "An EstimatorType.")
        .value("linear_acceleration_noise", &T::linear_acceleration_noise,
               "sqrt of the PSD of the velocities' random walk [m/s^2/sqrt(Hz)], >= 0.")
        .value("angular_acceleration_noise", &T::angular_acceleration_noise,
               "sqrt of the PSD of the rates' random walk [rad/s^2/sqrt(Hz)], >= 0.")
        .vector("initial_std", &T::initial_std,
                "Standard deviations of the initial estimate (15,): position, angles, body "
                "velocity, rates, gyro bias.")
        .finish();
  }
  {
    using T = SinusoidalDisturbance<double>;
    Fields<T>(m, "SinusoidalDisturbance",
              "A force or moment in one body DOF: amplitude * sin(2 pi frequency (t - start) + "
              "phase) for t >= start.")
        .value("dof", &T::dof, "0..5: surge, sway, heave, roll, pitch, yaw.")
        .value("amplitude", &T::amplitude, "[N] or [N m].")
        .value("frequency", &T::frequency, "[Hz].")
        .value("phase", &T::phase, "[rad].")
        .value("start", &T::start, "[s].")
        .finish();
  }
  {
    using T = ThrusterFailure<double>;
    Fields<T>(m, "ThrusterFailure",
              "Thruster `index` works at `efficiency` (0: failed) from `time` on.")
        .value("index", &T::index, "The thruster (a column of the thruster matrix).")
        .value("efficiency", &T::efficiency, "In [0, 1].")
        .value("time", &T::time, "[s].")
        .finish();
  }
  {
    using T = SensorFault<double>;
    Fields<T>(m, "SensorFault",
              "A sensor fault over [start, end): the measurement of eta and/or nu freezes, drops "
              "out (NaN) or gets extra white noise.")
        .value("kind", &T::kind, "A SensorFaultKind.")
        .value("start", &T::start, "[s].")
        .value("end", &T::end, "[s], >= start.")
        .value("eta", &T::eta, "Affects the pose measurement.")
        .value("nu", &T::nu, "Affects the velocity measurement.")
        .vector("noise_eta", &T::noise_eta, "Standard deviations (6,); noise_burst only.")
        .vector("noise_nu", &T::noise_nu, "Standard deviations (6,); noise_burst only.")
        .finish();
  }
  {
    using T = CurrentStep<double>;
    Fields<T>(m, "CurrentStep",
              "From `time` on, the mean current is `velocity`.")
        .value("time", &T::time, "[s].")
        .vector("velocity", &T::velocity, "NED [m/s] (3,).")
        .finish();
  }
  {
    using T = Command<double>;
    auto cls = Fields<T>(m, "Command",
                         "Commanded poses at increasing times; held before the first and after the "
                         "last; between them linear or held.")
        .dynamic_vector("times", &T::times, "(K,) strictly increasing [s].")
        .dynamic_matrix("poses", &T::poses, -1, 6, "(K, 6) poses eta.")
        .value("linear", &T::linear, "Linear between the poses; False: piecewise constant.")
        .finish();
    cls.def("at", &T::at, py::arg("t"), "The commanded pose at time t.");
  }
  {
    using T = SimulationConfig<double>;
    Fields<T>(m, "SimulationConfig",
              "Everything of a closed-loop run but the vehicle and the controller. Rows of a run "
              "are at t_k = k dt; the force is held over each control period and the plant "
              "integrated by RK4 at dt / substeps.")
        .value("dt", &T::dt, "Control period [s].")
        .value("substeps", &T::substeps, "RK4 steps per control period, 1 to 10000 (MAX_SUBSTEPS).")
        .value("duration", &T::duration, "[s].")
        .vector("eta0", &T::eta0, "Initial pose (6,).")
        .vector("nu0", &T::nu0, "Initial body velocity (6,).")
        .value("command", &T::command, "The commanded path (a Command).")
        .vector("lambda_d", &T::lambda_d, "Reference-model damping (6,).")
        .vector("omega", &T::omega, "Reference-model stiffness (6,).")
        .list("disturbances", &T::disturbances, "SinusoidalDisturbance",
              "Sinusoidal forces (a tuple; assign a list).")
        .vector("current", &T::current, "Mean current, NED [m/s] (3,).")
        .vector("current_amplitude", &T::current_amplitude,
                "Amplitude of the current's sinusoid per axis (3,).")
        .value("current_period", &T::current_period, "[s]; 0 means a constant current.")
        .vector("noise_eta", &T::noise_eta, "Standard deviations of the pose noise (6,).")
        .vector("noise_nu", &T::noise_nu, "Standard deviations of the velocity noise (6,).")
        .value("seed", &T::seed,
               "Seed of the measurement noise; the current's and the waves' streams are "
               "derived from it.")
        .value("use_thrusters", &T::use_thrusters,
               "Allocate the force to `thrusters`; False: the force acts directly.")
        .value("thrusters", &T::thrusters, "The thruster layout (a ThrusterConfig).")
        .list("thruster_failures", &T::thruster_failures, "ThrusterFailure",
              "Thruster failures (a tuple; assign a list).")
        .list("sensor_faults", &T::sensor_faults, "SensorFault",
              "Sensor faults (a tuple; assign a list).")
        .list("current_steps", &T::current_steps, "CurrentStep",
              "Steps of the mean current, in increasing time (a tuple; assign a list).")
        .value("refused_step_policy", &T::refused_step_policy,
               "The force applied on a refused step (a RefusedStepPolicy).")
        .value("current_model", &T::current_model, "A CurrentModel.")
        .value("gauss_markov_current", &T::gauss_markov_current,
               "The Gauss-Markov current (a GaussMarkovCurrentConfig), used with "
               "current_model gauss_markov.")
        .optional("waves", &T::waves, "A WaveConfig, or None for a calm sea.")
        .list("payload", &T::payload, "PayloadEvent",
              "Payload events in non-decreasing time (a tuple; assign a list).")
        .value("control_delay", &T::control_delay,
               "Control periods between a measurement and the force computed from it acting, "
               "0..16 (0: in the same period).")
        .value("water_density", &T::water_density,
               "[kg/m^3], > 0 (sea water by default); a vehicle file's displaced volume gives "
               "its buoyancy as buoyancy_in_water(water_density, volume).")
        .value("sensors", &T::sensors, "The sensors (a SensorsConfig); none: ideal sensing.")
        .value("estimator", &T::estimator, "The estimator (an EstimatorConfig).")
        .optional("tether", &T::tether, "A TetherConfig, or None: no tether.")
        .validator("SimulationConfig")
        .finish();
  }
}

}  // namespace neurov::bindings
