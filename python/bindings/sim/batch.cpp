// neurov/sim/batch.hpp in Python: K runs stepped in lockstep from Python with
// one call per step for all lanes (BatchSimulator), and K built-in closed
// loops run to the end over threads (run_batch). The GIL is released while
// C++ steps; no Python runs per lane. Also the metric sums of a run
// (sim/window_sums.hpp's RunSums), which a Python Result's rows go through.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "numpy_args.hpp"
#include "neurov/sim/batch.hpp"
#include "result.hpp"
#include "typed_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

using Batch = BatchSimulator<double>;
using Controller = AnyBuiltInController<double>;

/// Raises neurov._core.ValidationError (a NeurovError) for a bad argument:
/// its `field` is the argument's name.
[[noreturn]] void bad_argument(const std::string& where, const std::string& name,
                               const std::string& expected, const std::string& got) {
  py::object cls = py::module_::import("neurov._core").attr("ValidationError");
  py::object exc = cls(where + ": argument '" + name + "' must be " + expected + ", got " + got);
  exc.attr("field") = py::str(name);
  exc.attr("index") = -1;
  exc.attr("value") = py::none();
  exc.attr("expected") = py::str(expected);
  PyErr_SetObject(cls.ptr(), exc.ptr());
  throw py::error_already_set();
}

/// A list (any sequence, not a str), each item what convert(item) makes of
/// it; an empty std::optional refuses the item, which must be `one`.
template <typename Convert>
auto items(const py::handle& seq, const char* where, const char* name, const std::string& list,
           const std::string& one, Convert&& convert) {
  if (!py::isinstance<py::sequence>(seq) || py::isinstance<py::str>(seq))
    bad_argument(where, name, list, py_args::type_name(seq));
  const py::sequence s = py::reinterpret_borrow<py::sequence>(seq);
  std::vector<typename decltype(convert(py::object()))::value_type> out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const py::object item = s[i];
    auto converted = convert(item);
    if (!converted) bad_argument(where, std::string(name) + "[" + std::to_string(i) + "]", one, py_args::type_name(item));
    out.push_back(std::move(*converted));
  }
  return out;
}

/// A list of objects of the bound type T (`what`: its Python name), copied.
template <typename T>
std::vector<T> items(const py::handle& seq, const char* where, const char* name, const char* what) {
  return items(seq, where, name, std::string("a list of ") + what, std::string("a ") + what,
               [](const py::object& item) {
                 return py::isinstance<T>(item) ? std::optional<T>(item.cast<const T&>()) : std::nullopt;
               });
}

/// A numpy array of `dtype` (real numbers, bools, integers >= 0) of `shape`
/// (py_args::numpy_array), refused with a ValidationError naming it.
template <typename T>
py::array_t<T, py::array::c_style> checked_array(const py::handle& obj, const char* where, const char* name,
                                                  std::initializer_list<py::ssize_t> shape, const char* dtype) {
  const auto dims = shape.begin();
  const std::string expected = std::string("a numpy array of ") + dtype + " of shape " +
                               py_args::shape_string(dims[0], shape.size() == 1 ? -1 : dims[1]);
  return py_args::numpy_array<T>(
      obj, shape, [&](py_args::Refusal, const std::string& got) { bad_argument(where, name, expected, got); });
}

/// The lanes' mask: a (K,) bool array, or none (None: every lane).
py::array_t<bool, py::array::c_style> mask_array(const Batch& b, const py::handle& mask, const char* where) {
  if (mask.is_none()) return {};
  return checked_array<bool>(mask, where, "mask", {static_cast<py::ssize_t>(b.size())}, "bool");
}

std::size_t lane_index(const Batch& b, const py::handle& i, const char* where) {
  const auto k = py_args::integer<long long>(i, std::string(where) + ": argument 'i'");
  if (k < 0 || k >= static_cast<long long>(b.size()))
    bad_argument(where, "i", "a lane index in [0, " + std::to_string(b.size()) + ")",
                 std::to_string(k));
  return static_cast<std::size_t>(k);
}

using Readout = LaneReadout<double>;

