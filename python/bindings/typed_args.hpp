// The declared Python types of arguments that the bindings take as a plain
// object and convert themselves (numpy_args.hpp, fields.hpp), so that the
// signatures pybind11 writes, and the stub generated from them
// (tools/generate_stubs.py), say what a caller may pass: `numpy.typing.ArrayLike`,
// `typing.SupportsFloat`, `X | None`, ... instead of `object`.
//
// Each is a py::object that pybind11 hands over whatever it is given (so the
// binding's own checks still run and their errors still name the argument);
// only its name in the signature differs. Returned dicts have names too.
#pragma once

#include <pybind11/pybind11.h>

namespace neurov::typed {

namespace py = pybind11;

namespace detail {
// Every object is accepted; the binding's conversion judges it.
inline int any(PyObject*) { return 1; }
}  // namespace detail

/// An argument of any value, declared as `Name::name`.
template <typename Name>
class Arg : public py::object {
  PYBIND11_OBJECT_DEFAULT(Arg, object, detail::any)
};

/// A dict returned, declared as `Name::name`.
template <typename Name>
class Dict : public py::dict {
  PYBIND11_OBJECT_DEFAULT(Dict, dict, PyDict_Check)
};

namespace names {
using py::detail::const_name;
using py::detail::make_caster;

/// A type named by its text (a char array of static storage).
template <const auto& Text>
struct Named {
  static constexpr auto name = const_name(Text);
};
inline constexpr char array_like[] = "numpy.typing.ArrayLike";
inline constexpr char real[] = "typing.SupportsFloat";
inline constexpr char index[] = "typing.SupportsIndex";
inline constexpr char boolean[] = "bool";
inline constexpr char str[] = "str";
inline constexpr char real_or_array_like[] = "typing.SupportsFloat | numpy.typing.ArrayLike";
using RealOrArrayLike = Named<real_or_array_like>;
/// A TypedDict that tools/generate_stubs.py writes into the stub (pybind11
/// cannot declare one).
inline constexpr char simulation_result[] = "_SimulationResult";
inline constexpr char arrays[] = "dict[str, numpy.typing.NDArray[numpy.float64]]";
inline constexpr char any_values[] = "dict[str, typing.Any]";
/// A bound class or enum (its registered Python name).
template <typename T>
struct Of {
  static constexpr auto name = make_caster<T>::name;
};
template <typename T>
struct OrNone {
  static constexpr auto name = T::name + const_name(" | None");
};
template <typename T>
struct IterableOf {
  static constexpr auto name =
      const_name("collections.abc.Iterable[") + make_caster<T>::name + const_name("]");
};
/// A bound enum or one of its members' names.
template <typename E>
struct EnumOrStr {
  static constexpr auto name = make_caster<E>::name + const_name(" | str");
};
}  // namespace names

using ArrayLike = Arg<names::Named<names::array_like>>;
using OptionalArrayLike = Arg<names::OrNone<names::Named<names::array_like>>>;
using Real = Arg<names::Named<names::real>>;
using Index = Arg<names::Named<names::index>>;
using OptionalIndex = Arg<names::OrNone<names::Named<names::index>>>;
using Bool = Arg<names::Named<names::boolean>>;
using Str = Arg<names::Named<names::str>>;
using RealOrArrayLike = Arg<names::RealOrArrayLike>;
template <typename T>
using Of = Arg<names::Of<T>>;
template <typename T>
using OptionalOf = Arg<names::OrNone<names::Of<T>>>;
template <typename T>
using IterableOf = Arg<names::IterableOf<T>>;
template <typename E>
using EnumOrStr = Arg<names::EnumOrStr<E>>;

/// What run_closed_loop, Simulator.result and drain return.
using SimulationResultDict = Dict<names::Named<names::simulation_result>>;
/// A dict of float64 arrays (a tracking error, a controller's snapshot).
using ArraysDict = Dict<names::Named<names::arrays>>;
/// A dict of mixed values (a vehicle's parameters).
using AnyDict = Dict<names::Named<names::any_values>>;

}  // namespace neurov::typed

namespace pybind11::detail {
template <typename Name>
struct handle_type_name<neurov::typed::Arg<Name>> {
  static constexpr auto name = Name::name;
};
template <typename Name>
struct handle_type_name<neurov::typed::Dict<Name>> {
  static constexpr auto name = Name::name;
};
}  // namespace pybind11::detail
