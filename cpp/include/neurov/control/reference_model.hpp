// Reference model (eq. 12-13, with the printed J^T in eq. 13 read as J):
//   nu_d_dot  = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d)
//   eta_d_dot =  J(eta_d) nu_d
// A second-order filter in the earth frame that turns a commanded pose r into
// a smooth (eta_d, eta_d_dot, eta_d_ddot). Near eta_d = r with small angles it
// is eta_d_ddot + Lambda_d eta_d_dot + Omega (eta_d - r) = 0 per DOF.
//
// The pitch singularity. J(eta_d) is undefined at theta_d = +-90 deg and Euler
// angles cannot pass through it, so the reference's pitch is limited to
//   |theta_d| <= pitch_limit() = 90 deg - kPitchMargin,  kPitchMargin = 0.2 rad
// (78.5 deg). The margin is set by the integration, not by the band: near
// 90 deg the J^T Omega J coupling makes the roll and yaw modes stiffer by
// about 2 / cos^2(theta), and RK4 stays stable at the limit while
// dt sqrt(2 max(omega)) < 2.8 sin(kPitchMargin) = 0.56 (the defaults,
// omega = 0.25 at dt = 0.2 s, have a factor 4 to spare; at dt = 0.2 s and a
// margin of 0.05 rad a 6-DOF command diverges already at omega = 1).
//   * The pitch of the command r is clamped to +-pitch_limit(): a command at
//     or beyond it leads the reference to the limit, where it stops, and a
//     command back brings it back.
//   * The reference's own pitch is held at the limit as by a wall: an RK4
//     stage beyond it is evaluated at the limit, the step's result is put
//     back on it, and in both the pitch rate outwards is removed from the
//     body rates (omega -= theta_dot (0, cos phi, -sin phi), which leaves
//     phi_dot and psi_dot as they were). This catches what the clamp does not:
//     an underdamped pitch (lambda_d^2 < 4 omega) overshoots a command by up
//     to exp(-zeta pi / sqrt(1 - zeta^2)) of the step, and a reference reset
//     beyond the limit is put on it by its first step. On the wall the
//     restoring term pulls it back inwards.
// So no RK4 stage is evaluated in or beyond the singular band (|cos theta| <
// singularity_threshold(), 7e-4 rad wide in float), and none can carry the
// reference over it. A limited step is taken and returns ok, because every
// other status means "refused, state unchanged" to the callers (the C
// interface, Python, the firmware examples); pitch_limited() reports it.
// Inside the limit the model is exactly eq. 12-13. A reference reset beyond
// 90 deg is held likewise in the same interval about the multiple of 180 deg
// its pitch is nearest (it stays on its side of the band); one reset into the
// band is refused with near_singularity and changes nothing.
#pragma once

#include <algorithm>
#include <cmath>

#include "neurov/core/config.hpp"
#include "neurov/core/rk4.hpp"
#include "neurov/control/desired_state.hpp"
#include "neurov/model/kinematics.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov {

template <typename Scalar>
class ReferenceModel {
 public:
  using Vec6 = Vector6<Scalar>;

  /// Distance [rad] of the pitch limit from +-90 deg (see the top of the file).
  static constexpr double kPitchMargin = 0.2;

  /// The pitch limit of the command and of the reference, 90 deg - kPitchMargin.
  static Scalar pitch_limit() noexcept { return static_cast<Scalar>(kHalfPi - kPitchMargin); }

  /// Unconfigured: step() returns invalid_argument until create() fills it.
  ReferenceModel() = default;

#if NEUROV_HAS_EXCEPTIONS
  /// lambda_d: damping diagonal (> 0); omega: stiffness diagonal (> 0).
  ReferenceModel(const Vec6& lambda_d, const Vec6& omega, const Vec6& eta0 = Vec6::Zero()) {
    throw_if_invalid(create(lambda_d, omega, eta0, *this), "reference model");
  }
#endif

  /// Validates and builds; `out` is untouched on failure. The model starts at
  /// rest at eta0.
  static ValidationError create(const Vec6& lambda_d, const Vec6& omega, const Vec6& eta0,
                                ReferenceModel& out) noexcept {
    if (auto e = detail::check_positive("lambda_d", lambda_d)) return e;
    if (auto e = detail::check_positive("omega", omega)) return e;
    if (auto e = detail::check_finite("eta0", eta0)) return e;
    if (EulerTrig<Scalar>::from_pose(eta0).status != Status::ok)
      return detail::invalid("eta0", 4, static_cast<double>(eta0(4)),
                             "a pitch away from +-90 deg");
    out.lambda_d_ = lambda_d;
    out.omega_ = omega;
    out.configured_ = true;
    out.reset(eta0);
    return {};
  }

