// The thruster failures of SimulationConfig::thruster_failures: thruster
// `index` at `efficiency` from the first substep at or after `time` on.
#pragma once

#include <vector>

#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/flags.hpp"

namespace neurov::parts {

template <typename Scalar>
struct ThrusterFailures : PartDefaults<Scalar> {
  struct State {
    std::vector<bool> applied;  ///< sized by create(), so reset allocates nothing
  };

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    for (std::size_t i = 0; i < c.thruster_failures.size(); ++i) {
      const auto& f = c.thruster_failures[i];
      if (!c.use_thrusters)
        return detail::invalid("thruster_failures", static_cast<int>(i), std::nan(""),
                               "a thruster configuration");
      if (f.index < 0 || f.index >= c.thrusters.matrix.cols())
        return detail::invalid("thruster_failures.index", static_cast<int>(i), f.index,
                               "a thruster index");
      if (!(f.efficiency >= Scalar(0) && f.efficiency <= Scalar(1)))
        return detail::invalid("thruster_failures.efficiency", static_cast<int>(i),
                               static_cast<double>(f.efficiency), "in [0, 1]");
      if (!std::isfinite(f.time))
        return detail::invalid("thruster_failures.time", static_cast<int>(i),
                               static_cast<double>(f.time), "finite");
    }
    return {};
  }

  template <typename C>
  static ValidationError create(const C& c, const Vehicle<Scalar>&, State& s) {
    s.applied.assign(c.thruster_failures.size(), false);
    return {};
  }

  template <typename C>
  static void reset(const C&, State& s, std::uint64_t, const Plant<Scalar>&) noexcept {
    std::fill(s.applied.begin(), s.applied.end(), false);
  }

  /// The failures due by the substep's start; the fault bit is checked per
  /// substep, where a failure or repair takes effect, so that it describes
  /// the same interval as the row's thrusts and tau_applied.
  template <typename C>
  static void substep(const C& c, State& s, const Plant<Scalar>& p, Substep<Scalar>& sub) noexcept {
    if (!c.use_thrusters) return;
    for (std::size_t f = 0; f < c.thruster_failures.size(); ++f) {
      const auto& failure = c.thruster_failures[f];
      if (!s.applied[f] && sub.t >= failure.time) {
        p.thrusters.set_efficiency(failure.index, failure.efficiency);
        s.applied[f] = true;
      }
    }
    if ((p.thrusters.efficiency().array() < Scalar(1)).any()) sub.faults |= fault_bits::thruster;
  }
};

}  // namespace neurov::parts
