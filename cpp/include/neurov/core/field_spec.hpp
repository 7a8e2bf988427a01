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