  /// Back to rest at eta0 (nu_d = 0). A non-finite eta0 is refused (false).
  bool reset(const Vec6& eta0, const Vec6& nu_d0 = Vec6::Zero()) noexcept {
    if (!(eta0.allFinite() && nu_d0.allFinite())) return false;
    eta_d_ = eta0;
    nu_d_ = nu_d0;
    pitch_limited_ = false;
    fill_desired(EulerKinematics<Scalar>::from_pose(eta_d_), eta_d_, nu_d_, Vec6::Zero());
    return true;
  }

  /// Advances by dt with r held (RK4) and writes the new desired state, the
  /// pitch limited to +-pitch_limit() (see the top of the file;
  /// pitch_limited() tells). On any error status the model's state is
  /// unchanged and `out` keeps the last good desired state; near_singularity
  /// means the reference was reset into the singular band.
  Status step(const Vec6& r, Scalar dt, DesiredState<Scalar>& out) noexcept {
    if (!configured_ || detail::check_step("dt", static_cast<double>(dt))) {
      out = desired_;
      return Status::invalid_argument;
    }
    if (!r.allFinite()) {
      out = desired_;
      return Status::non_finite_input;
    }
    // The interval about k pi that the reference's pitch is in (k = 0 for
    // |theta_d| < 90 deg); the command's pitch is clamped to it.
    const Scalar centre = pitch_centre(eta_d_(4));
    if (!(std::abs(eta_d_(4) - centre) <= pitch_limit()) && in_singular_band(eta_d_(4))) {
      // Reset into the singular band: which side it is on is not known.
      out = desired_;
      return Status::near_singularity;
    }
    Vec6 rc = r;
    rc(4) = std::min(std::max(r(4), centre - pitch_limit()), centre + pitch_limit());
    bool limited = rc(4) != r(4);
    Vec6 eta_next, nu_next;
    // The stages run on copies, which the wall may move (see derivative()).
    Status s = detail::rk4(
                   eta_d_, nu_d_, dt,
                   [&](const Vec6& eta_stage, const Vec6& nu_stage, Vec6& eta_dot,
                       Vec6& nu_dot) noexcept {
                     Vec6 eta = eta_stage, nu = nu_stage;
                     return derivative(eta, nu, rc, centre, eta_dot, nu_dot, limited);
                   },
                   [](Status st) noexcept { return st == Status::ok; }, eta_next, nu_next)
                   .status;
    if (s == Status::ok && !(eta_next.allFinite() && nu_next.allFinite()))
      s = Status::non_finite_output;
    if (s == Status::ok) {
      Vec6 nu_dot;
      Vec6 unused;
      EulerKinematics<Scalar> k_next;
      // The result is held by the wall in place.
      s = derivative(eta_next, nu_next, rc, centre, unused, nu_dot, limited, &k_next);
      if (s == Status::ok) {
        // A finite state can still give a desired velocity or acceleration
        // that overflows (a command of 1e308): refuse it, keep the last good one.
        const DesiredState<Scalar> previous = desired_;
        fill_desired(k_next, eta_next, nu_next, nu_dot);
        if (desired_.eta_d_dot.allFinite() && desired_.eta_d_ddot.allFinite()) {
          eta_d_ = eta_next;
          nu_d_ = nu_next;
          pitch_limited_ = limited;
        } else {
          desired_ = previous;
          s = Status::non_finite_output;
        }
      }
    }
    out = desired_;
    return s;
  }

  /// Puts back the state a snapshot recorded (the model's eta_d, nu_d, the
  /// desired state last written and whether it was pitch-limited): false,
  /// and nothing changed, when unconfigured or for a non-finite value.
  bool restore(const Vec6& eta_d, const Vec6& nu_d, const DesiredState<Scalar>& desired,
               bool pitch_limited) noexcept {
    if (!configured_ ||
        !detail::all_finite(eta_d, nu_d, desired.eta_d, desired.eta_d_dot, desired.eta_d_ddot))
      return false;
    eta_d_ = eta_d;
    nu_d_ = nu_d;
    desired_ = desired;
    pitch_limited_ = pitch_limited;
    return true;
  }

