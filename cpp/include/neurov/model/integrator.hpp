// Fixed-step fourth-order Runge-Kutta for the 12-state plant x = (eta, nu)
// under a force tau held constant over the step (zero-order hold). Only the
// vehicle's scalar type is deduced, so tau and dt may be any expression.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "neurov/core/config.hpp"
#include "neurov/core/rk4.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/model/vehicle.hpp"

namespace neurov {

/// Advances (eta, nu) by dt in place. On invalid_argument (dt <= 0 or not
/// finite, empty vehicle), non_finite_input or non_finite_output the state is
/// left exactly as it was. near_singularity means a stage ran with a clamped
/// cos(theta) (pitch at +-90 deg); the finite result is kept and flagged.
/// Always inlined: GCC otherwise keeps it out of line once the simulator's
/// step (its disturbance parts inlined) grows, and the plant loop slowed by
/// about 14 % (bench BM_ClosedLoopPlantOnly).
template <typename Scalar>
NEUROV_ALWAYS_INLINE Status rk4_step(const Vehicle<Scalar>& vehicle, Vector6<Scalar>& eta, Vector6<Scalar>& nu,
                       const typename Vehicle<Scalar>::Vec6& tau,
                       typename Vehicle<Scalar>::Scalar dt,
                       const typename Vehicle<Scalar>::Vec3& current_ned =
                           Vector3<Scalar>::Zero()) noexcept {
  if (detail::check_step("dt", static_cast<double>(dt))) return Status::invalid_argument;
  if (vehicle.valid() && vehicle.diagonal()) {
    // The kernel a batch runs in SIMD lanes, here on one lane: a run alone
    // and the same run in a batch share every rounding.
    const Scalar h = dt;
    detail::Rk4Masks<Scalar> m;
    detail::plant_rk4(vehicle.plant_coefficients(), eta.data(), nu.data(), tau.data(),
                      current_ned.data(), h, m);
    return detail::status_of(m, 0);
  }
  using V6 = Vector6<Scalar>;
  V6 eta_next = eta, nu_next = nu;  // set by rk4; initialised for GCC's flow analysis
  const detail::Rk4Outcome r = detail::rk4(
      eta, nu, dt,
      [&](const V6& e, const V6& n, V6& e_dot, V6& n_dot) noexcept {
        return vehicle.derivative(e, n, tau, current_ned, e_dot, n_dot);
      },
      [](Status s) noexcept { return s == Status::ok || s == Status::near_singularity; },
      eta_next, nu_next);
  // A later stage that fails started from a finite state the first accepted:
  // the step itself overflowed.
  if (r.stage == 1) return r.status;
  if (r.stage > 1) return Status::non_finite_output;
  const Status flag = r.status;
  if (!detail::all_finite(eta_next, nu_next)) return Status::non_finite_output;
  eta = eta_next;
  nu = nu_next;
  return flag;
}

/// Where rk4_segments stopped: the status of the step that failed, its
/// segment and its interval within the segment (status ok: none failed).
struct SegmentFailure {
  Status status = Status::ok;
  std::size_t segment = 0;
  std::int64_t step = 0;
};

/// S open-loop runs of `vehicle` (a model fit's shooting segments): segment i
/// starts from eta0[i], nu0[i] (rows of 6) and takes steps[i] intervals;
/// interval k, counted over the segments in order, holds tau[k] (6) and
/// current[k] (3, NED; current null: still water) over dt[k], in `substeps`
/// rk4_step calls of dt[k] / substeps each. Writes nu at every segment's rows
/// 0..steps[i] to `out` (sum(steps) + S rows of 6) and stops at the first
/// step that is not ok, which it returns.
template <typename Scalar>
SegmentFailure rk4_segments(const Vehicle<Scalar>& vehicle, std::size_t segments, const Scalar* eta0,
                            const Scalar* nu0, const std::int64_t* steps, const Scalar* tau, const Scalar* dt,
                            const Scalar* current, int substeps, Scalar* out) noexcept {
  using V6 = Vector6<Scalar>;
  using V3 = Vector3<Scalar>;
  std::size_t k = 0;
  for (std::size_t i = 0; i < segments; ++i) {
    V6 eta = Eigen::Map<const V6>(eta0 + 6 * i), nu = Eigen::Map<const V6>(nu0 + 6 * i);
    Eigen::Map<V6>{out} = nu;
    out += 6;
    for (std::int64_t j = 0; j < steps[i]; ++j, ++k) {
      const V6 f = Eigen::Map<const V6>(tau + 6 * k);
      const V3 c = current ? V3(Eigen::Map<const V3>(current + 3 * k)) : V3::Zero();
      const Scalar h = dt[k] / static_cast<Scalar>(substeps);
      for (int s = 0; s < substeps; ++s) {
        const Status st = rk4_step(vehicle, eta, nu, f, h, c);
        if (st != Status::ok) return {st, i, j};
      }
      Eigen::Map<V6>{out} = nu;
      out += 6;
    }
  }
  return {};
}

}  // namespace neurov
