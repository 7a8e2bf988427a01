// The bindings of a controller from its header alone: its configuration's
// description (config_fields, neurov/core/field_spec.hpp) and the names and
// docstring of NEUROV_CONTROLLER_NAMES and kDoc. From them come its
// configuration class (bound field by field with the C++ validator), its
// class with the constructor from the configuration and the keyword one (the
// fields by name, the struct's defaults shown), the members every controller
// has, its state and its snapshot. A controller with more (the NN's network,
// the linear adaptive's theta_hat) adds it in an overload of bind_controller
// in controllers.cpp.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <array>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "controller_bindings.hpp"
#include "fields.hpp"
#include "neurov/control/built_in_controllers.hpp"
#include "neurov/model/vehicle.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;

/// The NN's modification: a RobustModification or its name.
template <>
struct FieldForm<RobustModification> {
  static constexpr bool custom = true;
  using Argument = typed::EnumOrStr<RobustModification>;
  template <typename T>
  static void bind(Fields<T>& f, const char* name, RobustModification T::*member, const char* doc) {
    f.field(
        name, [member](const T& c) { return c.*member; },
        [member](T& c, const Argument& v, const std::string&) { c.*member = parse_modification(v); },
        doc);
  }
};

/// A nominal model: a Vehicle in Python (None until set), its parameters in C++.
template <>
struct FieldForm<VehicleParameters<double>> {
  static constexpr bool custom = true;
  using Argument = typed::Of<Vehicle<double>>;
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
        [member](T& c, const Argument& v, const std::string& qualified) {
          if (!py::isinstance<Vehicle<double>>(v))
            throw py::type_error(qualified + " must be a Vehicle, got " + py_args::type_name(v));
          c.*member = v.cast<const Vehicle<double>&>().parameters();
        },
        doc);
  }
};

/// py::kw_only() where `here`: the keyword-only fields start where the
/// description's flag kKeywordOnly says, known when the class is bound.
struct KeywordOnlyIf {
  bool here;
};

}  // namespace neurov::bindings

namespace pybind11::detail {
template <>
struct process_attribute<neurov::bindings::KeywordOnlyIf>
    : process_attribute_default<neurov::bindings::KeywordOnlyIf> {
  static void init(const neurov::bindings::KeywordOnlyIf& k, function_record* r) {
    if (k.here) process_attribute<kw_only>::init(kw_only(), r);
  }
};
}  // namespace pybind11::detail

