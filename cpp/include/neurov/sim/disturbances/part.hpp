// What a disturbance part is: one source of force or flow on the plant (a
// sinusoidal force, a current model, the waves, payload events, thruster
// failures, a tether) with its validation, its state, its reset from its own
// random stream, what it adds over a substep and what it logs.
//
// A part is a class template on the scalar with static hooks over
// (configuration, state, ...) and a `State` it does not hold itself: the law
// is shared and the state lives where the caller puts it. Simulator holds one
// State per part (PartList::States); a batch of runs holds an array of them
// per part and calls the same hooks lane by lane. A part overrides only the
// hooks it needs (PartDefaults gives the others, which do nothing). A part
// configured by a scenario table of its own names it `kTable`: the
// SimulationConfig field of that name (an optional struct for [table], a
// list of structs for [[table]]), described with config_fields beside the
// part; the scenario reader (neurov/config/sea.py) reads every such table
// generically. A part whose struct is its own names it `Settings`, with its
// Python class name and docstring (kSettingsClass, kSettingsDoc): the
// bindings bind it from its description. A new part is then its header and
// config.hpp (its include, its field in SimulationConfig and that field's
// description, its line in DisturbanceParts).
//
// The hooks, in the order Simulator::step calls them (PartList calls each
// hook on every part in the order of the list, see DisturbanceParts in
// config.hpp):
//   validate(c)                   the part's fields of SimulationConfig
//   create(c, vehicle, state)     once, before the run: allocates, checks
//                                 what needs the vehicle
//   reset(c, state, seed, plant)  t = 0, from the run's seed; no allocation
//   period(c, state, t, plant)    at t_k, before the row is logged
//   current(c, state, s)          the current at s.t into s.current
//   force(c, state, plant, s)     body forces over s added to s.force
//   log(c, state, row, result)    the part's own columns of row k
//   follow(c, state, plant, tau, row)  at t_k, the force that will act known
//   substep(c, state, plant, s)   at a substep's start: events due by s.t
//   flow(c, state, plant, s)      the flow the RK4 step meets (s.in_flow)
//   advance(c, state, dt)         at the end of the control period
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <tuple>

#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/flow.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/result.hpp"
#include "neurov/sim/waves.hpp"

