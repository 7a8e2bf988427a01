// Checked conversion of Python arguments to fixed-size Eigen objects, so that a
// wrong shape, dtype or a non-finite number is an error naming the argument
// (pybind11's own casters only say that no overload matched).
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

inline std::string shape_string(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) {
    if (i) s += ", ";
    s += std::to_string(a.shape(i));
  }
  if (a.ndim() == 1) s += ",";
  return s + ")";
}

inline std::string shape_string(py::ssize_t rows, py::ssize_t cols) {
  if (cols < 0) return "(" + (rows < 0 ? std::string("n") : std::to_string(rows)) + ",)";
  return "(" + (rows < 0 ? std::string("n") : std::to_string(rows)) + ", " +
         (cols < 0 ? std::string("m") : std::to_string(cols)) + ")";
}

/// obj as a C-contiguous float64 array of real numbers; TypeError otherwise.
inline py::array_t<double, py::array::c_style> real_array(const py::handle& obj, const char* name,
                                                          const std::string& expected) {
  if (obj.is_none())
    throw py::type_error(std::string("argument '") + name + "' must be a float array of shape " +
                         expected + ", got None");
  py::array arr;
  try {
    arr = py::array::ensure(obj);
  } catch (const py::error_already_set&) {
    arr = py::array();
  }
  if (!arr) {
    throw py::type_error(std::string("argument '") + name + "' must be a float array of shape " +
                         expected + ", got " + type_name(obj));
  }
  const char kind = arr.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') {
    throw py::type_error(std::string("argument '") + name + "' must hold real numbers (shape " +
                         expected + "), got dtype " + std::string(py::str(arr.dtype())));
  }
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(arr);
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
  bool shape_ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  py::ssize_t axis = 0;
  for (const py::ssize_t n : shape) shape_ok = shape_ok && (n < 0 || a.shape(axis++) == n);
  if (!shape_ok) refuse(Refusal::value, "shape " + shape_string(a));
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

inline void require_finite(const double* data, py::ssize_t n, const char* name) {
  for (py::ssize_t i = 0; i < n; ++i) {
    if (!std::isfinite(data[i])) {
      throw py::value_error(std::string("argument '") + name + "' must be finite; element " +
                            std::to_string(i) + " is " + num(data[i]));
    }
  }
}

/// obj as a C-contiguous float64 array of shape (rows, cols), or (rows,)
/// for cols < 0; rows < 0 takes any number of rows (any length). `finite` refuses NaN
/// and Inf. The errors name `name` and the shape expected.
inline py::array_t<double, py::array::c_style> real_rows(const py::handle& obj, const char* name, py::ssize_t rows,
                                                         py::ssize_t cols, bool finite = true) {
  const std::string expected = shape_string(rows, cols);
  auto a = real_array(obj, name, expected);
  const bool ok = a.ndim() == (cols < 0 ? 1 : 2) && (rows < 0 || a.shape(0) == rows) &&
                  (cols < 0 || a.shape(1) == cols);
  if (!ok)
    throw py::value_error(std::string("argument '") + name + "' must have shape " + expected + ", got " +
                          shape_string(a));
  if (finite) require_finite(a.data(), a.size(), name);
  return a;
}

/// A vector of fixed length N.
template <int N>
Eigen::Matrix<double, N, 1> vector(const py::handle& obj, const char* name) {
  return Eigen::Map<const Eigen::Matrix<double, N, 1>>(real_rows(obj, name, N, -1).data());
}

/// A vector of length N, or zero for None (an optional argument).
template <int N>
Eigen::Matrix<double, N, 1> vector_or_zero(const py::handle& obj, const char* name) {
  if (obj.is_none()) return Eigen::Matrix<double, N, 1>::Zero();
  return vector<N>(obj, name);
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
  return {vector<6>(eta, "eta"), vector<6>(nu, "nu"),
          tau_may_be_none ? vector_or_zero<6>(tau, "tau") : vector<6>(tau, "tau"),
          vector_or_zero<3>(current, "current")};
}

/// A matrix of fixed size R x C.
template <int R, int C>
Eigen::Matrix<double, R, C> matrix(const py::handle& obj, const char* name) {
  return Eigen::Map<const Eigen::Matrix<double, R, C, Eigen::RowMajor>>(real_rows(obj, name, R, C).data());
}

