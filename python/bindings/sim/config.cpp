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

void bind_sim_config(py::module_& m) {
  py::enum_<SensorFaultKind>(m, "SensorFaultKind", "What a sensor fault does to a measurement.")
      .value("freeze", SensorFaultKind::freeze, "Repeats the last measurement delivered.")
      .value("dropout", SensorFaultKind::dropout, "NaN, which the controller refuses.")
      .value("noise_burst", SensorFaultKind::noise_burst, "Extra white noise.");
  py::enum_<RefusedStepPolicy>(m, "RefusedStepPolicy",
                               "The force applied when the controller refuses a step.")
      .value("zero", RefusedStepPolicy::zero, "No force.")
      .value("hold", RefusedStepPolicy::hold, "The last force the controller accepted.");

  {
    using T = SinusoidalDisturbance<double>;
    py::class_<T> cls(m, "SinusoidalDisturbance",
                      "A force or moment in one body DOF: amplitude * sin(2 pi frequency "
                      "(t - start) + phase) for t >= start.");
    Fields<T>(cls, "SinusoidalDisturbance")
        .value("dof", &T::dof, "0..5: surge, sway, heave, roll, pitch, yaw.")
        .value("amplitude", &T::amplitude, "[N] or [N m].")
        .value("frequency", &T::frequency, "[Hz].")
        .value("phase", &T::phase, "[rad].")
        .value("start", &T::start, "[s].")
        .finish();
  }
  {
    using T = ThrusterFailure<double>;
    py::class_<T> cls(m, "ThrusterFailure",
                      "Thruster `index` works at `efficiency` (0: failed) from `time` on.");
    Fields<T>(cls, "ThrusterFailure")
        .value("index", &T::index, "The thruster (a column of the thruster matrix).")
        .value("efficiency", &T::efficiency, "In [0, 1].")
        .value("time", &T::time, "[s].")
        .finish();
  }
  {
    using T = SensorFault<double>;
    py::class_<T> cls(m, "SensorFault",
                      "A sensor fault over [start, end): the measurement of eta and/or nu "
                      "freezes, drops out (NaN) or gets extra white noise.");
    Fields<T>(cls, "SensorFault")
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
    py::class_<T> cls(m, "CurrentStep", "From `time` on, the mean current is `velocity`.");
    Fields<T>(cls, "CurrentStep")
        .value("time", &T::time, "[s].")
        .vector("velocity", &T::velocity, "NED [m/s] (3,).")
        .finish();
  }
  {
    using T = Command<double>;
    py::class_<T> cls(m, "Command",
                      "Commanded poses at increasing times; held before the first and after "
                      "the last; between them linear or held.");
    Fields<T>(cls, "Command")
        .dynamic_vector("times", &T::times, "(K,) strictly increasing [s].")
        .dynamic_matrix("poses", &T::poses, -1, 6, "(K, 6) poses eta.")
        .value("linear", &T::linear, "Linear between the poses; False: piecewise constant.")
        .finish();
    cls.def("at", &T::at, py::arg("t"), "The commanded pose at time t.");
  }
  {
    using T = SimulationConfig<double>;
    py::class_<T> cls(m, "SimulationConfig",
                      "Everything of a closed-loop run but the vehicle and the controller. "
                      "Rows of a run are at t_k = k dt; the force is held over each control "
                      "period and the plant integrated by RK4 at dt / substeps.");
    Fields<T>(cls, "SimulationConfig")
        .value("dt", &T::dt, "Control period [s].")
        .value("substeps", &T::substeps, "RK4 steps per control period.")
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
        .value("seed", &T::seed, "Seed of the measurement noise.")
        .value("use_thrusters", &T::use_thrusters,
               "Allocate the force to `thrusters`; False: the force acts directly.")
        .value("thrusters", &T::thrusters, "The thruster layout (a ThrusterConfig).")
        .list("failures", &T::failures, "ThrusterFailure",
              "Thruster failures (a tuple; assign a list).")
        .list("sensor_faults", &T::sensor_faults, "SensorFault",
              "Sensor faults (a tuple; assign a list).")
        .list("current_steps", &T::current_steps, "CurrentStep",
              "Steps of the mean current, in increasing time (a tuple; assign a list).")
        .value("refused_step_policy", &T::refused_step_policy,
               "The force applied on a refused step (a RefusedStepPolicy).")
        .validator("SimulationConfig")
        .finish();
  }
}

}  // namespace neurov::bindings
