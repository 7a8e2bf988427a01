// neurov._bench, timing helpers for bench/compare.py, built only with
// NEUROV_BUILD_BENCH so the production module carries none of them: a loop of
// steps run inside C++ (on a copy, so the caller's object is untouched, and
// with the GIL released), timed there, so Python can put the per-step cost of
// the C++ loop beside the per-call cost from Python in one run.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "neurov/model/integrator.hpp"
#include "neurov/control/linear_adaptive_controller.hpp"
#include "neurov/control/nn_controller.hpp"
#include "neurov/control/rbf_kernels.hpp"
#include "numpy_args.hpp"

namespace neurov::bench {

namespace py = pybind11;
using Vec6 = Vector6<double>;

namespace {

/// Seconds per step of `steps` steps, the best of `repeats` loops; the
/// steps cycle through the rows of inputs (K, 30) = [eta, nu, eta_d,
/// eta_d_dot, eta_d_ddot].
template <typename Controller>
double time_steps(const Controller& controller, py::handle inputs, long steps, int repeats) {
  const Eigen::MatrixXd in = py_args::dynamic_matrix(inputs, "inputs", -1, 30);
  if (steps < 1 || repeats < 1) throw py::value_error("steps and repeats must be >= 1");
  std::vector<Vec6> rows(static_cast<std::size_t>(in.rows()) * 5);
  for (Eigen::Index k = 0; k < in.rows(); ++k)
    for (int p = 0; p < 5; ++p) rows[static_cast<std::size_t>(k * 5 + p)] = in.row(k).segment<6>(6 * p);
  const auto k_rows = static_cast<long>(in.rows());
  double best = 0;
  {
    py::gil_scoped_release release;
    for (int r = 0; r < repeats; ++r) {
      Controller c = controller;
      Vec6 tau;
      const auto t0 = std::chrono::steady_clock::now();
      for (long s = 0; s < steps; ++s) {
        const Vec6* x = &rows[static_cast<std::size_t>((s % k_rows) * 5)];
        (void)c.step(x[0], x[1], x[2], x[3], x[4], tau);
      }
      const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!tau.allFinite()) throw std::runtime_error("non-finite tau in the timing loop");
      best = r == 0 ? dt : std::min(best, dt);
    }
  }
  return best / static_cast<double>(steps);
}

/// Seconds per plant evaluation (vehicle.acceleration) in a C++ loop.
double time_acceleration(const Vehicle<double>& vehicle, py::handle eta, py::handle nu,
                         py::handle tau, long steps, int repeats) {
  Vec6 e = py_args::vector<6>(eta, "eta"), n = py_args::vector<6>(nu, "nu");
  const Vec6 t = py_args::vector<6>(tau, "tau");
  double best = 0;
  py::gil_scoped_release release;
  for (int r = 0; r < repeats; ++r) {
    Vec6 nu_dot, acc = Vec6::Zero();
    const auto t0 = std::chrono::steady_clock::now();
    for (long s = 0; s < steps; ++s) {
      // Each input depends on the last output, so no call can be skipped.
      n(0) = e(0) + 1e-12 * acc(0);
      (void)vehicle.acceleration(e, n, t, nu_dot);
      acc += nu_dot;
    }
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!acc.allFinite()) throw std::runtime_error("non-finite acceleration in the timing loop");
    best = r == 0 ? dt : std::min(best, dt);
  }
  return best / static_cast<double>(steps);
}

}  // namespace

}  // namespace neurov::bench

PYBIND11_MODULE(_bench, m) {
  namespace py = pybind11;
  using namespace neurov;
  using namespace neurov::bench;
  m.doc() = "Timing helpers for bench/compare.py (built with NEUROV_BUILD_BENCH); not public API.";
  // The controllers and the vehicle are _core's types: import it so they are registered.
  py::module_::import("neurov._core");
  m.def("time_controller_steps", &time_steps<NNAdaptiveController<double>>,
        py::arg("controller"), py::arg("inputs"), py::arg("steps"), py::arg("repeats") = 5);
  m.def("time_controller_steps", &time_steps<LinearAdaptiveController<double>>,
        py::arg("controller"), py::arg("inputs"), py::arg("steps"), py::arg("repeats") = 5);
  m.def("time_acceleration", &time_acceleration, py::arg("vehicle"), py::arg("eta"),
        py::arg("nu"), py::arg("tau"), py::arg("steps"), py::arg("repeats") = 5);
}
