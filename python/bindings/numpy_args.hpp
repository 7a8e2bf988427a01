// Checked conversion of Python arguments (and of bound structs' fields,
// fields.hpp) to Eigen objects and numbers, so that a wrong type, shape, dtype
// or a non-finite number is an error naming the argument or field (pybind11's
// own casters only say that no overload matched). One array reader, real().
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>

#include "neurov/core/status.hpp"
#include "neurov/core/validation.hpp"
#include "core/errors.hpp"
#include "typed_args.hpp"

namespace neurov::py_args {

namespace py = pybind11;

/// A number as %.9g: short, and exact enough to recognise.
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

/// A Python object's type name ("list", "NoneType"): what every refusal of
/// the bindings says it got.
inline std::string type_name(const py::handle& obj) {
  return py::str(py::type::handle_of(obj).attr("__name__"));
}

/// Who a refusal names: an argument by its name ("argument 'eta'"), or a
/// field by its qualified name (field("Type.field"): "Type.field"). Made
/// from an argument's name, so call sites pass just the name.
struct Who {
  const char* name;
  bool is_field = false;
  Who(const char* argument) : name(argument) {}  // NOLINT: implicit by design
  std::string str() const { return is_field ? name : std::string("argument '") + name + "'"; }
};
inline Who field(const std::string& qualified) {
  Who w(qualified.c_str());
  w.is_field = true;
  return w;
}

inline std::string shape_string(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// A shape expected, as numpy prints it; a size < 0 (any) is "n" on the
/// first axis, "m" on the second.
inline std::string shape_string(std::initializer_list<py::ssize_t> shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    const py::ssize_t n = shape.begin()[i];
    s += (i ? ", " : "") + (n >= 0 ? std::to_string(n) : std::string(i ? "m" : "n"));
  }
  return s + (shape.size() == 1 ? ",)" : ")");
}
/// (rows, cols), or (rows,) for cols < 0.
inline std::string shape_string(py::ssize_t rows, py::ssize_t cols) {
  return cols < 0 ? shape_string({rows}) : shape_string({rows, cols});
}

/// Whether a's shape is `shape` (-1: any size on that axis).
inline bool has_shape(const py::array& a, std::initializer_list<py::ssize_t> shape) {
  if (a.ndim() != static_cast<py::ssize_t>(shape.size())) return false;
  for (std::size_t i = 0; i < shape.size(); ++i)
    if (shape.begin()[i] >= 0 && a.shape(static_cast<py::ssize_t>(i)) != shape.begin()[i]) return false;
  return true;
}

/// obj (any array-like, not None) as a C-contiguous float64 array of real
/// numbers, of any shape; TypeError naming `who` and the shape `expected`.
inline py::array_t<double, py::array::c_style> real_array(const py::handle& obj, const Who& who,
                                                          const std::string& expected) {
  py::object converted;  // null: None, or not an array-like
  if (!obj.is_none()) {
    try {
      converted = py::array::ensure(obj);
    } catch (const py::error_already_set&) {
    }
  }
  if (!converted)
    throw py::type_error(who.str() + " must be a float array of shape " + expected + ", got " +
                         (obj.is_none() ? std::string("None") : type_name(obj)));
  const auto arr = py::reinterpret_borrow<py::array>(converted);
  const char kind = arr.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(who.str() + " must hold real numbers (shape " + expected + "), got dtype " +
                         std::string(py::str(arr.dtype())));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
}

inline void require_finite(const double* data, py::ssize_t n, const Who& who) {
  for (py::ssize_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i]))
      throw py::value_error(who.str() + " must be finite; element " + std::to_string(i) + " is " +
                            num(data[i]));
}

/// The one reader of a real array: obj as a C-contiguous float64 array whose
/// shape is `shape` (-1: any size on that axis), with no NaN or Inf when
/// `finite`. The errors name `who` and the shape expected (`expected`, or
/// `shape` written by shape_string).
inline py::array_t<double, py::array::c_style> real(const py::handle& obj, const Who& who,
                                                    std::initializer_list<py::ssize_t> shape,
                                                    bool finite = true, std::string expected = {}) {
  if (expected.empty()) expected = shape_string(shape);
  auto a = real_array(obj, who, expected);
  if (!has_shape(a, shape))
    throw py::value_error(who.str() + " must have shape " + expected + ", got " + shape_string(a));
  if (finite) require_finite(a.data(), a.size(), who);
  return a;
}

