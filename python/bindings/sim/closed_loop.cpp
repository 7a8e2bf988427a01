// neurov/sim/closed_loop.hpp in Python: a whole run with a built-in controller
// in one call, the GIL released.
#include <pybind11/pybind11.h>
#include <pybind11/typing.h>

#include <string>
#include <utility>

#include "bindings.hpp"
#include "numpy_args.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "neurov/sim/closed_loop.hpp"
#include "result.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

template <typename Controller>
typed::SimulationResultDict run(const Vehicle<double>& vehicle, Controller& controller,
             const SimulationConfig<double>& config) {
  SimulationResult<double> result;
  ValidationError e;
  {
    // The loop touches no Python object: other threads may run meanwhile.
    py::gil_scoped_release release;
    e = simulate(vehicle, controller, config, result);
  }
  py_args::raise_if_invalid(e, "SimulationConfig");
  return result_dict(std::move(result));
}

/// The docstring names the series from the one table (neurov/sim/result.hpp).
const char* run_doc() {
  static const std::string doc =
      "Runs a closed loop in C++ with the configuration `config` (a SimulationConfig) and "
      "returns a dict of arrays (rows at t_k = k dt), one per entry of RESULT_SERIES (" +
      result_series_names() +
      "), and diverged (bool). The controller is used as given and left in its final state. A "
      "bad configuration raises ValueError naming the field. neurov.simulate(scenario) is the "
      "friendly front end.";
  return doc.c_str();
}

/// The loop runs without the GIL; it is taken back only to hand a chunk to
/// `on_rows`, whose exception ends the run and propagates.
template <typename Controller>
void run_chunks(const Vehicle<double>& vehicle, Controller& controller,
                const SimulationConfig<double>& config, Eigen::Index chunk_rows,
                const py::typing::Callable<void(typed::SimulationResultDict)>& on_rows) {
  ValidationError e;
  {
    py::gil_scoped_release release;
    e = simulate_in_chunks(vehicle, controller, config, chunk_rows,
                           [&on_rows](const SimulationResult<double>& chunk) {
                             py::gil_scoped_acquire acquire;
                             on_rows(result_dict(chunk));
                           });
  }
  py_args::raise_if_invalid(e, "run_closed_loop_chunks");
}

constexpr const char* kChunksDoc =
    "The run of run_closed_loop with its rows handed over in chunks: on_rows(dict) is "
    "called with each chunk of at most chunk_rows rows, in time order (the dict of "
    "run_closed_loop; the last chunk's 'diverged' says how the run ended), so a run of any "
    "length holds one chunk in memory. A bad configuration or chunk_rows < 1 raises "
    "ValueError before any step; an exception raised by on_rows ends the run and propagates.";

template <typename Controller>
void def_run(py::module_& m) {
  m.def("run_closed_loop", &run<Controller>, py::arg("vehicle"), py::arg("controller"),
        py::arg("config"), run_doc());
  m.def("run_closed_loop_chunks", &run_chunks<Controller>, py::arg("vehicle"),
        py::arg("controller"), py::arg("config"), py::arg("chunk_rows"), py::arg("on_rows"),
        kChunksDoc);
}

}  // namespace

void bind_closed_loop(py::module_& m) {
  // One overload per built-in controller: pybind11 picks it by the
  // controller's class.
  for_each_type(BuiltInControllers<double>{},
                [&m](auto tag) { def_run<typename decltype(tag)::type>(m); });
}

}  // namespace neurov::bindings