/// A (K,) array, or (K, width), that `field` of `r` points at.
template <typename T>
py::array_t<T> stacked(const Batch& b, Readout& r, T* Readout::*field, py::ssize_t width = 1) {
  const auto k = static_cast<py::ssize_t>(b.size());
  py::array_t<T> out(width == 1 ? std::vector<py::ssize_t>{k} : std::vector<py::ssize_t>{k, width});
  r.*field = out.mutable_data();
  return out;
}

/// One field of every lane.
template <typename T>
py::array_t<T> lane_values(const Batch& b, T* Readout::*field, py::ssize_t width = 1) {
  Readout r;
  auto out = stacked(b, r, field, width);
  r.read(b);
  return out;
}

py::dict observation(const Batch& b) {
  Readout r;
  py::dict d;
  d["t"] = stacked(b, r, &Readout::t);
  for (const auto& [name, field] : {std::pair{"eta", &Readout::eta}, std::pair{"nu", &Readout::nu},
                                    std::pair{"eta_d", &Readout::eta_d}, std::pair{"eta_d_dot", &Readout::eta_d_dot},
                                    std::pair{"eta_d_ddot", &Readout::eta_d_ddot}})
    d[name] = stacked(b, r, field, 6);
  d["faults"] = stacked(b, r, &Readout::faults);
  r.read(b);
  return d;
}

/// "<where>: configs[i]: <the validator's message>" for a lane refused at creation.
std::string lane_what(const char* where, std::size_t lane) {
  return std::string(where) + ": lane " + std::to_string(lane) + " (vehicles[" + std::to_string(lane) +
         "], configs[" + std::to_string(lane) + "])";
}

Batch make_batch(const typed::IterableOf<Vehicle<double>>& vehicles_in,
                 const typed::IterableOf<SimulationConfig<double>>& configs_in, int logged_parameters,
                 Eigen::Index log_rows) {
  const char* where = "BatchSimulator";
  auto vehicles = items<Vehicle<double>>(vehicles_in, where, "vehicles", "neurov.Vehicle");
  auto configs = items<SimulationConfig<double>>(configs_in, where, "configs", "neurov.SimulationConfig");
  if (vehicles.size() != configs.size())
    bad_argument(where, "configs", "one configuration per vehicle (" + std::to_string(vehicles.size()) + ")",
                 std::to_string(configs.size()));
  Batch b;
  std::size_t lane = 0;
  const ValidationError e = Batch::create(vehicles, configs, b, logged_parameters, log_rows, &lane);
  if (e) py_args::raise_if_invalid(e, lane_what(where, lane).c_str());
  return b;
}

py::array_t<std::uint8_t> step(Batch& b, const typed::ArrayLike& tau_in,
                               const typed::OptionalArrayLike& mask_in,
                               const typed::OptionalArrayLike& parameters_in, unsigned threads) {
  const char* where = "BatchSimulator.step";
  const auto k = static_cast<py::ssize_t>(b.size());
  const auto tau = checked_array<double>(tau_in, where, "tau", {k, 6}, "float64");
  const auto mask_in_lanes = mask_array(b, mask_in, where);
  const bool* mask = mask_in.is_none() ? nullptr : mask_in_lanes.data();
  py::array_t<double, py::array::c_style> parameters;  // read only when the batch logs some
  if (b.logged_parameters() > 0) {
    if (parameters_in.is_none())
      bad_argument(where, "parameters",
                   "an array of shape (" + std::to_string(k) + ", " + std::to_string(b.logged_parameters()) +
                       ") (the batch logs that many parameters per row)",
                   "None");
    parameters = checked_array<double>(parameters_in, where, "parameters", {k, b.logged_parameters()}, "float64");
  } else if (!parameters_in.is_none()) {
    bad_argument(where, "parameters", "None (the batch logs no parameters)", py_args::type_name(parameters_in));
  }
  py::array_t<std::uint8_t> statuses(std::vector<py::ssize_t>{k});
  std::uint8_t* out = statuses.mutable_data();
  {
    py::gil_scoped_release release;
    step_threaded(b, threads, tau.data(), mask, out, b.logged_parameters() > 0 ? parameters.data() : nullptr,
                  shared_pool(threads));
  }
  return statuses;
}

