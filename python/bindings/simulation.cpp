#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "neurov/sim/simulation.hpp"
#include "neurov/model/thrusters.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Config = SimulationConfig<double>;
using Result = SimulationResult<double>;

namespace {

template <typename T>
T item(const py::handle& seq_item, const char* key, const std::string& where) {
  try {
    return seq_item[py::str(key)].cast<T>();
  } catch (const py::error_already_set&) {
    throw py::value_error(where + ": missing or invalid key '" + key + "'");
  } catch (const py::cast_error&) {
    throw py::type_error(where + ": key '" + key + "' has the wrong type");
  }
}

/// Every keyword run_closed_loop takes: a misspelt one must not be ignored.
constexpr const char* kKeywords[] = {
    "dt", "substeps", "duration", "eta0", "nu0", "command_times", "command_poses",
    "command_interpolation", "lambda_d", "omega", "disturbances", "current", "current_amplitude",
    "current_period", "noise_eta", "noise_nu", "seed", "sensor_faults", "current_steps",
    "refused_step_policy", "thruster_matrix", "thruster_max", "thruster_min", "thruster_weights",
    "saturation", "thruster_time_constant", "thruster_failures"};

Config parse_config(const py::dict& kw) {
  for (const auto& item : kw) {
    const auto key = py::str(item.first).cast<std::string>();
    bool known = false;
    for (const char* k : kKeywords) known = known || key == k;
    if (!known)
      throw py::type_error("run_closed_loop() got an unexpected keyword argument '" + key + "'");
  }
  Config c;
  auto get = [&](const char* key) -> py::object {
    return kw.contains(key) ? py::object(kw[key]) : py::object(py::none());
  };
  if (!get("dt").is_none()) c.dt = py_args::scalar(get("dt"), "dt");
  if (!get("substeps").is_none()) {
    const py::object s = get("substeps");
    if (!py::isinstance<py::int_>(s) || py::isinstance<py::bool_>(s))
      throw py::type_error("argument 'substeps' must be an int");
    c.substeps = s.cast<int>();
  }
  if (!get("duration").is_none()) c.duration = py_args::scalar(get("duration"), "duration");
  if (!get("eta0").is_none()) c.eta0 = py_args::vector<6>(get("eta0"), "eta0");
  if (!get("nu0").is_none()) c.nu0 = py_args::vector<6>(get("nu0"), "nu0");
  c.command.times = py_args::dynamic_vector(get("command_times"), "command_times", -1);
  c.command.poses = py_args::dynamic_matrix(get("command_poses"), "command_poses",
                                            c.command.times.size(), 6);
  if (!get("command_interpolation").is_none()) {
    c.command.linear =
        py_args::choice(get("command_interpolation"), "command_interpolation", {"linear", "hold"}) ==
        "linear";
  }
  if (!get("lambda_d").is_none()) c.lambda_d = py_args::vector<6>(get("lambda_d"), "lambda_d");
  if (!get("omega").is_none()) c.omega = py_args::vector<6>(get("omega"), "omega");
  if (!get("disturbances").is_none()) {
    int i = 0;
    for (const py::handle d : get("disturbances")) {
      const std::string where = "disturbances[" + std::to_string(i++) + "]";
      SinusoidalDisturbance<double> s;
      s.dof = item<int>(d, "dof", where);
      s.amplitude = item<double>(d, "amplitude", where);
      s.frequency = item<double>(d, "frequency", where);
      s.phase = item<double>(d, "phase", where);
      s.start = item<double>(d, "start", where);
      c.disturbances.push_back(s);
    }
  }
  if (!get("current").is_none()) c.current = py_args::vector<3>(get("current"), "current");
  if (!get("current_amplitude").is_none())
    c.current_amplitude = py_args::vector<3>(get("current_amplitude"), "current_amplitude");
  if (!get("current_period").is_none())
    c.current_period = py_args::scalar(get("current_period"), "current_period");
  if (!get("noise_eta").is_none()) c.noise_eta = py_args::vector<6>(get("noise_eta"), "noise_eta");
  if (!get("noise_nu").is_none()) c.noise_nu = py_args::vector<6>(get("noise_nu"), "noise_nu");
  if (!get("seed").is_none()) {
    const py::object s = get("seed");
    if (!py::isinstance<py::int_>(s) || py::isinstance<py::bool_>(s))
      throw py::type_error("argument 'seed' must be an int");
    const auto v = s.cast<long long>();
    if (v < 0) throw py::value_error("argument 'seed' must be >= 0");
    c.seed = static_cast<std::uint64_t>(v);
  }
  if (!get("sensor_faults").is_none()) {
    int i = 0;
    for (const py::handle f : get("sensor_faults")) {
      const std::string where = "sensor_faults[" + std::to_string(i++) + "]";
      SensorFault<double> sf;
      const auto kind = item<std::string>(f, "kind", where);
      if (kind == "freeze")
        sf.kind = SensorFaultKind::freeze;
      else if (kind == "dropout")
        sf.kind = SensorFaultKind::dropout;
      else if (kind == "noise_burst")
        sf.kind = SensorFaultKind::noise_burst;
      else
        throw py::value_error(where + ": kind must be 'freeze', 'dropout' or 'noise_burst', got '" +
                              kind + "'");
      sf.start = item<double>(f, "start", where);
      sf.end = item<double>(f, "end", where);
      sf.eta = item<bool>(f, "eta", where);
      sf.nu = item<bool>(f, "nu", where);
      sf.noise_eta = py_args::vector<6>(f[py::str("noise_eta")], "noise_eta");
      sf.noise_nu = py_args::vector<6>(f[py::str("noise_nu")], "noise_nu");
      c.sensor_faults.push_back(sf);
    }
  }
  if (!get("current_steps").is_none()) {
    int i = 0;
    for (const py::handle cs : get("current_steps")) {
      const std::string where = "current_steps[" + std::to_string(i++) + "]";
      CurrentStep<double> step;
      step.time = item<double>(cs, "time", where);
      step.velocity = py_args::vector<3>(cs[py::str("velocity")], "velocity");
      c.current_steps.push_back(step);
    }
  }
  if (!get("refused_step_policy").is_none()) {
    c.refused_step_policy =
        py_args::choice(get("refused_step_policy"), "refused_step_policy", {"zero", "hold"}) == "hold"
            ? RefusedStepPolicy::hold
            : RefusedStepPolicy::zero;
  }
  if (!get("thruster_matrix").is_none()) {
    c.use_thrusters = true;
    c.thrusters.matrix = py_args::dynamic_matrix(get("thruster_matrix"), "thruster_matrix", 6, -1);
    const auto n = c.thrusters.matrix.cols();
    c.thrusters.max_thrust = py_args::dynamic_vector(get("thruster_max"), "thruster_max", n);
    c.thrusters.min_thrust = get("thruster_min").is_none()
                                 ? Eigen::VectorXd(-c.thrusters.max_thrust)
                                 : py_args::dynamic_vector(get("thruster_min"), "thruster_min", n);
    if (!get("thruster_weights").is_none())
      c.thrusters.weights = py_args::dynamic_vector(get("thruster_weights"), "thruster_weights", n);
    if (!get("saturation").is_none()) {
      c.thrusters.saturation =
          py_args::choice(get("saturation"), "saturation", {"scale", "clip"}) == "clip"
              ? Saturation::clip
              : Saturation::scale;
    }
    if (!get("thruster_time_constant").is_none())
      c.thrusters.time_constant =
          py_args::scalar(get("thruster_time_constant"), "thruster_time_constant");
    if (!get("thruster_failures").is_none()) {
      int i = 0;
      for (const py::handle f : get("thruster_failures")) {
        const std::string where = "thruster_failures[" + std::to_string(i++) + "]";
        ThrusterFailure<double> tf;
        tf.index = item<int>(f, "index", where);
        tf.efficiency = item<double>(f, "efficiency", where);
        tf.time = item<double>(f, "time", where);
        c.failures.push_back(tf);
      }
    }
  }
  return c;
}

py::dict result_dict(const Result& r) {
  py::dict d;
  d["t"] = r.t;
  d["eta"] = r.eta;
  d["nu"] = r.nu;
  d["eta_d"] = r.eta_d;
  d["eta_d_dot"] = r.eta_d_dot;
  d["tau_demanded"] = r.tau_demanded;
  d["tau_applied"] = r.tau_applied;
  d["disturbance"] = r.disturbance;
  d["s"] = r.s;
  d["thrusts"] = r.thrusts;
  d["theta"] = r.theta;
  d["adaptive_norm"] = r.adaptive_norm;
  d["controller_status"] = r.controller_status;
  d["plant_status"] = r.plant_status;
  d["faults"] = r.faults;
  d["diverged"] = r.diverged;
  return d;
}

template <typename Controller>
py::dict run(const Vehicle<double>& vehicle, Controller& controller, const py::kwargs& kw) {
  const Config config = parse_config(kw);
  Result result;
  ValidationError e;
  {
    // The loop touches no Python object: other threads may run meanwhile.
    py::gil_scoped_release release;
    e = simulate(vehicle, controller, config, result);
  }
  py_args::raise_if_invalid(e, "simulation");
  return result_dict(result);
}

constexpr const char* kDoc =
    "Runs a closed loop in C++ and returns a dict of arrays (rows at t_k = k dt): t, eta, nu, "
    "eta_d, eta_d_dot, tau_demanded, tau_applied, disturbance, s, thrusts, theta, "
    "adaptive_norm, controller_status, plant_status, and diverged (bool). The controller is "
    "used as given and left in its final state. Keyword arguments: dt, substeps, duration, "
    "eta0, nu0, command_times (K,), command_poses (K, 6), command_interpolation "
    "('linear'|'hold'), lambda_d, omega (reference model), disturbances (list of dicts dof, "
    "amplitude, frequency [Hz], phase, start), current, current_amplitude (NED, m/s), "
    "current_period, noise_eta, noise_nu (std devs), seed, thruster_matrix (6, n), "
    "thruster_max, thruster_min, thruster_weights (n,), saturation ('scale'|'clip'), "
    "thruster_time_constant, thruster_failures (list of dicts index, efficiency, time), "
    "sensor_faults (list of dicts kind 'freeze'|'dropout'|'noise_burst', start, end, eta, nu "
    "(bools), noise_eta, noise_nu), current_steps (list of dicts time, velocity), "
    "refused_step_policy ('zero'|'hold'). The result's faults column has bits 1 freeze, 2 "
    "dropout, 4 noise burst, 8 a thruster below full efficiency, 16 the row's eta_d came from a "
    "pitch-limited reference step (command or reference held at +-(pi/2 - 0.2) rad). "
    "neurov.simulate(scenario) is the friendly front end.";

}  // namespace

