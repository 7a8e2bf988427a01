// Result codes of the real-time path. The hot path never throws: it returns one
// of these and always leaves finite numbers in its outputs.
#pragma once

#include <cstdint>

namespace neurov {

enum class Status : std::uint8_t {
  ok = 0,
  /// |cos(theta)| fell below the singularity threshold: pitch is at or near
  /// +-90 deg, where the Euler-angle transform T(phi, theta) is undefined.
  near_singularity = 1,
  /// An input (state, reference, command or time step) held NaN or +-Inf.
  non_finite_input = 2,
  /// An input was finite but outside what the function accepts (e.g. dt <= 0).
  invalid_argument = 3,
  /// The computation produced a non-finite number from finite inputs
  /// (overflow); the outputs were replaced by safe values.
  non_finite_output = 4,
};

/// Stable lower-case name of a status, for logs and for Python.
constexpr const char* to_string(Status status) noexcept {
  switch (status) {
    case Status::ok:
      return "ok";
    case Status::near_singularity:
      return "near_singularity";
    case Status::non_finite_input:
      return "non_finite_input";
    case Status::invalid_argument:
      return "invalid_argument";
    case Status::non_finite_output:
      return "non_finite_output";
  }
  return "unknown";
}

/// The first non-ok status wins: lets a function combine the statuses of the
/// steps it calls without branching on each.
constexpr Status worst(Status a, Status b) noexcept { return a != Status::ok ? a : b; }

}  // namespace neurov
