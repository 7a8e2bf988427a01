// Every controller's configuration struct, bound from its description beside
// it in C++ (config_fields; the fields of its own kinds in generic_controller.hpp):
// the one schema Python and C++ share. Defaults are the structs' own; the
// validator is the C++ one (validate() and every controller's constructor run it).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "generic_controller.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

RobustModification parse_modification(py::handle obj) {
  if (py::isinstance<RobustModification>(obj)) return obj.cast<RobustModification>();
  const auto s =
      py_args::choice(obj, "modification", {"none", "sigma", "e_modification", "projection"});
  for (auto m : {RobustModification::sigma, RobustModification::e_modification,
                 RobustModification::projection})
    if (s == to_string(m)) return m;
  return RobustModification::none;
}

void bind_controller_configs(py::module_& m) {
  py::enum_<RobustModification>(m, "RobustModification",
                                "Robust modification of the NN controller's adaptive law.")
      .value("none", RobustModification::none, "The paper's pure gradient law.")
      .value("sigma", RobustModification::sigma, "Leakage: W_dot += -sigma_m W Gamma_w.")
      .value("e_modification", RobustModification::e_modification,
             "Leakage in proportion to the error: W_dot += -kappa ||J^-1 s|| W Gamma_w.")
      .value("projection", RobustModification::projection,
             "After each update, W scaled back onto ||W||_F <= w_max.");

  for_each_type(BuiltInControllers<double>{},
                [&m](auto tag) { bind_generic_config<typename decltype(tag)::type>(m); });
}

}  // namespace neurov::bindings
