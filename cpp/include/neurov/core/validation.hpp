// What went wrong when a vehicle or a controller was configured. Plain data, no
// heap and no exceptions, so firmware can use it; `format` writes a message
// such as "mass = -1: expected > 0 and finite".
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdio>

#include <Eigen/Core>

#include "neurov/core/config.hpp"

#if NEUROV_HAS_EXCEPTIONS
#include <stdexcept>
#include <string>
#endif

namespace neurov {

struct ValidationError {
  /// Name of the offending field; nullptr when the configuration is valid.
  const char* field = nullptr;
  /// Element index within the field, or -1: the position in a vector; for a
  /// matrix entry (i, j) the row-major index i * cols + j in every check (the
  /// flat index of a C-ordered numpy array, whatever Eigen's storage order).
  int index = -1;
  /// The offending value (NaN when the field is a whole matrix).
  double value = 0.0;
  /// What the field must satisfy, e.g. "> 0 and finite".
  const char* expected = nullptr;

  constexpr bool ok() const noexcept { return field == nullptr; }
  explicit constexpr operator bool() const noexcept { return !ok(); }

  /// Writes a one-line message into buf (always NUL-terminated when size > 0).
  void format(char* buf, std::size_t size) const noexcept {
    if (size == 0) return;
    if (ok()) {
      std::snprintf(buf, size, "valid");
    } else if (std::isnan(value)) {
      if (index >= 0)
        std::snprintf(buf, size, "%s[%d]: expected %s", field, index, expected);
      else
        std::snprintf(buf, size, "%s: expected %s", field, expected);
    } else if (index >= 0) {
      std::snprintf(buf, size, "%s[%d] = %.9g: expected %s", field, index, value, expected);
    } else {
      std::snprintf(buf, size, "%s = %.9g: expected %s", field, value, expected);
    }
  }
};

/// The longest step [s] that rk4_step and ReferenceModel::step take. A step
/// is one control period or one RK4 substep of the plant (the paper: 0.2 s),
/// and RK4 is stable only while |lambda| dt < 2.785 for a real mode lambda:
/// the slowest damped mode of the shipped vehicles, NEROV's surge
/// ((m + X_u_dot) / X_u = 215 / 70 = 3.1 s), allows 8.6 s. Nothing a vehicle
/// model can integrate needs 10 s or more; such a dt is a unit mistake or a
/// corrupt value, whose "result" would be finite nonsense (1e43 after a step
/// of 1e6 s) or an overflow reported as if the input were not finite.
inline constexpr double kMaxStep = 10.0;

#if NEUROV_HAS_EXCEPTIONS
/// The throwing constructors' one check (vehicle, network, reference model,
/// controllers): std::invalid_argument "what: message".
inline void throw_if_invalid(const ValidationError& e, const char* what) {
  if (!e) return;
  char buf[256];
  e.format(buf, sizeof buf);
  throw std::invalid_argument(std::string(what) + ": " + buf);
}
#endif

namespace detail {

inline ValidationError invalid(const char* field, int index, double value,
                               const char* expected) noexcept {
  ValidationError e;
  e.field = field;
  e.index = index;
  e.value = value;
  e.expected = expected;
  return e;
}

/// First entry m(i, j), in row-major order, for which ok(value) is false,
/// reported at the row-major index i * cols + j (for a vector: its position;
/// for a matrix: numpy's flat index of a C-ordered array and the position in a
/// row-major C table), whatever the storage order of m; or ok. A 1 x 1 object
/// is reported with index -1. Every matrix check uses this one convention.
template <typename Derived, typename Ok>
inline ValidationError check_entries(const char* field, const Derived& m, Ok entry_ok,
                                     const char* expected) noexcept {
  const int rows = static_cast<int>(m.rows()), cols = static_cast<int>(m.cols());
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double v = static_cast<double>(m(i, j));
      if (!entry_ok(v)) return invalid(field, m.size() > 1 ? i * cols + j : -1, v, expected);
    }
  return {};
}

/// First entry (row-major, index i * cols + j) that is not finite, or ok.
template <typename Derived>
inline ValidationError check_finite(const char* field, const Derived& m) noexcept {
  return check_entries(field, m, [](double v) { return std::isfinite(v); }, "finite");
}

/// First entry (row-major, index i * cols + j) that is negative or not finite, or ok.
template <typename Derived>
inline ValidationError check_non_negative(const char* field, const Derived& m) noexcept {
  return check_entries(field, m, [](double v) { return std::isfinite(v) && v >= 0.0; },
                       ">= 0 and finite");
}

/// First entry (row-major, index i * cols + j) that is not strictly positive
/// and finite, or ok.
template <typename Derived>
inline ValidationError check_positive(const char* field, const Derived& m) noexcept {
  return check_entries(field, m, [](double v) { return std::isfinite(v) && v > 0.0; },
                       "> 0 and finite");
}

/// First pair (i, j) with |m(i,j) - m(j,i)| above rounding, reported at the
/// row-major index i * cols + j with the value m(i,j) - m(j,i); or ok.
template <typename Derived>
inline ValidationError check_symmetric(const char* field, const Derived& m) noexcept {
  using Scalar = typename Derived::Scalar;
  const Scalar scale = m.cwiseAbs().maxCoeff();
  const Scalar tol = Scalar(64) * Eigen::NumTraits<Scalar>::epsilon() * scale;
  for (int i = 0; i < static_cast<int>(m.rows()); ++i)
    for (int j = i + 1; j < static_cast<int>(m.cols()); ++j)
      if (!(std::abs(m(i, j) - m(j, i)) <= tol))
        return invalid(field, i * static_cast<int>(m.cols()) + j,
                       static_cast<double>(m(i, j) - m(j, i)),
                       "a symmetric matrix (value is M[i,j] - M[j,i], index i*cols + j)");
  return {};
}

inline ValidationError check_positive_scalar(const char* field, double v) noexcept {
  if (!(std::isfinite(v) && v > 0.0)) return invalid(field, -1, v, "> 0 and finite");
  return {};
}

/// A time step: > 0, finite and at most kMaxStep.
inline ValidationError check_step(const char* field, double dt) noexcept {
  if (!(std::isfinite(dt) && dt > 0.0 && dt <= kMaxStep))
    return invalid(field, -1, dt, "> 0 and <= 10 s (neurov::kMaxStep)");
  return {};
}

inline ValidationError check_non_negative_scalar(const char* field, double v) noexcept {
  if (!(std::isfinite(v) && v >= 0.0)) return invalid(field, -1, v, ">= 0 and finite");
  return {};
}

}  // namespace detail
}  // namespace neurov
