// The 12-state plant as python-control sees it: its right-hand side
// f(x, tau) and the analytic Jacobians A = df/dx, B = df/dtau (neurov.control
// builds NonlinearIOSystem and StateSpace from these).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>
#include <utility>

#include "bindings.hpp"
#include "numpy_args.hpp"
#include "neurov/model/linearization.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

namespace {

void raise_plant_status(Status s, const char* what) {
  if (s == Status::ok) return;
  if (s == Status::near_singularity)
    throw py::value_error(std::string(what) +
                          ": argument 'eta' has its pitch at the Euler-angle singularity "
                          "(|cos(theta)| < " + py_args::num(singularity_threshold<double>()) +
                          "), where J(eta) is not defined");
  if (s == Status::non_finite_output)
    throw py::value_error(std::string(what) +
                          ": the result overflowed to a non-finite number; the inputs are "
                          "outside the model's range");
  throw py::value_error(std::string(what) + " failed: " + to_string(s));
}

}  // namespace

void bind_linearization(py::module_& m) {
  m.def(
      "plant_derivative",
      [](const Vehicle<double>& v, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& tau,
         const typed::OptionalArrayLike& current) {
        const auto a = py_args::plant_args(eta, nu, tau, current);
        Vec6 eta_dot, nu_dot;
        raise_plant_status(v.derivative(a.eta, a.nu, a.tau, a.current, eta_dot, nu_dot),
                           "plant_derivative");
        Vec12 x_dot;
        x_dot << eta_dot, nu_dot;
        return x_dot;
      },
      py::arg("vehicle"), py::arg("eta"), py::arg("nu"), py::arg("tau"),
      py::arg("current") = py::none(),
      "The 12-state plant's right-hand side (eta_dot, nu_dot), shape (12,): eta_dot = "
      "J(eta) nu and nu_dot as in Vehicle.acceleration; the function rk4_step integrates. "
      "`current` (3,) is a constant NED current velocity [m/s]. Raises ValueError at the "
      "pitch singularity.");

  m.def(
      "plant_jacobians",
      [](const Vehicle<double>& v, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::OptionalArrayLike& tau,
         const typed::OptionalArrayLike& current) {
        const auto x = py_args::plant_args(eta, nu, tau, current, true);
        Matrix12<double> a;
        Matrix12x6<double> b;
        raise_plant_status(linearize(v, x.eta, x.nu, x.tau, x.current, a, b), "plant_jacobians");
        return std::make_pair(a, b);
      },
      py::arg("vehicle"), py::arg("eta"), py::arg("nu"), py::arg("tau") = py::none(),
      py::arg("current") = py::none(),
      "Analytic Jacobians of plant_derivative at (eta, nu): A = d(eta_dot, nu_dot)/d(eta, nu), "
      "shape (12, 12), and B = d(eta_dot, nu_dot)/d tau, shape (12, 6). The plant is affine in "
      "tau, so `tau` (default zero) changes neither. `current` (3,) is a constant NED current "
      "velocity [m/s]. Raises ValueError at the pitch singularity.");
}

}  // namespace neurov::bindings