/// Why numpy_array refuses an argument: its type or dtype (a TypeError to
/// most callers) or its shape or values (a ValueError).
enum class Refusal { type, value };

/// The one reader of a numpy array argument (a list is refused): obj as a
/// C-contiguous array of T, converted if need be, whose shape is `shape`
/// (-1: any size on that axis). T = double takes any real dtype, bool dtype
/// bool, std::int64_t any integer dtype, std::uint64_t one with no element
/// < 0. A refusal calls refuse(why, got), which raises; `got` says what was
/// given ("list", "dtype complex128", "shape (2, 5)", "element 1 = -1").
template <typename T, typename Refuse>
py::array_t<T, py::array::c_style> numpy_array(const py::handle& obj, std::initializer_list<py::ssize_t> shape,
                                               Refuse&& refuse) {
  if (!py::isinstance<py::array>(obj)) refuse(Refusal::type, type_name(obj));
  const auto a = py::reinterpret_borrow<py::array>(obj);
  const char kind = a.dtype().kind();
  bool dtype_ok = kind == 'i' || kind == 'u';
  if constexpr (std::is_same_v<T, double>) dtype_ok = dtype_ok || kind == 'f';
  if constexpr (std::is_same_v<T, bool>) dtype_ok = kind == 'b';
  if (!dtype_ok) refuse(Refusal::type, "dtype " + std::string(py::str(a.dtype())));
  if (!has_shape(a, shape)) refuse(Refusal::value, "shape " + shape_string(a));
  if constexpr (std::is_same_v<T, std::uint64_t>) {
    if (kind == 'i') {
      const auto s = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
      for (py::ssize_t i = 0; i < s.size(); ++i)
        if (s.data()[i] < 0)
          refuse(Refusal::value, "element " + std::to_string(i) + " = " + std::to_string(s.data()[i]) + " (< 0)");
    }
  }
  return py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
}

/// obj as an integer of type D; TypeError for a non-integer (a bool too),
/// ValueError giving D's range for one outside it (pybind11's own cast would
/// say "Unable to cast ... to C++ type '?'").
template <typename D>
D integer(const py::handle& obj, const std::string& name) {
  if (py::isinstance<py::bool_>(obj) || !py::hasattr(obj, "__index__"))
    throw py::type_error(name + " must be an int, got " +
                         type_name(obj));
  const py::int_ i(py::reinterpret_borrow<py::object>(obj));
  const py::int_ low(std::numeric_limits<D>::min()), high(std::numeric_limits<D>::max());
  if (i < low || i > high)
    throw py::value_error(name + " must be >= " + std::string(py::str(low)) + " and <= " +
                          std::string(py::str(high)) + ", got " + std::string(py::str(i)));
  return i.cast<D>();
}

/// obj as a C-contiguous float64 array of shape (rows, cols), or (rows,)
/// for cols < 0; rows < 0 takes any number of rows (real()).
inline py::array_t<double, py::array::c_style> real_rows(const py::handle& obj, const Who& who, py::ssize_t rows,
                                                         py::ssize_t cols, bool finite = true) {
  return cols < 0 ? real(obj, who, {rows}, finite) : real(obj, who, {rows, cols}, finite);
}

/// A vector of fixed length N.
template <int N>
Eigen::Matrix<double, N, 1> vector(const py::handle& obj, const Who& who, bool finite = true) {
  return Eigen::Map<const Eigen::Matrix<double, N, 1>>(real(obj, who, {N}, finite).data());
}

