// Changes of the vehicle that its controller is not told about: a payload
// picked up or dropped, buoyancy gained or lost (a flooded or a dropped
// float), and a different damping and added mass (a model mismatch from a
// given time on). An event turns one valid VehicleParameters into another;
// the simulator then builds a new Vehicle from it, so the mass matrix, not
// only the weight, changes.
#pragma once

#include <cmath>
#include <optional>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/sea_constants.hpp"

namespace neurov {

/// The fields of the scenario file's [[payload]] entries.
template <typename Scalar>
struct PayloadEvent {
  Scalar time = Scalar(0);      ///< when it happens [s]
  /// Mass added [kg] (negative: dropped); the weight changes by mass * g
  /// with g = standard_gravity.
  Scalar mass = Scalar(0);
  /// Where the added (or dropped) mass sits, body axes [m], taken as a
  /// point mass: r_g and the inertia about the origin move with it. Empty:
  /// at the vehicle's centre of gravity, which then stays where it was.
  std::optional<Vector3<Scalar>> mass_position{};
  Scalar buoyancy = Scalar(0);  ///< buoyancy added [N] (negative: lost)
  /// Where the added buoyancy acts, body axes [m]; r_b moves to the
  /// buoyancy-weighted mean. Empty: at the centre of buoyancy.
  std::optional<Vector3<Scalar>> buoyancy_position{};
  /// Factors on the linear and the quadratic damping of each DOF.
  Vector6<Scalar> damping_scale = Vector6<Scalar>::Ones();
  /// Factor on the whole added-mass matrix M_A.
  Scalar added_mass_scale = Scalar(1);
};

template <typename Scalar>
auto config_fields(const PayloadEvent<Scalar>*) noexcept {
  using C = PayloadEvent<Scalar>;
  return std::make_tuple(
      field_spec<C>("time", &C::time, "s", Check::non_negative, "When it happens"),
      field_spec<C>("mass", &C::mass, "kg", Check::finite,
                    "Mass added (negative: dropped; the vehicle keeps m + mass > 0); weight mass * 9.81"),
      field_spec<C>("mass_position", &C::mass_position, "m", Check::none,
                    "Where the mass sits, body axes (3,); None: the centre of gravity"),
      field_spec<C>("buoyancy", &C::buoyancy, "N", Check::finite,
                    "Buoyancy added (negative: lost; the vehicle keeps B + buoyancy >= 0)"),
      field_spec<C>("buoyancy_position", &C::buoyancy_position, "m", Check::none,
                    "Where it acts, body axes (3,); None: the centre of buoyancy"),
      field_spec<C>("damping_scale", &C::damping_scale, "", Check::non_negative,
                    "Factors on the linear and quadratic damping per DOF (6,)"),
      field_spec<C>("added_mass_scale", &C::added_mass_scale, "", Check::non_negative,
                    "Factor on the added-mass matrix"));
}

namespace detail {

template <typename Scalar>
inline ValidationError check_payload_fields(const PayloadEvent<Scalar>& e,
                                            const VehicleParameters<Scalar>& before) noexcept {
  const auto d = [](Scalar v) { return static_cast<double>(v); };
  if (auto err = check_non_negative_scalar("time", d(e.time))) return err;
  if (!std::isfinite(d(e.mass))) return invalid("mass", -1, d(e.mass), "finite");
  if (!(before.mass + e.mass > Scalar(0)))
    return invalid("mass", -1, d(e.mass),
                   "> -(the vehicle's mass): the vehicle must keep a mass > 0");
  // value_or: a copy GCC can see initialised (with *opt it warns
  // -Wmaybe-uninitialized through Eigen's loops).
  const Vector3<Scalar> zero = Vector3<Scalar>::Zero();
  if (auto err = check_finite("mass_position", e.mass_position.value_or(zero))) return err;
  if (!std::isfinite(d(e.buoyancy))) return invalid("buoyancy", -1, d(e.buoyancy), "finite");
  if (!(before.buoyancy + e.buoyancy >= Scalar(0)))
    return invalid("buoyancy", -1, d(e.buoyancy),
                   ">= -(the vehicle's buoyancy): the vehicle must keep a buoyancy >= 0");
  if (auto err = check_finite("buoyancy_position", e.buoyancy_position.value_or(zero))) return err;
  if (auto err = check_non_negative("damping_scale", e.damping_scale)) return err;
  if (auto err = check_non_negative_scalar("added_mass_scale", d(e.added_mass_scale))) return err;
  return {};
}

/// The changed parameters, for fields that check_payload_fields accepted.
template <typename Scalar>
inline VehicleParameters<Scalar> changed_vehicle(const PayloadEvent<Scalar>& e,
                                                 const VehicleParameters<Scalar>& p) noexcept {
  VehicleParameters<Scalar> q = p;
  const Vector3<Scalar> r_m = e.mass_position.value_or(p.centre_of_gravity);
  q.mass = p.mass + e.mass;
  q.centre_of_gravity = (p.mass * p.centre_of_gravity + e.mass * r_m) / q.mass;
  // A point mass dm at r adds dm S(r)^T S(r) = dm (|r|^2 I - r r^T) to I_o.
  const Matrix3<Scalar> s = skew<Scalar>(r_m);
  q.inertia = p.inertia + e.mass * (s.transpose() * s);
  q.inertia = (Scalar(0.5) * (q.inertia + q.inertia.transpose())).eval();
  q.weight = p.weight + e.mass * static_cast<Scalar>(standard_gravity);
  q.buoyancy = p.buoyancy + e.buoyancy;
  if (e.buoyancy_position && q.buoyancy > Scalar(0))
    q.centre_of_buoyancy = (p.buoyancy * p.centre_of_buoyancy +
                            e.buoyancy * e.buoyancy_position.value_or(p.centre_of_buoyancy)) /
                           q.buoyancy;
  q.linear_damping = p.linear_damping.cwiseProduct(e.damping_scale);
  q.quadratic_damping = p.quadratic_damping.cwiseProduct(e.damping_scale);
  q.added_mass = e.added_mass_scale * p.added_mass;
  return q;
}

}  // namespace detail

/// Checks an event against the vehicle it will change: finite numbers, a
/// time >= 0, scales >= 0, and a vehicle left with mass > 0 and buoyancy
/// >= 0; then the changed vehicle as validate(VehicleParameters) does (a
/// dropped point mass can leave an inertia that is not positive definite).
template <typename Scalar>
inline ValidationError validate(const PayloadEvent<Scalar>& e,
                                const VehicleParameters<Scalar>& before) noexcept {
  if (auto err = detail::check_payload_fields(e, before)) return err;
  return validate(detail::changed_vehicle(e, before));
}

/// The vehicle after the event: `after` is written only when the event is
/// valid for `before` (the error is returned otherwise). Allocation-free.
template <typename Scalar>
inline ValidationError apply_payload(const PayloadEvent<Scalar>& e,
                                     const VehicleParameters<Scalar>& before,
                                     VehicleParameters<Scalar>& after) noexcept {
  if (auto err = detail::check_payload_fields(e, before)) return err;
  const VehicleParameters<Scalar> q = detail::changed_vehicle(e, before);
  if (auto err = validate(q)) return err;
  after = q;
  return {};
}

/// The vehicle after the event, built with Vehicle::create; `after` is
/// untouched on error. Allocation-free, so a simulator may call it mid-run.
template <typename Scalar>
inline ValidationError apply_payload(const PayloadEvent<Scalar>& e, const Vehicle<Scalar>& before,
                                     Vehicle<Scalar>& after) noexcept {
  if (!before.valid()) return detail::invalid("vehicle", -1, std::nan(""), "a valid vehicle");
  VehicleParameters<Scalar> q;
  if (auto err = apply_payload(e, before.parameters(), q)) return err;
  return Vehicle<Scalar>::create(q, after);
}

}  // namespace neurov
