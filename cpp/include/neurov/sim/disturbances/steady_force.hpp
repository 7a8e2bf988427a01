// A steady force fixed in the earth frame: the mean pull of a wind on a
// surface float or mast, a surface drift, a steady cable or towing load, the
// mean second-order wave drift force. From `start` on, the force F (NED) acts
// at the body point r (body axes): in body axes R^T F, with the moment
// r x R^T F about the body origin, R the rotation of the pose at each
// substep's start. Allocation-free and deterministic; its own table
// [steady_force] in a scenario file.
#pragma once

#include <tuple>

#include "neurov/core/field_spec.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/sim/disturbances/part.hpp"

namespace neurov {

/// The fields of the scenario file's [steady_force] table.
template <typename Scalar>
struct SteadyForceConfig {
  Vector3<Scalar> force = Vector3<Scalar>::Zero();  ///< F, NED [N]
  Vector3<Scalar> point = Vector3<Scalar>::Zero();  ///< r, body axes [m]
  Scalar start = Scalar(0);                         ///< from when [s]
};

template <typename Scalar>
auto config_fields(const SteadyForceConfig<Scalar>*) noexcept {
  using C = SteadyForceConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("force", &C::force, "N", Check::finite, "The force, NED (3,)"),
      field_spec<C>("point", &C::point, "m", Check::finite, "Where it acts, body axes (3,)"),
      field_spec<C>("start", &C::start, "s", Check::non_negative, "From when it acts"));
}

namespace parts {

template <typename Scalar>
struct SteadyForce : PartDefaults<Scalar> {
  struct State {};
  /// Its scenario table [steady_force]: SimulationConfig's field of the same name.
  static constexpr const char* kTable = "steady_force";
  using Settings = SteadyForceConfig<Scalar>;
  static constexpr const char* kSettingsClass = "SteadyForceConfig";
  static constexpr const char* kSettingsDoc =
      "A steady force fixed in the earth frame (a wind's pull on a surface float, a surface "
      "drift, a towing load) acting at a body point from `start` on.";

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    return c.steady_force ? check_fields(*c.steady_force) : ValidationError{};
  }

  template <typename C>
  static void force(const C& c, const State&, const Plant<Scalar>& p, Substep<Scalar>& s) noexcept {
    if (!c.steady_force || s.t < c.steady_force->start) return;
    const Vector3<Scalar> body =
        rotation(EulerTrig<Scalar>::from_pose(p.eta)).transpose() * c.steady_force->force;
    s.force.template head<3>() += body;
    s.force.template tail<3>() += c.steady_force->point.cross(body);
  }
};

}  // namespace parts
}  // namespace neurov