void reset(Batch& b, const typed::ArrayLike& seeds_in, const typed::OptionalArrayLike& mask_in) {
  const char* where = "BatchSimulator.reset";
  const auto seeds = checked_array<std::uint64_t>(seeds_in, where, "seeds",
                                                  {static_cast<py::ssize_t>(b.size())}, "uint64");
  const auto mask = mask_array(b, mask_in, where);
  py::gil_scoped_release release;
  b.reset(seeds.data(), mask_in.is_none() ? nullptr : mask.data());
}

/// The controllers as given, copied into the lanes (the objects passed are
/// not changed).
std::vector<Controller> controllers_of(const py::handle& seq) {
  return items(seq, "run_batch", "controllers", "a list of built-in controllers",
               "a built-in controller (neurov.BUILT_IN_CONTROLLERS; a Python controller runs "
               "through neurov.simulate_many)",
               [](const py::object& item) {
                 std::optional<Controller> out;
                 for_each_type(BuiltInControllers<double>{}, [&](auto tag) {
                   using C = typename decltype(tag)::type;
                   if (!out && py::isinstance<C>(item)) out.emplace(std::in_place_type<C>, item.cast<const C&>());
                 });
                 return out;
               });
}

std::vector<double> after_of(const py::handle& after, std::size_t k) {
  if (after.is_none())
    bad_argument("run_batch", "after", "the metrics window's start [s] (a float or one per run) with metrics_only",
                 "None");
  std::vector<double> out;
  if (py::isinstance<py::array>(after) && py::reinterpret_borrow<py::array>(after).ndim() > 0) {
    const auto a = checked_array<double>(after, "run_batch", "after", {static_cast<py::ssize_t>(k)}, "float64");
    out.assign(a.data(), a.data() + k);
  } else if (py::isinstance<py::sequence>(after)) {
    const py::sequence s = py::reinterpret_borrow<py::sequence>(after);
    if (s.size() != k)
      bad_argument("run_batch", "after", "a float or one per run (" + std::to_string(k) + ")",
                   std::to_string(s.size()) + " values");
    for (std::size_t i = 0; i < k; ++i) out.push_back(py_args::scalar(s[i], "after"));
  } else {
    out.assign(k, py_args::scalar(after, "after"));
  }
  return out;
}

/// A run's sums as Python values: a dict for each WindowSums, a (6,) array
/// for a sum per DOF, a tuple or None for first_refused.
template <typename T>
py::object sums_value(const T& v) {
  if constexpr (std::is_same_v<T, WindowSums>) {
    py::dict d;
    v.visit([&d](const WindowSumSpec& spec, const auto& sum) { d[spec.name] = sums_value(sum); });
    return std::move(d);
  } else {
    return py::cast(v);
  }
}

typed::AnyDict run_sums_dict(const RunSums& s) {
  typed::AnyDict d;
  s.visit([&d](const char* name, const auto& v) { d[name] = sums_value(v); });
  return d;
}

py::list run(const typed::IterableOf<Vehicle<double>>& vehicles_in,
             const typed::IterableOf<Controller>& controllers_in,
             const typed::IterableOf<SimulationConfig<double>>& configs_in, unsigned threads,
             bool metrics_only, const typed::Arg<typed::names::OrNone<typed::names::RealOrArrayLike>>& after) {
  const char* where = "run_batch";
  auto vehicles = items<Vehicle<double>>(vehicles_in, where, "vehicles", "neurov.Vehicle");
  auto configs = items<SimulationConfig<double>>(configs_in, where, "configs", "neurov.SimulationConfig");
  auto controllers = controllers_of(controllers_in);
  if (controllers.size() != vehicles.size())
    bad_argument(where, "controllers", "one per vehicle (" + std::to_string(vehicles.size()) + ")",
                 std::to_string(controllers.size()));
  if (configs.size() != vehicles.size())
    bad_argument(where, "configs", "one per vehicle (" + std::to_string(vehicles.size()) + ")",
                 std::to_string(configs.size()));
  BatchOptions options;
  options.threads = threads;
  options.metrics_only = metrics_only;
  if (metrics_only) options.after = after_of(after, vehicles.size());
  std::vector<SimulationResult<double>> results;
  std::vector<RunSums> sums;
  std::size_t lane = 0;
  ValidationError e;
  {
    py::gil_scoped_release release;
    e = run_batch(vehicles, controllers, configs, options, &results, &sums, &lane);
  }
  if (e) py_args::raise_if_invalid(e, lane_what(where, lane).c_str());
  py::list out;
  if (metrics_only) {
    for (const RunSums& s : sums) out.append(run_sums_dict(s));
  } else {
    for (SimulationResult<double>& r : results) out.append(result_dict(std::move(r)));
  }
  return out;
}

}  // namespace