namespace neurov::bindings {

// How a field is given to a keyword constructor: a number, an array, or (an
// enum, a bound object) what its configuration property takes.
template <typename D>
constexpr bool is_number_field = std::is_floating_point_v<D>;
template <typename D>
constexpr bool is_array_field = std::is_base_of_v<Eigen::MatrixBase<D>, D>;
template <typename D>
constexpr bool is_object_field = !is_number_field<D> && !is_array_field<D> && !std::is_enum_v<D>;

template <typename D, typename = void>
struct KeywordArgument {
  using type = typename FieldForm<D>::Argument;
};
template <typename D>
struct KeywordArgument<D, std::enable_if_t<is_number_field<D>>> {
  using type = typed::Real;
};
template <typename D>
struct KeywordArgument<D, std::enable_if_t<is_array_field<D>>> {
  using type = typed::ArrayLike;
};

/// `spec` as a one-element tuple when Keep, else an empty one.
template <bool Keep, typename Spec>
auto keep_if(const Spec& spec) {
  if constexpr (Keep)
    return std::make_tuple(spec);
  else
    return std::tuple<>();
}

/// The fields in the order of the keyword constructor: the bound objects
/// (a nominal vehicle) first, then the others in the description's order.
template <typename Config>
auto keyword_fields() {
  return std::apply(
      [](const auto&... s) {
        return std::tuple_cat(keep_if<is_object_field<typename std::decay_t<decltype(s)>::Type>>(s)...,
                              keep_if<!is_object_field<typename std::decay_t<decltype(s)>::Type>>(s)...);
      },
      config_fields(static_cast<const Config*>(nullptr)));
}

/// Which of them have a default: from the first number or enum on, all
/// (an array then defaults to None, the struct's value); before it, none.
template <typename... S>
constexpr std::array<bool, sizeof...(S)> defaulted_fields(const std::tuple<S...>*) {
  constexpr bool own[] = {!is_array_field<typename S::Type> && !is_object_field<typename S::Type>...,
                          false};
  std::array<bool, sizeof...(S)> out{};
  bool seen = false;
  for (std::size_t i = 0; i < sizeof...(S); ++i) out[i] = seen = seen || own[i];
  return out;
}
template <typename Specs>
inline constexpr auto kDefaulted = defaulted_fields(static_cast<const Specs*>(nullptr));

/// The field's argument, with the struct's default when it has one.
template <bool Defaulted, typename Config, typename D>
auto keyword_arg(const FieldSpec<Config, D>& s) {
  if constexpr (!Defaulted)
    return py::arg(s.name);
  else if constexpr (is_number_field<D>)
    return py::arg(s.name) = py::float_(Config{}.*(s.member));
  else if constexpr (std::is_enum_v<D>)
    return py::arg(s.name) = py::str(to_string(Config{}.*(s.member)));
  else
    return py::arg(s.name) = py::none();
}

/// Sets the field from its argument `v`, errors naming the argument; an
/// array with a default keeps it for None.
template <typename Config, typename D>
void set_keyword(Config& c, const FieldSpec<Config, D>& s, py::handle v, bool defaulted) {
  if constexpr (is_number_field<D>) {
    c.*(s.member) = py_args::scalar(v, s.name);
  } else if constexpr (is_array_field<D>) {
    if (defaulted && v.is_none()) return;
    if ((s.flags & kNumberFills) && (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)))
      c.*(s.member) = D::Constant(py_args::scalar(v, s.name));
    else
      c.*(s.member) = py_args::vector<D::RowsAtCompileTime>(v, s.name);
  } else {
    py::cast(&c, py::return_value_policy::reference).attr(s.name) = v;  // its property's checks
  }
}

/// Arguments of a keyword constructor that are not fields (the NN's network
/// before them, its learning rates after them): their types and declarations.
template <typename Types, typename Decls>
struct ExtraArgs {
  Decls decls;
};
template <typename... T, typename... Decl>
ExtraArgs<TypeList<T...>, std::tuple<Decl...>> extra_args(Decl... decls) {
  return {std::make_tuple(decls...)};
}

template <typename Controller, typename Specs, std::size_t... I, typename... Lead, typename LeadDecls,
          typename... Tail, typename TailDecls, typename Make>
void def_keyword_init(py::class_<Controller>& cls, const char* doc, const Specs& specs,
                      std::index_sequence<I...>, ExtraArgs<TypeList<Lead...>, LeadDecls> lead,
                      ExtraArgs<TypeList<Tail...>, TailDecls> tail, Make make) {
  using Config = typename Controller::Config;
  auto init = py::init(
      [specs, make](const Lead&... lead_values,
                    const typename KeywordArgument<typename std::tuple_element_t<I, Specs>::Type>::type&... values,
                    const Tail&... tail_values) {
        Config config;
        (set_keyword(config, std::get<I>(specs), values, kDefaulted<Specs>[I]), ...);
        return make(lead_values..., config, tail_values...);
      });
  std::size_t first_keyword_only = sizeof...(I);
  ((first_keyword_only = (std::get<I>(specs).flags & kKeywordOnly) && first_keyword_only > I
                             ? I : first_keyword_only),
   ...);
  std::apply([&](const auto&... decls) { cls.def(std::move(init), decls..., doc); },
             std::tuple_cat(lead.decls,
                            std::make_tuple(KeywordOnlyIf{I == first_keyword_only},
                                            keyword_arg<kDefaulted<Specs>[I]>(std::get<I>(specs)))...,
                            tail.decls));
}

/// The keyword constructor: `lead`, the configuration's fields (keyword_fields),
/// `tail`; make(lead..., config, tail...) builds the controller.
template <typename Controller, typename Lead = ExtraArgs<TypeList<>, std::tuple<>>,
          typename Tail = ExtraArgs<TypeList<>, std::tuple<>>, typename Make>
