// The plant's right-hand side and its RK4 step for the common structure
// (r_g = 0, diagonal inertia, added mass and M^-1: NEROV and BlueROV2 Heavy),
// written once on a lane type V (core/lane_math.hpp). V = Scalar is one run:
// Vehicle::derivative and rk4_step take this path for such vehicles. V a
// vector is L runs in SIMD lanes: the batch (sim/batch.hpp, through
// model/plant_block.hpp). Every operation acts on each lane alone, so lane
// i of a batch gets the single run's numbers; where the vector copy is
// compiled for a wider unit, plant_block.hpp keeps the compiler from fusing
// multiplies and adds that the single run does apart.
//
//   eta_dot = J(eta) nu,
//   nu_dot  = M^-1 (tau - C(nu_r) nu_r - D(nu_r) nu_r - g(eta)) - [w x v_c; 0],
//
// nu_r = nu - [v_c; 0] in a uniform current v_c = R^T current_ned (see
// Vehicle::acceleration for why the whole model runs on nu_r).
#pragma once

#include <cstdint>
#include <cstring>

#include "neurov/core/config.hpp"
#include "neurov/core/lane_math.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/trig.hpp"
#include "neurov/core/vector_unit.hpp"
#include "neurov/model/kinematics.hpp"

namespace neurov {
namespace detail {

/// Where each of the plant's numbers sits in a coefficient array: mass,
/// inertia (3), added mass (6), M^-1 (6), linear and quadratic damping (6
/// each), W - B and the restoring moments' arms r_g W - r_b B (x, y, z).
namespace plant_coef {
inline constexpr int mass = 0, inertia = 1, added_mass = 4, m_inv = 10, linear = 16,
                     quadratic = 22, net_weight = 28, moment_x = 29, moment_y = 30, moment_z = 31,
                     count = 32;
}  // namespace plant_coef

/// The Euler angles' sines and cosines on each lane, and sec(theta) with the
/// clamp of EulerTrig (where |cos theta| is below the threshold: `singular`).
template <typename V>
struct TrigLanes {
  V sf, cf, st, ct, sp, cp, sec;
  MaskOf<V> singular;
};

/// sin and cos of float lanes through the double routine, as sincos(float)
/// does on a machine with hardware double: in two halves, so that each half's
/// doubles fill one register of the unit the float lanes fill (a vector of
/// doubles twice as wide would be split by the compiler, badly).
template <typename V>
NEUROV_ALWAYS_INLINE void sincos_of_lanes(const V& x, V& s, V& c) noexcept {
  if constexpr (kLanes<V> == 1) {
    sincos(x, s, c);
  } else if constexpr (std::is_same_v<LaneScalar<V>, double>) {
    sincos_lanes(x, s, c);
  } else {
    constexpr int H = kLanes<V> / 2;
    using FH = Vec<float, H>;
    using DH = Vec<double, H>;
    FH xf[2], sf[2], cf[2];
    std::memcpy(xf, &x, sizeof x);
    for (int k = 0; k < 2; ++k) {
      const DH xd = __builtin_convertvector(xf[k], DH);
      DH sd, cd;
      sincos_lanes(xd, sd, cd);
      sf[k] = __builtin_convertvector(sd, FH);
      cf[k] = __builtin_convertvector(cd, FH);
    }
    std::memcpy(&s, sf, sizeof s);
    std::memcpy(&c, cf, sizeof c);
  }
}

template <typename V>
NEUROV_ALWAYS_INLINE void trig_lanes(const V& phi, const V& theta, const V& psi, TrigLanes<V>& t) noexcept {
  using S = LaneScalar<V>;
  sincos_of_lanes(phi, t.sf, t.cf);
  sincos_of_lanes(theta, t.st, t.ct);
  sincos_of_lanes(psi, t.sp, t.cp);
  const V threshold = V{} + singularity_threshold<S>();
  V abs_ct, clamped;
  lane_abs(t.ct, abs_ct);
  lane_copysign(threshold, t.ct, clamped);
  t.singular = abs_ct < threshold;
  t.sec = t.singular ? S(1) / clamped : S(1) / t.ct;
}

/// The same numbers as an EulerTrig of one run.
template <typename S>
inline TrigLanes<S> trig_lanes(const EulerTrig<S>& e) noexcept {
  return {e.sin_phi, e.cos_phi,   e.sin_theta, e.cos_theta, e.sin_psi,
          e.cos_psi, e.sec_theta, e.status == Status::near_singularity};
}

/// What went wrong on each lane in one evaluation.
template <typename V>
struct PlantMasks {
  MaskOf<V> bad_input;   ///< a non-finite pose, velocity, force or current
  MaskOf<V> bad_output;  ///< a non-finite eta_dot or nu_dot
  MaskOf<V> singular;    ///< sec(theta) clamped
};

/// The right-hand side on each lane, coefficients `c` (plant_coef), the
/// Euler angles' trigonometry `t`, force tau (6) and NED current (3). With
/// kChecked, `masks` says which lanes had non-finite inputs or outputs (the
/// outputs of such a lane are unspecified); without, only `masks.singular`
/// is set.
template <bool kChecked, typename V>
NEUROV_ALWAYS_INLINE void plant_derivative(const V* c, const TrigLanes<V>& t, const V* eta,
                                          const V* nu, const V* tau, const V* current, V* eta_dot,
                                          V* nu_dot, PlantMasks<V>& masks) noexcept {
  namespace pc = plant_coef;
  using M = MaskOf<V>;
  M finite = M(V{} == V{});  // every lane
  if constexpr (kChecked) {
    for (int i = 0; i < 3; ++i) and_finite(finite, current[i]);
    for (int i = 0; i < 6; ++i) {
      and_finite(finite, eta[i]);
      and_finite(finite, nu[i]);
      and_finite(finite, tau[i]);
    }
  }

  // R = Rz(psi) Ry(theta) Rx(phi) and T(phi, theta) (kinematics.hpp).
  const V &sf = t.sf, &cf = t.cf, &st = t.st, &ct = t.ct, &sp = t.sp, &cp = t.cp;
  const V r00 = cp * ct, r01 = -sp * cf + cp * st * sf, r02 = sp * sf + cp * cf * st;
  const V r10 = sp * ct, r11 = cp * cf + sf * st * sp, r12 = -cp * sf + st * sp * cf;
  const V r20 = -st, r21 = ct * sf, r22 = ct * cf;
  const V tt = st * t.sec;
  eta_dot[0] = r00 * nu[0] + r01 * nu[1] + r02 * nu[2];
  eta_dot[1] = r10 * nu[0] + r11 * nu[1] + r12 * nu[2];
  eta_dot[2] = r20 * nu[0] + r21 * nu[1] + r22 * nu[2];
  eta_dot[3] = nu[3] + sf * tt * nu[4] + cf * tt * nu[5];
  eta_dot[4] = cf * nu[4] - sf * nu[5];
  eta_dot[5] = sf * t.sec * nu[4] + cf * t.sec * nu[5];

  // v_c = R^T current in body axes, where there is a current.
  const auto has_current = (current[0] != V{}) | (current[1] != V{}) | (current[2] != V{});
  const V vc0 = r00 * current[0] + r10 * current[1] + r20 * current[2];
  const V vc1 = r01 * current[0] + r11 * current[1] + r21 * current[2];
  const V vc2 = r02 * current[0] + r12 * current[1] + r22 * current[2];
  const V n[6] = {has_current ? nu[0] - vc0 : nu[0], has_current ? nu[1] - vc1 : nu[1],
                  has_current ? nu[2] - vc2 : nu[2], nu[3], nu[4], nu[5]};

  // g(eta) (Vehicle::restoring).
  const V ctcf = ct * cf, ctsf = ct * sf;
  const V &wb = c[pc::net_weight], &xm = c[pc::moment_x], &ym = c[pc::moment_y],
          &zm = c[pc::moment_z];
  const V g[6] = {wb * st, -wb * ctsf, -wb * ctcf, -ym * ctcf + zm * ctsf, zm * st + xm * ctcf,
                  -xm * ctsf - ym * st};

  // C(nu_r) nu_r for the diagonal structure: [w x (m v + a1); w x (I w + a2) + v x a1].
  const V a1[3] = {c[pc::added_mass] * n[0], c[pc::added_mass + 1] * n[1],
                   c[pc::added_mass + 2] * n[2]};
  const V a2[3] = {c[pc::added_mass + 3] * n[3], c[pc::added_mass + 4] * n[4],
                   c[pc::added_mass + 5] * n[5]};
  const V b1[3] = {c[pc::mass] * n[0] + a1[0], c[pc::mass] * n[1] + a1[1],
                   c[pc::mass] * n[2] + a1[2]};
  const V b2[3] = {c[pc::inertia] * n[3] + a2[0], c[pc::inertia + 1] * n[4] + a2[1],
                   c[pc::inertia + 2] * n[5] + a2[2]};
  const V f[6] = {n[4] * b1[2] - n[5] * b1[1],
                  n[5] * b1[0] - n[3] * b1[2],
                  n[3] * b1[1] - n[4] * b1[0],
                  (n[4] * b2[2] - n[5] * b2[1]) + (n[1] * a1[2] - n[2] * a1[1]),
                  (n[5] * b2[0] - n[3] * b2[2]) + (n[2] * a1[0] - n[0] * a1[2]),
                  (n[3] * b2[1] - n[4] * b2[0]) + (n[0] * a1[1] - n[1] * a1[0])};
  for (int i = 0; i < 6; ++i) {
    V abs_n;
    lane_abs(n[i], abs_n);
    const V d = c[pc::linear + i] + c[pc::quadratic + i] * abs_n;
    nu_dot[i] = c[pc::m_inv + i] * (((tau[i] - f[i]) - d * n[i]) - g[i]);
  }
  // nu_c_dot = -w x v_c as the body turns in the current.
  nu_dot[0] = has_current ? nu_dot[0] - (nu[4] * vc2 - nu[5] * vc1) : nu_dot[0];
  nu_dot[1] = has_current ? nu_dot[1] - (nu[5] * vc0 - nu[3] * vc2) : nu_dot[1];
  nu_dot[2] = has_current ? nu_dot[2] - (nu[3] * vc1 - nu[4] * vc0) : nu_dot[2];

  if constexpr (kChecked) {
    M out_finite = M(V{} == V{});
    for (int i = 0; i < 6; ++i) {
      and_finite(out_finite, eta_dot[i]);
      and_finite(out_finite, nu_dot[i]);
    }
    masks.bad_input = M(finite == M{});
    masks.bad_output = M((out_finite == M{}) & finite);
  }
  masks.singular = t.singular;
}

/// How each lane's RK4 step ended (rk4_step's statuses, status_of()).
template <typename V>
struct Rk4Masks {
  MaskOf<V> first_input;   ///< stage 1 met a non-finite input
  MaskOf<V> first_output;  ///< stage 1 gave a non-finite derivative
  MaskOf<V> overflowed;    ///< a later stage, or the step's result, not finite
  MaskOf<V> singular;      ///< a stage ran with a clamped cos(theta)
};

/// Lane i's status as rk4_step reports it.
template <typename V>
NEUROV_ALWAYS_INLINE Status status_of(const Rk4Masks<V>& m, int i) noexcept {
  if (mask_lane(m.first_input, i)) return Status::non_finite_input;
  if (mask_lane(m.first_output, i) || mask_lane(m.overflowed, i)) return Status::non_finite_output;
  return mask_lane(m.singular, i) ? Status::near_singularity : Status::ok;
}

/// One RK4 step of dt = h on each lane, (eta, nu) advanced in place where it
/// succeeded and left exactly as they were elsewhere; the classical stages
/// of core/rk4.hpp, all four evaluated on every lane (a lane that failed
/// early keeps its state, whatever its later stages computed). The statuses
/// are rk4_step's: stage 1's failure by its cause, any later one as
/// non_finite_output.
template <typename V>
NEUROV_ALWAYS_INLINE void plant_rk4(const V* c, V* eta, V* nu, const V* tau, const V* current,
                                    const V& h, Rk4Masks<V>& out) noexcept {
  using M = MaskOf<V>;
  V ke[4][6], kn[4][6], xe[6], xn[6];
  const V h2 = LaneScalar<V>(0.5) * h;
  TrigLanes<V> t;
  PlantMasks<V> m;
  trig_lanes(eta[3], eta[4], eta[5], t);
  plant_derivative<true>(c, t, eta, nu, tau, current, ke[0], kn[0], m);
  out.first_input = m.bad_input;
  out.first_output = m.bad_output;
  out.singular = m.singular;
  const M failed = M(m.bad_input | m.bad_output);
  for (int s = 1; s < 4; ++s) {
    const V step = s == 3 ? h : h2;
    for (int i = 0; i < 6; ++i) {
      xe[i] = eta[i] + step * ke[s - 1][i];
      xn[i] = nu[i] + step * kn[s - 1][i];
    }
    trig_lanes(xe[3], xe[4], xe[5], t);
    plant_derivative<false>(c, t, xe, xn, tau, current, ke[s], kn[s], m);
    out.singular = M(out.singular | m.singular);
  }
  const V h6 = h / LaneScalar<V>(6);
  // A later stage that met or made a non-finite number passes it on to the
  // result (every input of a stage reaches the result, through the next
  // stage's trigonometry or the final sum), so one check of the result
  // stands for the later stages' checks, at a third of a stage's cost.
  M next_finite = M(failed == M{});
  for (int i = 0; i < 6; ++i) {
    xe[i] = eta[i] + h6 * (ke[0][i] + LaneScalar<V>(2) * (ke[1][i] + ke[2][i]) + ke[3][i]);
    xn[i] = nu[i] + h6 * (kn[0][i] + LaneScalar<V>(2) * (kn[1][i] + kn[2][i]) + kn[3][i]);
    and_finite(next_finite, xe[i]);
    and_finite(next_finite, xn[i]);
  }
  out.overflowed = M((failed == M{}) & (next_finite == M{}));
  for (int i = 0; i < 6; ++i) {
    eta[i] = next_finite ? xe[i] : eta[i];
    nu[i] = next_finite ? xn[i] : nu[i];
  }
}

}  // namespace detail
}  // namespace neurov