/// The arguments of the plant's functions, checked in this order: eta, nu,
/// tau (None: zero where `tau_may_be_none`) and the current (None: still
/// water).
struct PlantArgs {
  Eigen::Matrix<double, 6, 1> eta, nu, tau;
  Eigen::Matrix<double, 3, 1> current;
};
inline PlantArgs plant_args(const py::handle& eta, const py::handle& nu, const py::handle& tau,
                            const py::handle& current, bool tau_may_be_none = false) {
  PlantArgs a{vector<6>(eta, "eta"), vector<6>(nu, "nu"), Eigen::Matrix<double, 6, 1>::Zero(),
              Eigen::Matrix<double, 3, 1>::Zero()};
  if (!(tau_may_be_none && tau.is_none())) a.tau = vector<6>(tau, "tau");
  if (!current.is_none()) a.current = vector<3>(current, "current");
  return a;
}

/// A square N x N matrix, or a length-N vector taken as its diagonal.
template <int N>
Eigen::Matrix<double, N, N> matrix_or_diagonal(const py::handle& obj, const Who& who) {
  const std::string expected = shape_string({N, N}) + " or its diagonal " + shape_string({N});
  const auto a = real_array(obj, who, expected);
  if (has_shape(a, {N})) return Eigen::Map<const Eigen::Matrix<double, N, 1>>(real(a, who, {N}, true, expected).data()).asDiagonal();
  return Eigen::Map<const Eigen::Matrix<double, N, N, Eigen::RowMajor>>(real(a, who, {N, N}, true, expected).data());
}

/// A dynamic matrix; rows or cols < 0 mean "any".
inline Eigen::MatrixXd dynamic_matrix(const py::handle& obj, const Who& who, py::ssize_t rows, py::ssize_t cols,
                                      bool finite = true) {
  const auto a = real(obj, who, {rows, cols}, finite);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      a.data(), a.shape(0), a.shape(1));
}

/// A dynamic vector; n < 0 means any length.
inline Eigen::VectorXd dynamic_vector(const py::handle& obj, const Who& who, py::ssize_t n, bool finite = true) {
  const auto a = real(obj, who, {n}, finite);
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
}

/// A real number (Python int or float, or anything with __float__ but a bool
/// or an array of one or more dimensions), finite unless `finite` is false.
inline double scalar(const py::handle& obj, const Who& who, bool finite = true) {
  // A numpy array has __float__ but only a 0-d one is a number.
  if (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() != 0)
    throw py::type_error(who.str() + " must be a real number, got an array of shape " +
                         shape_string(py::reinterpret_borrow<py::array>(obj)));
  if (py::isinstance<py::bool_>(obj) || !py::hasattr(obj, "__float__"))
    throw py::type_error(who.str() + " must be a real number, got " + type_name(obj));
  const double v = obj.cast<double>();
  if (finite && !std::isfinite(v)) throw py::value_error(who.str() + " must be finite, got " + num(v));
  return v;
}

/// A string from a fixed set of choices (TypeError or ValueError naming it).
inline std::string choice(const py::handle& obj, const Who& who, std::initializer_list<const char*> choices) {
  std::string allowed;
  for (const char* c : choices) allowed += (allowed.empty() ? "'" : ", '") + std::string(c) + "'";
  if (!py::isinstance<py::str>(obj))
    throw py::type_error(who.str() + " must be a str, one of " + allowed + "; got " + type_name(obj));
  const auto s = obj.cast<std::string>();
  for (const char* c : choices)
    if (s == c) return s;
  throw py::value_error(who.str() + " must be one of " + allowed + ", got '" + s + "'");
}

/// A time step of an integrator: finite, > 0 and <= neurov::kMaxStep.
inline double step(const py::handle& obj, const Who& who) {
  const double v = scalar(obj, who);
  if (detail::check_step(who.name, v))
    throw py::value_error(who.str() + " must be > 0 and <= " + num(kMaxStep) +
                          " s (the longest step neurov integrates, docs/reliability.md), got " + num(v));
  return v;
}

/// Raises neurov._core.ValidationError (a ValueError carrying the field and
/// index) for a failed validation.
inline void raise_if_invalid(const ValidationError& e, const char* what) { bindings::raise_validation_error(e, what); }

}  // namespace neurov::py_args
