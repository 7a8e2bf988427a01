// The bindings of a controller that describes its configuration with
// config_fields (neurov/core/field_spec.hpp) and has the names of
// NEUROV_CONTROLLER_NAMES: its configuration class field by field with the
// C++ validator, its class with the constructor from the configuration and
// the keyword one (the fields in order, the struct's defaults shown), the
// members every controller has, its (6,) state and its snapshot. Every
// built-in controller's configuration is bound here (bind_generic_config); a
// controller with a constructor of its own (the NN's network, the linear
// adaptive's gamma as one number) has an overload of bind_controller in
// controllers.cpp.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "controller_bindings.hpp"
#include "fields.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;

/// "SuperTwistingController" -> "SuperTwistingConfig".
inline std::string config_class_name(const char* class_name) {
  std::string name = class_name;
  const std::string suffix = "Controller";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  return name + "Config";
}

/// "super-twisting controller": the prefix of the validator's errors.
template <typename Controller>
const char* controller_what() {
  return Controller::kWhat;
}

template <typename Config>
auto fields_of() {
  return ::neurov::config_fields(static_cast<const Config*>(nullptr));
}

template <typename Controller>
void bind_generic_config(py::module_& m) {
  using Config = typename Controller::Config;
  static const std::string name = config_class_name(Controller::kClassName);
  static const std::string doc = std::string("Configuration of ") + Controller::kClassName + ".";
  Fields<Config>::described(m, name.c_str(), doc.c_str())
      .validator(controller_what<Controller>())
      .finish();
}

/// A keyword argument for a field: a number defaults to the struct's value,
/// a vector is required (as the other controllers' gains are).
template <typename Config, typename D>
auto keyword_arg(const FieldSpec<Config, D>& spec) {
  if constexpr (std::is_same_v<D, double>)
    return config_arg_or(spec.name, spec.member, py::float_(Config{}.*(spec.member)));
  else
    return config_arg(spec.name, spec.member);
}

/// `spec` as a one-element tuple when Keep, else an empty one.
template <bool Keep, typename Spec>
auto keep_if(const Spec& spec) {
  if constexpr (Keep)
    return std::make_tuple(spec);
  else
    return std::tuple<>();
}

/// The fields in the order of the keyword constructor: the required ones
/// (vectors) first, then the numbers with their defaults, each group in the
/// struct's order (a signature with a required argument after a defaulted one
/// is not Python).
template <typename Config>
auto constructor_fields() {
  return std::apply(
      [](const auto&... s) {
        return std::tuple_cat(
            keep_if<!std::is_same_v<typename std::decay_t<decltype(s)>::Type, double>>(s)...,
            keep_if<std::is_same_v<typename std::decay_t<decltype(s)>::Type, double>>(s)...);
      },
      fields_of<Config>());
}

template <typename Controller, typename = void>
struct has_vector_state : std::false_type {};
template <typename Controller>
struct has_vector_state<Controller, std::void_t<decltype(Controller::kStateName)>>
    : std::true_type {};

template <typename Controller>
void bind_generic_controller(py::module_& m) {
  using Config = typename Controller::Config;
  py::class_<Controller> cls(m, Controller::kClassName, Controller::kDoc);
  static const std::string ctor_doc =
      "The configuration's fields by name (see " + config_class_name(Controller::kClassName) +
      "); ValueError names a bad one.";
  std::apply(
      [&cls](const auto&... spec) {
        def_constructors(cls, controller_what<Controller>(), ctor_doc.c_str(),
                         keyword_arg(spec)...);
      },
      constructor_fields<Config>());
  def_common<Controller>(cls);
  if constexpr (has_vector_state<Controller>::value) {
    // The state vector: (6,) for most, longer for a controller with more memory.
    constexpr int n = std::decay_t<decltype(std::declval<const Controller&>().state())>::RowsAtCompileTime;
    using StateD = Eigen::Matrix<double, n, 1>;
    def_controller_snapshot<Controller>(
        cls, controller_what<Controller>(),
        [](const Controller& c, py::dict& d) { d[Controller::kStateName] = StateD(c.state().template cast<double>()); },
        [](Controller& c, const py::dict& d, const TrackingError<double>& e, Status s) {
          return c.restore(e, s,
                           py_args::vector<n>(snapshot_field(d, Controller::kStateName),
                                              Controller::kStateName));
        });
    cls.def_property_readonly(
        Controller::kStateName, [](const Controller& c) { return StateD(c.state().template cast<double>()); },
        Controller::kStateDoc);
  } else {
    def_controller_snapshot<Controller>(
        cls, controller_what<Controller>(), [](const Controller&, py::dict&) {},
        [](Controller& c, const py::dict&, const TrackingError<double>& e, Status s) {
          return c.restore(e, s);
        });
  }
}

}  // namespace neurov::bindings
