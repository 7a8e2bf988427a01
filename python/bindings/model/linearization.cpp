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
using Vec3 = Vector3<double>;
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

Vec3 optional_vector3(const py::handle& obj, const char* name) {
  return obj.is_none() ? Vec3::Zero() : py_args::vector<3>(obj, name);
}

Vec6 optional_vector6(const py::handle& obj, const char* name) {
  return obj.is_none() ? Vec6::Zero() : py_args::vector<6>(obj, name);
}

}  // namespace

void bind_linearization(py::module_& m) {
  m.def(
      "plant_derivative",
      [](const Vehicle<double>& v, py::handle eta, py::handle nu, py::handle tau,
         py::handle current) {
        const Vec6 e = py_args::vector<6>(eta, "eta");
        const Vec6 n = py_args::vector<6>(nu, "nu");
        const Vec6 t = py_args::vector<6>(tau, "tau");
        const Vec3 c = optional_vector3(current, "current");
        Vec6 eta_dot, nu_dot;
        raise_plant_status(v.derivative(e, n, t, c, eta_dot, nu_dot), "plant_derivative");
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
      [](const Vehicle<double>& v, py::handle eta, py::handle nu, py::handle tau,
         py::handle current) {
        const Vec6 e = py_args::vector<6>(eta, "eta");
        const Vec6 n = py_args::vector<6>(nu, "nu");
        const Vec6 t = optional_vector6(tau, "tau");
        const Vec3 c = optional_vector3(current, "current");
        Matrix12<double> a;
        Matrix12x6<double> b;
        raise_plant_status(linearize(v, e, n, t, c, a, b), "plant_jacobians");
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
