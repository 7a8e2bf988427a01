// A ROV's umbilical from a surface point to the vehicle, as a quasi-static
// straight line (docs/disturbances.md, "The tether"): from the anchor A (NED)
// to the attachment point P = p + R r_a (r_a in body axes), of straight length
// L = |P - A| and direction e = (P - A) / L. The normal drag per unit length of
// the fluid velocity relative to the cable, whose own motion is not modelled
// (u: the current and the waves' orbital velocity at the point),
//   f(s) = 1/2 rho C_d d |u_n| u_n,   u_n = u - (u . e) e,
// is integrated along the line by Gauss-Legendre quadrature with kPoints
// points, and half of the line's total drag acts at the vehicle's attachment
// point (force and its moment about the body origin): the lumped split of a
// segment's load between its two end nodes of lumped-mass cable models, with
// the whole line as one segment; for a uniform load it is also the reaction
// of a straight line held at both ends. Slack (a `length` longer than the
// straight distance) is not modelled: the line is taken straight.
#pragma once

#include <cmath>
#include <optional>

#include "neurov/core/field_spec.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/sim/disturbances/part.hpp"

namespace neurov {

/// The fields of the scenario file's [tether] table.
template <typename Scalar>
struct TetherConfig {
  Scalar diameter = Scalar(0);            ///< d [m], > 0 (no default: the cable's own)
  Scalar drag_coefficient = Scalar(1.2);  ///< C_d of the normal flow, >= 0 (a circular cylinder)
  Vector3<Scalar> anchor = Vector3<Scalar>::Zero();      ///< A, NED [m]
  Vector3<Scalar> attachment = Vector3<Scalar>::Zero();  ///< r_a, body axes [m]
  /// The cable's length [m]; 0: the straight distance at t = 0. Not shorter
  /// than that distance; the extra is slack, which is not modelled.
  Scalar length = Scalar(0);
};

template <typename Scalar>
auto config_fields(const TetherConfig<Scalar>*) noexcept {
  using C = TetherConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("diameter", &C::diameter, "m", Check::positive, "d, the cable's diameter"),
      field_spec<C>("drag_coefficient", &C::drag_coefficient, "", Check::non_negative,
                    "C_d of the flow normal to the cable"),
      field_spec<C>("anchor", &C::anchor, "m", Check::finite, "The surface end, NED (3,)"),
      field_spec<C>("attachment", &C::attachment, "m", Check::finite, "The vehicle end, body axes (3,)"),
      field_spec<C>("length", &C::length, "m", Check::non_negative,
                    "The cable's length; 0: the straight distance at t = 0, which it may not be "
                    "shorter than (slack is not modelled)"));
}

namespace parts {

template <typename Scalar>
struct Tether : PartDefaults<Scalar> {
  /// Its scenario table [tether]: SimulationConfig's field of the same name.
  static constexpr const char* kTable = "tether";
  using Settings = TetherConfig<Scalar>;
  static constexpr const char* kSettingsClass = "TetherConfig";
  static constexpr const char* kSettingsDoc =
      "A ROV's umbilical from a surface anchor to the vehicle: a quasi-static straight line "
      "whose normal drag, integrated along it, acts half at the vehicle's attachment point.";
  using Vec3 = Vector3<Scalar>;
  struct State {};
  static constexpr int kPoints = 4;

  template <typename C>
  static ValidationError validate(const C& c) noexcept {
    if (!c.tether) return {};
    const TetherConfig<Scalar>& t = *c.tether;
    const auto d = [](Scalar v) { return static_cast<double>(v); };
    if (auto e = detail::check_positive_scalar("tether.diameter", d(t.diameter))) return e;
    if (auto e = detail::check_non_negative_scalar("tether.drag_coefficient",
                                                   d(t.drag_coefficient)))
      return e;
    if (auto e = detail::check_finite("tether.anchor", t.anchor)) return e;
    if (auto e = detail::check_finite("tether.attachment", t.attachment)) return e;
    if (auto e = detail::check_non_negative_scalar("tether.length", d(t.length))) return e;
    const Scalar reach = (point(t, c.eta0) - t.anchor).norm();
    if (t.length > Scalar(0) && t.length < reach)
      return detail::invalid("tether.length", -1, d(t.length),
                             ">= the straight distance from the anchor to the attachment at t = 0");
    return {};
  }

  /// Split from drag() so that a run without a tether pays a test, not a call.
  template <typename C>
  static void force(const C& c, const State&, const Plant<Scalar>& p,
                    Substep<Scalar>& s) noexcept {
    if (c.tether) drag(*c.tether, c.water_density, p, s);
  }

 private:
  static void drag(const TetherConfig<Scalar>& t, Scalar water_density, const Plant<Scalar>& p,
                   Substep<Scalar>& s) noexcept {
    const Matrix3<Scalar> r = rotation(EulerTrig<Scalar>::from_pose(p.eta));
    const Vec3 line = p.eta.template head<3>() + r * t.attachment - t.anchor;
    const Scalar length = line.norm();
    if (!(length > Scalar(0))) return;
    const Vec3 e = line / length;
    Vec3 sum = Vec3::Zero();  // sum of w_i |u_n| u_n at the nodes
    for (int i = 0; i < kPoints; ++i) {
      const Scalar along = length * (Scalar(1) + Scalar(kNodes[i])) / Scalar(2);
      Vec3 u = s.current;
      if (s.waves != nullptr) {
        WaveKinematics<Scalar> k;
        s.waves->evaluate(static_cast<double>(s.t), t.anchor + along * e, k);
        u += k.velocity;
      }
      const Vec3 normal = u - u.dot(e) * e;
      sum += Scalar(kWeights[i]) * normal.norm() * normal;
    }
    // The line's drag (1/2 rho C_d d) (L / 2) sum; half of it at the vehicle.
    const Vec3 ned = (water_density * t.drag_coefficient * t.diameter * length / Scalar(8)) * sum;
    const Vec3 body = r.transpose() * ned;
    s.force.template head<3>() += body;
    s.force.template tail<3>() += t.attachment.cross(body);
  }

  /// Gauss-Legendre nodes and weights on [-1, 1]: exact for a polynomial
  /// load of degree <= 7 (a uniform current gives a constant one).
  static constexpr double kNodes[kPoints] = {-0.8611363115940526, -0.3399810435848563,
                                             0.3399810435848563, 0.8611363115940526};
  static constexpr double kWeights[kPoints] = {0.34785484513745385, 0.6521451548625461,
                                               0.6521451548625461, 0.34785484513745385};

  /// The attachment point in NED at the pose eta.
  static Vec3 point(const TetherConfig<Scalar>& t, const Vector6<Scalar>& eta) noexcept {
    return eta.template head<3>() + rotation(EulerTrig<Scalar>::from_pose(eta)) * t.attachment;
  }
};

}  // namespace parts
}  // namespace neurov
