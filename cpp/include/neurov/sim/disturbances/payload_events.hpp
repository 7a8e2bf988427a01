// The payload events of SimulationConfig::payload: the plant's Vehicle
// rebuilt in place at the first substep at or after each event's time (the
// controller is not told); logs the mass picked up so far.
#pragma once

#include <vector>

#include "neurov/sim/disturbances/part.hpp"
#include "neurov/sim/payload.hpp"

namespace neurov::parts {

template <typename Scalar>
struct PayloadEvents : PartDefaults<Scalar> {
  /// Its scenario tables [[payload]]: SimulationConfig's list of the same name.
  static constexpr const char* kTable = "payload";
  struct State {
    std::vector<bool> applied;  ///< sized by create(), so reset allocates nothing
    Scalar mass = Scalar(0);
  };

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    for (std::size_t i = 0; i < c.payload.size(); ++i) {
      const Scalar t = c.payload[i].time;
      if (!(std::isfinite(t) && t >= Scalar(0) && (i == 0 || t >= c.payload[i - 1].time)))
        return detail::invalid("payload.time", static_cast<int>(i), static_cast<double>(t),
                               ">= 0, finite and non-decreasing");
    }
    return {};
  }

  /// Each event against the vehicle it changes (validate_payload).
  template <typename C>
  static ValidationError create(const C& c, const Vehicle<Scalar>& vehicle, State& s) {
    if (auto e = validate_payload(c.payload, vehicle)) return e;
    s.applied.assign(c.payload.size(), false);
    return {};
  }

  template <typename C>
  static void reset(const C&, State& s, std::uint64_t, const Plant<Scalar>& p) noexcept {
    p.vehicle = p.vehicle0;
    std::fill(s.applied.begin(), s.applied.end(), false);
    s.mass = Scalar(0);
  }

  template <typename C>
  static void period(const C& c, State& s, Scalar t, const Plant<Scalar>& p) noexcept {
    apply_due(c, s, t, p);
  }

  template <typename C>
  static void substep(const C& c, State& s, const Plant<Scalar>& p, Substep<Scalar>& sub) noexcept {
    if (apply_due(c, s, sub.t, p)) sub.vehicle_changed = true;
  }

  template <typename C>
  static void log(const C&, const State& s, Eigen::Index row, SimulationResult<Scalar>& r) noexcept {
    r.payload_mass(row) = s.mass;
  }

 private:
  /// The events due by t applied to the plant's vehicle, in order
  /// (Simulator::create checked that each gives a valid vehicle); whether
  /// any was.
  template <typename C>
  static bool apply_due(const C& c, State& s, Scalar t, const Plant<Scalar>& p) noexcept {
    bool any = false;
    for (std::size_t i = 0; i < c.payload.size(); ++i) {
      if (s.applied[i] || !(t >= c.payload[i].time)) continue;
      apply_payload(c.payload[i], p.vehicle, p.vehicle);
      s.mass += c.payload[i].mass;
      s.applied[i] = true;
      any = true;
    }
    return any;
  }
};

}  // namespace neurov::parts