namespace neurov {

template <typename Scalar>
struct SimulationConfig;

namespace parts {

/// The plant as the parts see it: the vehicle (payload events rebuild it),
/// the vehicle at t = 0, the thrusters (failures), the state.
template <typename Scalar>
struct Plant {
  Vehicle<Scalar>& vehicle;
  const Vehicle<Scalar>& vehicle0;
  Thrusters<Scalar>& thrusters;
  const Vector6<Scalar>& eta;
  const Vector6<Scalar>& nu;
};

/// What the parts give over one substep [t, t + h) that starts `offset`
/// into its control period (or, with h = 0, at a row's instant t_k).
template <typename Scalar>
struct Substep {
  Scalar t = Scalar(0);
  Scalar offset = Scalar(0);
  Scalar h = Scalar(0);
  Vector3<Scalar> current = Vector3<Scalar>::Zero();  ///< NED, uniform [m/s]
  /// The waves' field (evaluate() anywhere), or nullptr in a calm sea.
  const Waves<Scalar>* waves = nullptr;
  Vector6<Scalar> force = Vector6<Scalar>::Zero();  ///< body force and moment
  /// With in_flow, the RK4 step meets the flow start/mid/end (current and
  /// waves) rather than the uniform `current`.
  bool in_flow = false;
  FluidFlow<Scalar> start, mid, end;
  std::uint8_t faults = 0;  ///< fault_bits seen over the substep
  bool vehicle_changed = false;  ///< a part rebuilt the plant's vehicle at the substep's start
};

/// The hooks a part leaves alone (see the top of the file).
template <typename Scalar>
struct PartDefaults {
  using Config = SimulationConfig<Scalar>;
  using Vec6 = Vector6<Scalar>;
  template <typename C>
  static ValidationError validate(const C&) noexcept {
    return {};
  }
  template <typename C, typename S>
  static ValidationError create(const C&, const Vehicle<Scalar>&, S&) {
    return {};
  }
  template <typename C, typename S>
  static void reset(const C&, S&, std::uint64_t, const Plant<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void period(const C&, S&, Scalar, const Plant<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void current(const C&, const S&, Substep<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void force(const C&, const S&, const Plant<Scalar>&, Substep<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void log(const C&, const S&, Eigen::Index, SimulationResult<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void follow(const C&, S&, const Plant<Scalar>&, const Vec6&,
                     const Substep<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void substep(const C&, S&, const Plant<Scalar>&, Substep<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void flow(const C&, const S&, const Plant<Scalar>&, Substep<Scalar>&) noexcept {}
  template <typename C, typename S>
  static void advance(const C&, S&, Scalar) noexcept {}
};

/// The parts of a run, each hook called on them in this order.
template <typename Scalar, template <typename> class... Parts>
struct PartList {
  using Config = SimulationConfig<Scalar>;
  using States = std::tuple<typename Parts<Scalar>::State...>;
  using Vec6 = Vector6<Scalar>;

  /// The first part's error, in the order of the list.
  static ValidationError validate(const Config& c) {
    ValidationError e{};
    (void)((e = Parts<Scalar>::validate(c), !e) && ...);
    return e;
  }
  static ValidationError create(const Config& c, const Vehicle<Scalar>& v, States& s) {
    ValidationError e{};
    (void)((e = Parts<Scalar>::create(c, v, std::get<typename Parts<Scalar>::State>(s)), !e) &&
           ...);
    return e;
  }
  static void reset(const Config& c, States& s, std::uint64_t seed,
                    const Plant<Scalar>& p) noexcept {
    (Parts<Scalar>::reset(c, get<Parts>(s), seed, p), ...);
  }
  /// Row k at t_k: the events due, then the current and the forces there
  /// (the row's logged disturbance and current), then each part's columns.
  static Substep<Scalar> row(const Config& c, States& s, Scalar t, const Plant<Scalar>& p,
                             Eigen::Index row, SimulationResult<Scalar>& r) noexcept {
    (Parts<Scalar>::period(c, get<Parts>(s), t, p), ...);
    Substep<Scalar> at;
    at.t = t;
    (Parts<Scalar>::current(c, get<Parts>(s), at), ...);
    (Parts<Scalar>::force(c, get<Parts>(s), p, at), ...);
    r.disturbance.row(row) = at.force.transpose();
    r.current.row(row) = at.current.transpose();
    (Parts<Scalar>::log(c, get<Parts>(s), row, r), ...);
    return at;
  }
  /// With the force `tau` that acts over the control period known.
  static void follow(const Config& c, States& s, const Plant<Scalar>& p, const Vec6& tau,
                     const Substep<Scalar>& row) noexcept {
    (Parts<Scalar>::follow(c, get<Parts>(s), p, tau, row), ...);
  }
  /// What the substep [t, t + h), `offset` into its period, meets.
  static Substep<Scalar> substep(const Config& c, States& s, Scalar t, Scalar offset, Scalar h,
                                 const Plant<Scalar>& p) noexcept {
    Substep<Scalar> sub;
    sub.t = t;
    sub.offset = offset;
    sub.h = h;
    (Parts<Scalar>::substep(c, get<Parts>(s), p, sub), ...);
    (Parts<Scalar>::current(c, get<Parts>(s), sub), ...);
    (Parts<Scalar>::flow(c, get<Parts>(s), p, sub), ...);
    (Parts<Scalar>::force(c, get<Parts>(s), p, sub), ...);
    return sub;
  }
  static void advance(const Config& c, States& s, Scalar dt) noexcept {
    (Parts<Scalar>::advance(c, get<Parts>(s), dt), ...);
  }

 private:
  template <template <typename> class P>
  static typename P<Scalar>::State& get(States& s) noexcept {
    return std::get<typename P<Scalar>::State>(s);
  }
};

}  // namespace parts
}  // namespace neurov