void bind_batch(py::module_& m) {
  py::list sums;
  for (const WindowSumSpec& s : kWindowSums) sums.append(py::make_tuple(s.name, s.width, s.description));
  m.attr("WINDOW_SUMS") = py::tuple(sums);
  using Rows6 = Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>>;
  using Column = Eigen::Ref<const Eigen::VectorXd>;
  py::class_<RunSums>(m, "RunSums",
                      "A run's metric sums (WINDOW_SUMS before and from `after` on, and what the metrics "
                      "read over every row), added row by row as run_batch's metrics_only adds them.")
      .def(py::init([](double after) {
             RunSums s;
             s.after = after;
             return s;
           }),
           py::arg("after"))
      .def(
          "add",
          [](RunSums& s, const Column& t, const Rows6& eta, const Rows6& eta_d, const Rows6& tau_demanded,
             const Eigen::Ref<const Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>>& controller_status,
             const Column& adaptive_norm, bool diverged) {
            const std::pair<const char*, Eigen::Index> lengths[] = {
                {"eta", eta.rows()}, {"eta_d", eta_d.rows()}, {"tau_demanded", tau_demanded.rows()},
                {"controller_status", controller_status.rows()}, {"adaptive_norm", adaptive_norm.rows()}};
            for (const auto& [name, rows] : lengths)
              if (rows != t.rows())
                throw py::value_error(std::string("RunSums.add: argument '") + name + "' must have " +
                                      std::to_string(t.rows()) + " rows (one per t), got " + std::to_string(rows));
            s.add_rows(t, eta, eta_d, tau_demanded, controller_status, adaptive_norm, t.rows(), diverged);
          },
          py::arg("t"), py::arg("eta"), py::arg("eta_d"), py::arg("tau_demanded"), py::arg("controller_status"),
          py::arg("adaptive_norm"), py::arg("diverged"),
          "Adds a run's next rows (t (n,), eta, eta_d, tau_demanded (n, 6), controller_status (n,), "
          "adaptive_norm (n,)), in time order, and whether the run diverged.")
      .def("as_dict", &run_sums_dict, "The sums as run_batch's metrics_only gives them.");
  m.attr("LANE_NOT_STEPPED") = py::int_(kLaneNotStepped);
  m.attr("MIN_LANES_PER_THREAD") = py::int_(kMinLanesPerThread);

  py::class_<Batch>(m, "BatchSimulator",
                    "K runs (lanes) stepped in lockstep from outside, one call per step for every "
                    "lane; each lane gives the rows of the same run alone (a Simulator).")
      .def(py::init(&make_batch), py::arg("vehicles"), py::arg("configs"), py::arg("logged_parameters") = 0,
           py::arg("log_rows") = 0,
           "Lane i from vehicles[i] (a Vehicle) and configs[i] (a SimulationConfig), each copied. "
           "log_rows: the rows each lane's log holds (0, the default: every row of the run; n > 0: a "
           "window of n rows, which TrackingTask.step_batch empties as it steps, so that a vector "
           "environment holds the lanes' state and not a run's rows per lane). "
           "A refused lane raises ValidationError naming the lane and the field.")
      .def_property_readonly("log_rows", &Batch::log_rows,
                             "Rows each lane's log holds: 0 for every row of a run, else the window.")
      .def_property_readonly("size", &Batch::size, "K, the number of lanes.")
      .def_property_readonly("logged_parameters", &Batch::logged_parameters,
                             "Parameters each lane logs per row (step's `parameters` width).")
      .def_property_readonly("observation", &observation,
                             "What the controllers are to be given, stacked over the lanes: a dict of "
                             "t (K,), eta, nu, eta_d, eta_d_dot, eta_d_ddot (K, 6) and faults (K,) uint8 "
                             "(Simulator.observation's fields and Simulator.faults). A done lane keeps "
                             "its last observation.")
      .def_property_readonly(
          "state",
          [](const Batch& b) {
            return py::make_tuple(lane_values(b, &Readout::eta_true, 6), lane_values(b, &Readout::nu_true, 6));
          },
          "The true (eta, nu), each (K, 6).")
      .def("step", &step, py::arg("tau"), py::arg("mask") = py::none(), py::arg("parameters") = py::none(),
           py::arg("threads") = 1u,
           "Steps every lane whose mask is True (None: every lane) and that is not done with the force "
           "tau[i] (tau: (K, 6) float64) and, if the batch logs parameters, parameters[i] "
           "(K, logged_parameters). Returns the (K,) uint8 plant statuses (neurov.Status values; "
           "non_finite_input for a lane given a non-finite force, which is not stepped) and "
           "LANE_NOT_STEPPED (255) for a lane masked out or done. The GIL is released. threads: the lanes "
           "split over that many threads (0: one per hardware thread; at least MIN_LANES_PER_THREAD lanes a "
           "thread, so "
           "fewer threads for a small batch); the results are the same.")
      .def_property_readonly("done", [](const Batch& b) { return lane_values(b, &Readout::done); },
                             "(K,) bool: the lane's run is over (every row, or diverged).")
      .def_property_readonly("diverged", [](const Batch& b) { return lane_values(b, &Readout::diverged); },
                             "(K,) bool: the lane's plant diverged (its last row is where).")
      .def_property_readonly("steps", [](const Batch& b) { return lane_values(b, &Readout::steps); },
                             "(K,) int64: rows logged so far per lane.")
      .def_property_readonly("planned_steps", [](const Batch& b) { return lane_values(b, &Readout::planned_steps); },
                             "(K,) int64: rows of a whole run per lane.")
      .def("reset", &reset, py::arg("seeds"), py::arg("mask") = py::none(),
           "Lanes whose mask is True (None: every lane) back to t = 0 with noise from seeds[i] "
           "(seeds: (K,) uint64, or any integer dtype >= 0).")
      .def(
          "replace",
          [](Batch& b, const typed::Index& i, const Vehicle<double>& vehicle, const SimulationConfig<double>& config) {
            const char* where = "BatchSimulator.replace";
            py_args::raise_if_invalid(b.replace(lane_index(b, i, where), vehicle, config), where);
          },
          py::arg("i"), py::arg("vehicle"), py::arg("config"),
          "Lane i created again from a new vehicle and configuration, ready at t = 0 (e.g. a new "
          "episode's randomised plant). A refused one raises ValidationError naming the field and "
          "leaves lane i as it was.")
      .def(
          "result",
          [](const Batch& b, const typed::Index& i) {
            return result_dict(b.lane(lane_index(b, i, "BatchSimulator.result")).result());
          },
          py::arg("i"), "Lane i's rows so far, as the dict run_closed_loop returns.");

  m.def("run_batch", &run, py::arg("vehicles"), py::arg("controllers"), py::arg("configs"),
        py::arg("threads") = 0u, py::arg("metrics_only") = false, py::arg("after") = py::none(),
        "Runs K closed loops in C++, lane i vehicles[i] under controllers[i] (any built-in "
        "controllers, types mixed, each copied as given: the objects passed are not changed) with "
        "configs[i], over `threads` threads (0: one per hardware thread), the GIL released. Returns "
        "one dict per run, in order: run_closed_loop's, or with metrics_only no rows but the metric "
        "sums (keys after, before and window (each WINDOW_SUMS), final_adaptive_norm, "
        "max_adaptive_norm, diverged, first_refused), the window being t >= `after` (a float or "
        "one per run). A refused lane raises ValidationError naming the lane and the field before "
        "any run.");
}

}  // namespace neurov::bindings
