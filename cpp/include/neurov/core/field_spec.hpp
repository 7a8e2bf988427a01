// A configuration struct's fields described once, next to the struct: name,
// member, unit, the rule its value must satisfy and its meaning (and, for a
// parameter set such as ArduSub's, its default and documented range). From
// this one list come the Python binding of the struct (its checked setters
// and docstrings, python/bindings/fields.hpp), the scenario files' keys and
// their did-you-mean, the simple part of the validator (check_fields) and the
// docs' tables (neurov fields). A struct is described by an overload
//   auto config_fields(const Config<Scalar>*) noexcept { return std::make_tuple(...); }
// found by argument-dependent lookup.
#pragma once

#include <limits>
#include <tuple>
#include <type_traits>

#include "neurov/core/validation.hpp"

namespace neurov {

/// The rule a number or vector field must satisfy, checked by check_fields
/// with the messages of validation.hpp and shown in its docstring.
enum class Check : unsigned char {
  none,          ///< anything (or checked by the struct's own validator)
  finite,        ///< "finite"
  non_negative,  ///< ">= 0 and finite"
  positive,      ///< "> 0 and finite"
  step,          ///< "> 0 and <= 10 s (neurov::kMaxStep)": a time step
};

/// The rule as the docs write it ("" for none).
constexpr const char* check_text(Check c) noexcept {
  switch (c) {
    case Check::finite: return "finite";
    case Check::non_negative: return ">= 0";
    case Check::positive: return "> 0";
    case Check::step: return "> 0 and <= 10 s";
    default: return "";
  }
}

/// Ways Python may give a field besides its own type.
enum FieldFlag : unsigned {
  kNumberFills = 1u,  ///< a fixed-size vector also set from one number (every entry)
  kDiagonal = 2u,     ///< a square matrix also set from its diagonal (a vector)
  kRequired = 4u,     ///< no usable default: files and keyword constructors must give it
  kKeywordOnly = 8u,  ///< by name only in a keyword constructor, as every field after it
};

/// One field of Config: its Python/TOML name, the member, its meaning, its
/// unit ("" for none), its rule, and for a parameter set whose defaults the
/// list gives (ArduSub's) the default and the documented range [min, max].
template <typename Config, typename D>
struct FieldSpec {
  using Type = D;
  const char* name;
  D Config::*member;
  const char* doc;
  const char* unit = "";
  Check check = Check::none;
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  /// The struct's default when the list sets it (NaN: the member's initialiser).
  double default_value = std::numeric_limits<double>::quiet_NaN();
  unsigned flags = 0;

  /// The same with the documented range [lo, hi] (the readers refuse a
  /// count outside it before it reaches the struct).
  constexpr FieldSpec within(double lo, double hi) const noexcept {
    FieldSpec s = *this;
    s.min = lo;
    s.max = hi;
    return s;
  }
};

/// A FieldSpec of Config for a member that may be declared in a base of it
/// (SlidingGains' lambda and kd).
template <typename Config, typename D, typename Owner>
constexpr FieldSpec<Config, D> field_spec(const char* name, D Owner::*member,
                                          const char* doc) noexcept {
  FieldSpec<Config, D> s{name, static_cast<D Config::*>(member), doc};
  return s;
}

/// The same with its unit and rule.
template <typename Config, typename D, typename Owner>
constexpr FieldSpec<Config, D> field_spec(const char* name, D Owner::*member, const char* unit,
                                          Check check, const char* doc,
                                          unsigned flags = 0) noexcept {
  FieldSpec<Config, D> s{name, static_cast<D Config::*>(member), doc};
  s.unit = unit;
  s.check = check;
  s.flags = flags;
  return s;
}

/// A parameter of a set whose list gives its defaults (ArduSub's): default,
/// documented range, unit; checked finite, and >= 0 when its range is.
template <typename Config, typename D>
constexpr FieldSpec<Config, D> parameter_spec(const char* name, D Config::*member,
                                              double default_value, double min, double max,
                                              const char* unit, const char* doc) noexcept {
  FieldSpec<Config, D> s{name, member, doc};
  s.unit = unit;
  s.check = min >= 0 ? Check::non_negative : Check::finite;
  s.min = min;
  s.max = max;
  s.default_value = default_value;
  return s;
}

namespace detail {

template <typename D>
ValidationError check_value(const char* name, const D& v, Check c) noexcept {
  if constexpr (std::is_floating_point_v<D>) {
    const double x = static_cast<double>(v);
    switch (c) {
      case Check::finite:
        return std::isfinite(x) ? ValidationError{} : invalid(name, -1, x, "finite");
      case Check::non_negative: return check_non_negative_scalar(name, x);
      case Check::positive: return check_positive_scalar(name, x);
      case Check::step: return check_step(name, x);
      default: return {};
    }
  } else if constexpr (std::is_base_of_v<Eigen::MatrixBase<D>, D>) {
    switch (c) {
      case Check::finite: return check_finite(name, v);
      case Check::non_negative: return check_non_negative(name, v);
      case Check::positive: return check_positive(name, v);
      default: return {};
    }
  } else {
    return {};
  }
}

}  // namespace detail

/// Each described field's rule, in the order of the list: the first error.
/// Allocation-free; a struct's validator calls it for what its rules say.
template <typename Config>
ValidationError check_fields(const Config& c) noexcept {
  ValidationError e{};
  std::apply(
      [&](const auto&... s) {
        (void)((e = detail::check_value(s.name, c.*(s.member), s.check), !e) && ...);
      },
      config_fields(static_cast<const Config*>(nullptr)));
  return e;
}

}  // namespace neurov
