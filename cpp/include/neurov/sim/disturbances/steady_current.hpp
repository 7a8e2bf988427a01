// The current of CurrentModel::constant: the mean `current`, the last of the
// `current_steps` due replacing it, plus current_amplitude sin(2 pi t /
// current_period); NED and uniform, evaluated at each substep's start.
#pragma once

#include <cmath>

#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/flags.hpp"

namespace neurov::parts {

template <typename Scalar>
struct SteadyCurrent : PartDefaults<Scalar> {
  struct State {};

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    if (auto e = detail::check_finite("current", c.current)) return e;
    if (auto e = detail::check_finite("current_amplitude", c.current_amplitude)) return e;
    if (auto e = detail::check_non_negative_scalar("current_period",
                                                   static_cast<double>(c.current_period)))
      return e;
    for (std::size_t i = 0; i < c.current_steps.size(); ++i) {
      if (!std::isfinite(c.current_steps[i].time) ||
          (i > 0 && !(c.current_steps[i].time > c.current_steps[i - 1].time)))
        return detail::invalid("current_steps.time", static_cast<int>(i),
                               static_cast<double>(c.current_steps[i].time),
                               "finite and strictly increasing");
      if (auto e = detail::check_finite("current_steps.velocity", c.current_steps[i].velocity))
        return e;
    }
    return {};
  }

  /// The current models are exclusive (GaussMarkovFlow::validate): the one
  /// of the run's model sets the current.
  template <typename C>
  static void current(const C& c, const State&, Substep<Scalar>& s) noexcept {
    if (c.current_model != CurrentModel::constant) return;
    Vector3<Scalar> v = c.current;
    for (const auto& step : c.current_steps)
      if (s.t >= step.time) v = step.velocity;
    if (c.current_period > Scalar(0))
      v += c.current_amplitude * std::sin(kTwoPi * s.t / c.current_period);
    s.current = v;
  }

 private:
  static constexpr Scalar kTwoPi = Scalar(6.283185307179586);
};

}  // namespace neurov::parts