/// A square N x N matrix, or a length-N vector taken as its diagonal.
template <int N>
Eigen::Matrix<double, N, N> matrix_or_diagonal(const py::handle& obj, const char* name) {
  const std::string expected = shape_string(N, N) + " or its diagonal " + shape_string(N, -1);
  auto a = real_array(obj, name, expected);
  if (a.ndim() == 1 && a.shape(0) == N) {
    require_finite(a.data(), N, name);
    return Eigen::Map<const Eigen::Matrix<double, N, 1>>(a.data()).asDiagonal();
  }
  if (a.ndim() == 2 && a.shape(0) == N && a.shape(1) == N) {
    require_finite(a.data(), N * N, name);
    return Eigen::Map<const Eigen::Matrix<double, N, N, Eigen::RowMajor>>(a.data());
  }
  throw py::value_error(std::string("argument '") + name + "' must have shape " + expected +
                        ", got " + shape_string(a));
}

/// A dynamic matrix; rows or cols < 0 mean "any".
inline Eigen::MatrixXd dynamic_matrix(const py::handle& obj, const char* name, py::ssize_t rows,
                                      py::ssize_t cols) {
  const std::string expected = shape_string(rows, cols);
  auto a = real_array(obj, name, expected);
  if (a.ndim() != 2 || (rows >= 0 && a.shape(0) != rows) || (cols >= 0 && a.shape(1) != cols))
    throw py::value_error(std::string("argument '") + name + "' must have shape " + expected +
                          ", got " + shape_string(a));
  require_finite(a.data(), a.size(), name);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      a.data(), a.shape(0), a.shape(1));
}

/// A dynamic vector; n < 0 means any length.
inline Eigen::VectorXd dynamic_vector(const py::handle& obj, const char* name, py::ssize_t n) {
  const auto a = real_rows(obj, name, n, -1);
  return Eigen::Map<const Eigen::VectorXd>(a.data(), a.shape(0));
}

/// A finite real number (Python int or float; bool is refused).
inline double scalar(const py::handle& obj, const char* name) {
  // A numpy array has __float__ but only a 0-d one is a number.
  if (py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).ndim() != 0) {
    throw py::type_error(std::string("argument '") + name +
                         "' must be a real number, got an array of shape " +
                         shape_string(py::reinterpret_borrow<py::array>(obj)));
  }
  if (py::isinstance<py::bool_>(obj) ||
      !(py::isinstance<py::float_>(obj) || py::isinstance<py::int_>(obj) ||
        py::hasattr(obj, "__float__"))) {
    throw py::type_error(std::string("argument '") + name + "' must be a real number, got " +
                         type_name(obj));
  }
  const double v = obj.cast<double>();
  if (!std::isfinite(v))
    throw py::value_error(std::string("argument '") + name + "' must be finite, got " +
                          num(v));
  return v;
}

/// A string from a fixed set of choices (TypeError or ValueError naming it).
inline std::string choice(const py::handle& obj, const char* name,
                          std::initializer_list<const char*> choices) {
  std::string allowed;
  for (const char* c : choices) allowed += (allowed.empty() ? "'" : ", '") + std::string(c) + "'";
  if (!py::isinstance<py::str>(obj))
    throw py::type_error(std::string("argument '") + name + "' must be a str, one of " + allowed +
                         "; got " + type_name(obj));
  const auto s = obj.cast<std::string>();
  for (const char* c : choices)
    if (s == c) return s;
  throw py::value_error(std::string("argument '") + name + "' must be one of " + allowed +
                        ", got '" + s + "'");
}

/// A finite number > 0.
inline double positive(const py::handle& obj, const char* name) {
  const double v = scalar(obj, name);
  if (!(v > 0.0))
    throw py::value_error(std::string("argument '") + name + "' must be > 0, got " +
                          num(v));
  return v;
}

/// A time step of an integrator: finite, > 0 and <= neurov::kMaxStep.
inline double step(const py::handle& obj, const char* name) {
  const double v = scalar(obj, name);
  if (detail::check_step(name, v))
    throw py::value_error(std::string("argument '") + name + "' must be > 0 and <= " +
                          num(kMaxStep) + " s (the longest step neurov integrates, " +
                          "docs/reliability.md), got " + num(v));
  return v;
}

/// Raises neurov._core.ValidationError (a ValueError carrying the field and
/// index) for a failed validation.
inline void raise_if_invalid(const ValidationError& e, const char* what) {
  bindings::raise_validation_error(e, what);
}

}  // namespace neurov::py_args