  const Vec6& eta_d() const noexcept { return eta_d_; }
  const Vec6& nu_d() const noexcept { return nu_d_; }
  const DesiredState<Scalar>& desired() const noexcept { return desired_; }
  const Vec6& lambda_d() const noexcept { return lambda_d_; }
  const Vec6& omega() const noexcept { return omega_; }
  /// True when the last accepted step limited the pitch: the command's, or
  /// the reference's own at the wall (false after create() and reset()).
  bool pitch_limited() const noexcept { return pitch_limited_; }

 private:
  static constexpr double kPi = 3.14159265358979323846;
  static constexpr double kHalfPi = 1.57079632679489661923;

  /// The test of EulerTrig: |cos theta| below singularity_threshold().
  static bool in_singular_band(Scalar theta) noexcept {
    Scalar sin_theta, cos_theta;
    detail::sincos(theta, sin_theta, cos_theta);
    return std::abs(cos_theta) < singularity_threshold<Scalar>();
  }

  /// k pi for the interval (k pi - 90 deg, k pi + 90 deg) holding theta.
  static Scalar pitch_centre(Scalar theta) noexcept {
    const Scalar pi = static_cast<Scalar>(kPi);
    return pi * std::floor((theta + static_cast<Scalar>(kHalfPi)) / pi);
  }

  /// The right-hand side at (eta, nu) with the pitch held by the wall: a
  /// pitch beyond centre +- pitch_limit() is put on the limit and a pitch rate
  /// outwards is removed from the body rates (theta_dot = cos phi q - sin phi
  /// r; omega -= theta_dot (0, cos phi, -sin phi) keeps phi_dot and psi_dot),
  /// in eta and nu themselves; `limited` is set when the wall acted. Inside
  /// the limit it is eq. 12-13 and changes nothing. `kinematics` (if given)
  /// gets J at the held eta, which fill_desired() then need not recompute.
  Status derivative(Vec6& eta, Vec6& nu, const Vec6& r, Scalar centre, Vec6& eta_d_dot,
                    Vec6& nu_d_dot, bool& limited,
                    EulerKinematics<Scalar>* kinematics = nullptr) const noexcept {
    const Scalar lo = centre - pitch_limit(), hi = centre + pitch_limit();
    const bool outside = eta(4) > hi || eta(4) < lo;  // false for NaN: refused below
    Scalar outwards = Scalar(0);
    if (outside) {
      outwards = eta(4) > hi ? Scalar(1) : Scalar(-1);
      eta(4) = eta(4) > hi ? hi : lo;
      limited = true;
    }
    const auto k = EulerKinematics<Scalar>::from_pose(eta);
    if (outside) {
      const Scalar cf = k.trig.cos_phi, sf = k.trig.sin_phi;
      const Scalar theta_dot = cf * nu(4) - sf * nu(5);
      if (theta_dot * outwards > Scalar(0)) {
        nu(4) -= theta_dot * cf;
        nu(5) += theta_dot * sf;
      }
    }
    eta_d_dot = k.apply(nu);
    nu_d_dot = -lambda_d_.cwiseProduct(nu) + k.apply_transpose(omega_.cwiseProduct(r - eta));
    if (kinematics) *kinematics = k;
    return k.status();
  }

  /// k: J at eta_d.
  void fill_desired(const EulerKinematics<Scalar>& k, const Vec6& eta_d, const Vec6& nu_d,
                    const Vec6& nu_d_dot) noexcept {
    desired_.eta_d = eta_d;
    desired_.eta_d_dot = k.apply(nu_d);
    // eta_d_ddot = J nu_d_dot + J_dot nu_d.
    desired_.eta_d_ddot = k.apply(nu_d_dot) + k.apply_dot(nu_d, nu_d);
  }

  Vec6 lambda_d_ = Vec6::Ones();
  Vec6 omega_ = Vec6::Ones();
  Vec6 eta_d_ = Vec6::Zero();
  Vec6 nu_d_ = Vec6::Zero();
  DesiredState<Scalar> desired_{};
  bool configured_ = false;
  bool pitch_limited_ = false;
};

}  // namespace neurov
