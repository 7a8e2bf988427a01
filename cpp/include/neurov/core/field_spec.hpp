// A configuration struct's fields described once, next to the struct: name,
// member and meaning. The Python bindings bind a controller's configuration
// from this list field by field (python/bindings/control/generic_controller.hpp)
// and the scenario files read the same names, so a controller that describes
// its configuration this way needs no binding code of its own.
#pragma once

#include <tuple>

namespace neurov {

/// One field of Config: its Python/TOML name, the member, its documentation.
template <typename Config, typename D>
struct FieldSpec {
  using Type = D;
  const char* name;
  D Config::*member;
  const char* doc;
};

/// A FieldSpec of Config for a member that may be declared in a base of it
/// (SlidingGains' lambda and kd).
template <typename Config, typename D, typename Owner>
constexpr FieldSpec<Config, D> field_spec(const char* name, D Owner::*member,
                                          const char* doc) noexcept {
  return {name, static_cast<D Config::*>(member), doc};
}

}  // namespace neurov

namespace neurov {

/// One number of a parameter set described once with everything a user
/// reads about it: its name (the firmware's own, e.g. ArduSub's
/// "ATC_RAT_RLL_P"), the member, its default, the documented range
/// [min, max], its unit and its meaning. The struct's defaults, the bindings,
/// the readers' range warnings and the docs table all come from one list.
template <typename Config, typename D>
struct ParamSpec {
  using Type = D;
  const char* name;
  D Config::*member;
  double default_value;
  double min;
  double max;
  const char* unit;
  const char* doc;
};

}  // namespace neurov
