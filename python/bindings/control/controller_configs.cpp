// Every controller's configuration struct, bound from its description beside
// it in C++ (config_fields): the one schema Python and C++ share. Defaults
// are the structs' own; the validator is the C++ one (validate() and every
// controller's constructor run it).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "fields.hpp"
#include "generic_controller.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "neurov/model/vehicle.hpp"
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

/// The NN's modification: a RobustModification or its name.
template <>
struct FieldForm<RobustModification> {
  static constexpr bool custom = true;
  template <typename T>
  static void bind(Fields<T>& f, const char* name, RobustModification T::*member, const char* doc) {
    f.field(
        name, [member](const T& c) { return c.*member; },
        [member](T& c, const typed::EnumOrStr<RobustModification>& v, const std::string&) {
          c.*member = parse_modification(v);
        },
        doc);
  }
};

/// A nominal model: a Vehicle in Python (None until set), its parameters in C++.
template <>
struct FieldForm<VehicleParameters<double>> {
  static constexpr bool custom = true;
  template <typename T>
  static void bind(Fields<T>& f, const char* name, VehicleParameters<double> T::*member,
                   const char* doc) {
    f.field(
        name,
        [member](const T& c) -> py::typing::Optional<Vehicle<double>> {
          Vehicle<double> v;
          if (Vehicle<double>::create(c.*member, v)) return py::none();
          return py::cast(v);
        },
        [member](T& c, const typed::Of<Vehicle<double>>& v, const std::string& qualified) {
          if (!py::isinstance<Vehicle<double>>(v))
            throw py::type_error(qualified + " must be a Vehicle, got " +
                                 std::string(py::str(py::type::handle_of(v))));
          c.*member = v.cast<const Vehicle<double>&>().parameters();
        },
        doc);
  }
};

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