void def_keyword_init(py::class_<Controller>& cls, const char* doc, Make make, Lead lead = {},
                      Tail tail = {}) {
  const auto specs = keyword_fields<typename Controller::Config>();
  def_keyword_init(cls, doc, specs,
                   std::make_index_sequence<std::tuple_size_v<std::decay_t<decltype(specs)>>>(), lead,
                   tail, make);
}

/// "SuperTwistingController" -> "SuperTwistingConfig".
inline std::string config_class_name(const char* class_name) {
  std::string name = class_name;
  const std::string suffix = "Controller";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    name.resize(name.size() - suffix.size());
  return name + "Config";
}

/// "The configuration's fields by name (see PDConfig)...", the keyword
/// constructor's docstring, after `before`.
template <typename Controller>
const char* keyword_doc(const std::string& before = "") {
  static const std::string doc = before + "The configuration's fields by name (see " +
                                 config_class_name(Controller::kClassName) +
                                 "); ValueError names a bad one.";
  return doc.c_str();
}

template <typename Controller>
void bind_generic_config(py::module_& m) {
  static const std::string name = config_class_name(Controller::kClassName);
  static const std::string doc = std::string("Configuration of ") + Controller::kClassName + ".";
  Fields<typename Controller::Config>::described(m, name.c_str(), doc.c_str())
      .validator(Controller::kWhat)
      .finish();
}

/// The class with its two constructors and the members every controller has.
template <typename Controller>
py::class_<Controller> bind_controller_class(py::module_& m) {
  py::class_<Controller> cls(m, Controller::kClassName, Controller::kDoc);
  def_init_from_config<Controller>(cls, Controller::kWhat);
  def_keyword_init(cls, keyword_doc<Controller>(), [](const typename Controller::Config& config) {
    return from_config<Controller>(config, Controller::kWhat);
  });
  def_common<Controller>(cls);
  return cls;
}

// The state a snapshot keeps besides the tracking error, shown as a property
// of the same name: the vector a header names (kStateName), or a model law's
// last output f, or none.
template <typename Controller, typename = void>
struct StateOf {
  static constexpr const char* name = nullptr;
};
template <typename Controller>
struct StateOf<Controller, std::void_t<decltype(&Controller::model_output)>> {
  static constexpr const char* name = "model_output";
  static constexpr const char* doc = "The model's f of the last step, shape (6,).";
};
template <typename Controller>
struct StateOf<Controller, std::void_t<decltype(Controller::kStateName)>> {
  static constexpr const char* name = Controller::kStateName;
  static constexpr const char* doc = Controller::kStateDoc;
};

template <typename Controller>
auto state_of(const Controller& c) {
  constexpr int n = std::decay_t<decltype(c.state())>::RowsAtCompileTime;
  return Eigen::Matrix<double, n, 1>(c.state().template cast<double>());
}

template <typename Controller>
void def_state(py::class_<Controller>& cls) {
  cls.def_property_readonly(StateOf<Controller>::name, &state_of<Controller>, StateOf<Controller>::doc);
}

template <typename Controller>
py::class_<Controller> bind_generic_controller(py::module_& m) {
  py::class_<Controller> cls = bind_controller_class<Controller>(m);
  constexpr const char* name = StateOf<Controller>::name;
  if constexpr (name != nullptr) {
    using State = decltype(state_of(std::declval<const Controller&>()));
    def_controller_snapshot<Controller>(
        cls, Controller::kWhat, [](const Controller& c, py::dict& d) { d[name] = state_of(c); },
        [](Controller& c, const py::dict& d, const TrackingError<double>& e, Status s) {
          return c.restore(e, s, snapshot_vector<State::RowsAtCompileTime>(d, name));
        });
    def_state<Controller>(cls);
  } else {
    def_controller_snapshot<Controller>(
        cls, Controller::kWhat, [](const Controller&, py::dict&) {},
        [](Controller& c, const py::dict&, const TrackingError<double>& e, Status s) {
          return c.restore(e, s);
        });
  }
  return cls;
}

template <typename Controller>
void bind_controller(py::module_& m, TypeTag<Controller>) {
  bind_generic_controller<Controller>(m);
}

}  // namespace neurov::bindings
