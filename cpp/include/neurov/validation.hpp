// What went wrong when a vehicle or a controller was configured. Plain data, no
// heap and no exceptions, so firmware can use it; `format` writes a message
// such as "mass = -1: expected > 0 and finite".
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdio>

#include <Eigen/Core>

namespace neurov {

struct ValidationError {
  /// Name of the offending field; nullptr when the configuration is valid.
  const char* field = nullptr;
  /// Element index within the field (vector/matrix entry), or -1.
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

/// First entry of a dense Eigen object that is not finite, or ok.
template <typename Derived>
inline ValidationError check_finite(const char* field, const Derived& m) noexcept {
  for (int i = 0; i < static_cast<int>(m.size()); ++i) {
    const double v = static_cast<double>(m.data()[i]);
    if (!std::isfinite(v)) return invalid(field, m.size() > 1 ? i : -1, v, "finite");
  }
  return {};
}

/// First entry that is negative or not finite, or ok.
template <typename Derived>
inline ValidationError check_non_negative(const char* field, const Derived& m) noexcept {
  for (int i = 0; i < static_cast<int>(m.size()); ++i) {
    const double v = static_cast<double>(m.data()[i]);
    if (!(std::isfinite(v) && v >= 0.0))
      return invalid(field, m.size() > 1 ? i : -1, v, ">= 0 and finite");
  }
  return {};
}

/// First entry that is not strictly positive and finite, or ok.
template <typename Derived>
inline ValidationError check_positive(const char* field, const Derived& m) noexcept {
  for (int i = 0; i < static_cast<int>(m.size()); ++i) {
    const double v = static_cast<double>(m.data()[i]);
    if (!(std::isfinite(v) && v > 0.0))
      return invalid(field, m.size() > 1 ? i : -1, v, "> 0 and finite");
  }
  return {};
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

inline ValidationError check_non_negative_scalar(const char* field, double v) noexcept {
  if (!(std::isfinite(v) && v >= 0.0)) return invalid(field, -1, v, ">= 0 and finite");
  return {};
}

}  // namespace detail
}  // namespace neurov
