// The current of CurrentModel::gauss_markov (GaussMarkovCurrent, on the
// run's RandomStream::current): held over the control period, advanced once
// at its end, so its realisation does not depend on the substeps.
#pragma once

#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/flags.hpp"
#include "neurov/sim/gauss_markov_current.hpp"

namespace neurov::parts {

template <typename Scalar>
struct GaussMarkovFlow : PartDefaults<Scalar> {
  struct State {
    GaussMarkovCurrent<Scalar> process;
  };

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    if (c.current_model != CurrentModel::constant && c.current_model != CurrentModel::gauss_markov)
      return detail::invalid("current_model", -1, static_cast<double>(c.current_model),
                             "constant or gauss_markov");
    if (c.current_model != CurrentModel::gauss_markov) return {};
    // One current model at a time: the constant model's fields stay zero.
    if (!(c.current.isZero(Scalar(0)) && c.current_amplitude.isZero(Scalar(0)) &&
          c.current_steps.empty()))
      return detail::invalid("current_model", -1, static_cast<double>(c.current_model),
                             "zero current, current_amplitude and no current_steps with "
                             "gauss_markov");
    return neurov::validate(c.gauss_markov_current);
  }

  template <typename C>
  static void reset(const C& c, State& s, std::uint64_t seed, const Plant<Scalar>&) noexcept {
    if (c.current_model == CurrentModel::gauss_markov)
      GaussMarkovCurrent<Scalar>::create(c.gauss_markov_current, seed, s.process);
  }

  template <typename C>
  static void current(const C& c, const State& s, Substep<Scalar>& sub) noexcept {
    if (c.current_model == CurrentModel::gauss_markov) sub.current = s.process.velocity();
  }

  template <typename C>
  static void advance(const C& c, State& s, Scalar dt) noexcept {
    if (c.current_model == CurrentModel::gauss_markov) s.process.advance(dt);
  }
};

}  // namespace neurov::parts