void bind_simulation(py::module_& m) {
  m.def("run_closed_loop", &run<NNAdaptiveController<double>>, py::arg("vehicle"),
        py::arg("controller"), kDoc);
  m.def("run_closed_loop", &run<LinearAdaptiveController<double>>, py::arg("vehicle"),
        py::arg("controller"), kDoc);
  m.def("run_closed_loop", &run<PDController<double>>, py::arg("vehicle"), py::arg("controller"),
        kDoc);
  m.def("run_closed_loop", &run<PIDController<double>>, py::arg("vehicle"),
        py::arg("controller"), kDoc);
  m.def("run_closed_loop", &run<SlidingModeController<double>>, py::arg("vehicle"),
        py::arg("controller"), kDoc);

  m.def(
      "allocate_thrust",
      [](py::handle matrix, py::handle tau, py::handle max_thrust, py::handle min_thrust,
         py::handle saturation, py::handle weights) {
        ThrusterConfig<double> c;
        c.matrix = py_args::dynamic_matrix(matrix, "matrix", 6, -1);
        const auto n = c.matrix.cols();
        c.max_thrust = max_thrust.is_none()
                           ? Eigen::VectorXd::Constant(n, std::numeric_limits<double>::max())
                           : py_args::dynamic_vector(max_thrust, "max_thrust", n);
        c.min_thrust = min_thrust.is_none() ? Eigen::VectorXd(-c.max_thrust)
                                            : py_args::dynamic_vector(min_thrust, "min_thrust", n);
        if (!weights.is_none()) c.weights = py_args::dynamic_vector(weights, "weights", n);
        c.saturation = py_args::choice(saturation, "saturation", {"scale", "clip"}) == "clip"
                           ? Saturation::clip
                           : Saturation::scale;
        Thrusters<double> t;
        py_args::raise_if_invalid(Thrusters<double>::create(c, t), "thrusters");
        t.command(py_args::vector<6>(tau, "tau"));
        t.advance(1.0);
        return py::make_tuple(Eigen::VectorXd(t.thrust()), Vector6<double>(t.wrench()));
      },
      py::arg("matrix"), py::arg("tau"), py::arg("max_thrust") = py::none(),
      py::arg("min_thrust") = py::none(), py::arg("saturation") = "scale",
      py::arg("weights") = py::none(),
      "Allocates a wrench tau (6,) to thrusters with configuration matrix (6, n) by the "
      "weighted pseudo-inverse and saturates ('scale' keeps the direction, 'clip' clips each). "
      "Returns (thrusts (n,), produced wrench (6,)).");
}

}  // namespace neurov::bindings
