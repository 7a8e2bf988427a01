#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <cmath>

#include "bindings.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;

void bind_regressor(py::module_& m) {
  m.def(
      "regressor",
      [](const typed::ArrayLike& nu_r_dot, const typed::ArrayLike& nu_r, const typed::ArrayLike& nu, const typed::ArrayLike& eta) {
        const Vec6 e = py_args::vector<6>(eta, "eta");
        return RegressorMatrix<double>(regressor<double>(
            py_args::vector<6>(nu_r_dot, "nu_r_dot"), py_args::vector<6>(nu_r, "nu_r"),
            py_args::vector<6>(nu, "nu"), std::sin(e(3)), std::cos(e(3)), std::sin(e(4)),
            std::cos(e(4))));
      },
      py::arg("nu_r_dot"), py::arg("nu_r"), py::arg("nu"), py::arg("eta"),
      "Regressor Phi (6, 24) with Phi @ theta = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) "
      "for NEROV's model structure; THETA_NAMES names the columns.");

  m.def(
      "regressor_parameters",
      [](const Vehicle<double>& v) {
        ParameterVector<double> theta;
        py_args::raise_if_invalid(regressor_parameters(v.parameters(), theta), "vehicle");
        return theta;
      },
      py::arg("vehicle"),
      "The true theta (24,) of a vehicle whose structure the regressor covers (r_g = 0, "
      "diagonal inertia and added mass, r_b on the z axis); ValueError otherwise.");

  py::list names;
  for (int i = 0; i < kRegressorParameters; ++i) names.append(theta_name(i));
  m.attr("THETA_NAMES") = py::tuple(names);
}

}  // namespace neurov::bindings
