// The sinusoidal forces and moments of SimulationConfig::disturbances, each
// amplitude * sin(2 pi frequency (t - start) + phase) in one body DOF from
// its start on (held over no interval: evaluated at each substep's start).
#pragma once

#include <cmath>

#include "neurov/sim/disturbances/part.hpp"

namespace neurov::parts {

template <typename Scalar>
struct Sinusoids : PartDefaults<Scalar> {
  struct State {};

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    for (std::size_t i = 0; i < c.disturbances.size(); ++i) {
      const auto& d = c.disturbances[i];
      if (d.dof < 0 || d.dof > 5)
        return detail::invalid("disturbances.dof", static_cast<int>(i), d.dof, "0..5");
      if (!(std::isfinite(d.amplitude) && std::isfinite(d.phase) && std::isfinite(d.start)))
        return detail::invalid("disturbances", static_cast<int>(i), std::nan(""),
                               "finite amplitude, phase and start");
      if (!(std::isfinite(d.frequency) && d.frequency >= Scalar(0)))
        return detail::invalid("disturbances.frequency", static_cast<int>(i),
                               static_cast<double>(d.frequency), ">= 0 and finite");
    }
    return {};
  }

  template <typename C>
  static void force(const C& c, const State&, const Plant<Scalar>&, Substep<Scalar>& s) noexcept {
    for (const auto& d : c.disturbances)
      if (s.t >= d.start)
        s.force(d.dof) += d.amplitude * std::sin(kTwoPi * d.frequency * (s.t - d.start) + d.phase);
  }

 private:
  static constexpr Scalar kTwoPi = Scalar(6.283185307179586);
};

}  // namespace neurov::parts
