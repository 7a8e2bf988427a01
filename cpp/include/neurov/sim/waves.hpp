// Linear (Airy) deep-water waves realised from a spectrum as a sum of N
// sinusoids (see docs/disturbances.md). Component i has the amplitude a_i,
// the frequency w_i drawn uniformly within the i-th of N equal bins of
// [0.5, 6] wp (so the sea never repeats itself within a run), the
// wavenumber k_i = w_i^2 / g, the direction beta_i and a random phase eps_i.
// At the point (x, y) north and east, z >= 0 below the mean surface:
//   theta_i = w_i t - k_i (x cos beta_i + y sin beta_i) + eps_i,
//   zeta    = sum a_i cos theta_i                      (elevation, up)
//   v       = sum a_i w_i e^(-k_i z) [cos theta_i cos beta_i,
//                                     cos theta_i sin beta_i, sin theta_i]
//   a       = sum a_i w_i^2 e^(-k_i z) [-sin theta_i cos beta_i,
//                                       -sin theta_i sin beta_i, cos theta_i]
// (NED: the third entries point down), the local acceleration dv/dt.
//
// Two ways to evaluate: evaluate() computes the sum directly (a sin, cos
// and exp per component); start()/advance() follow one moving point at a
// fixed time step and update each component's phasor e^(i theta_i) and
// decay e^(-k_i z) by a complex rotation and short series in the small
// position change, with a direct evaluation every resync_interval steps.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "neurov/core/random.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/sim/random_streams.hpp"
#include "neurov/sim/sea_constants.hpp"
#include "neurov/sim/wave_spectrum.hpp"

namespace neurov {

template <typename Scalar>
struct WaveKinematics {
  Scalar elevation = Scalar(0);                       ///< zeta above (x, y) [m], up
  Vector3<Scalar> velocity = Vector3<Scalar>::Zero();      ///< orbital velocity, NED [m/s]
  Vector3<Scalar> acceleration = Vector3<Scalar>::Zero();  ///< its time derivative, NED [m/s^2]
};

namespace detail {
/// cos and sin of a small angle d (|d| <= 0.1) by their series to d^8 and
/// d^9: the first terms left out, d^10/10! and d^11/11!, are below 3e-17.
inline void small_sincos(double d, double& s, double& c) noexcept {
  const double d2 = d * d;
  c = 1.0 + d2 * (-1.0 / 2 + d2 * (1.0 / 24 + d2 * (-1.0 / 720 + d2 * (1.0 / 40320))));
  s = d * (1.0 + d2 * (-1.0 / 6 + d2 * (1.0 / 120 + d2 * (-1.0 / 5040 + d2 * (1.0 / 362880)))));
}
/// exp(d) for |d| <= 0.1 by its series to d^9 (d^10/10! < 3e-17 left out).
inline double small_exp(double d) noexcept {
  double term = 1.0, sum = 1.0;
  for (int n = 1; n <= 9; ++n) sum += (term *= d / n);
  return sum;
}
}  // namespace detail

/// A seeded realisation of a wave spectrum with at most Capacity components,
/// held inline (no heap: the object is about 120 bytes per component).
template <typename ScalarT, int Capacity = 512>
class Waves {
 public:
  using Scalar = ScalarT;
  using Vec3 = Vector3<Scalar>;
  static constexpr int capacity = Capacity;
  /// Steps of advance() between two direct evaluations.
  static constexpr int resync_interval = 1000;
  /// Largest phase or decay exponent change per step that advance() follows
  /// by series; a larger jump of the point is evaluated directly.
  static constexpr double max_series_argument = 0.1;
  /// The band realised, in multiples of the peak frequency: it holds all
  /// but 0.1 % of the Pierson-Moskowitz m0 (the tail above 6 wp holds
  /// 5/4 * 6^-4); the realised amplitudes are scaled up to give Hs exactly.
  static constexpr double band_low = 0.5, band_high = 6.0;

  Waves() = default;

  /// Validates c and, if valid, fills `out` (untouched otherwise) with the
  /// realisation drawn from stream_seed(seed, RandomStream::waves): first
  /// each component's frequency within its bin and its phase, then, with
  /// spreading, the directions, so that spreading leaves frequencies and
  /// phases as they were. No heap, but a pass over the components.
  static ValidationError create(const WaveConfig<Scalar>& c, std::uint64_t seed,
                                Waves& out) noexcept {
    if (auto e = validate(c, Capacity)) return e;
    constexpr double pi = 3.14159265358979323846, two_pi = 2.0 * pi;
    out.config_ = c;
    out.spectrum_ = SpectralDensity::from(c);
    const int n = c.components;
    out.n_ = n;
    NormalRandom rng(stream_seed(seed, RandomStream::waves));
    const double wp = out.spectrum_.peak_frequency;
    const double lo = band_low * wp, dw = (band_high - band_low) * wp / n;
    double m0 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double w = lo + (i + rng.uniform()) * dw;
      out.omega_[i] = w;
      out.k_[i] = w * w / standard_gravity;
      out.amp_[i] = std::sqrt(2.0 * out.spectrum_(w) * dw);
      out.phase_[i] = two_pi * rng.uniform();
      m0 += 0.5 * out.amp_[i] * out.amp_[i];
    }
    const double hs = static_cast<double>(c.hs);
    // m0 is 0 only when Hs^2 underflows: the amplitudes are 0 then anyway.
    const double scale = m0 > 0.0 ? std::sqrt(hs * hs / 16.0 / m0) : 0.0;
    const double main = static_cast<double>(c.direction) * pi / 180.0;
    const double spread = static_cast<double>(c.spreading);
    out.k_max_ = 0.0;
    for (int i = 0; i < n; ++i) {
      double beta = main;
      if (spread > 0.0) {  // cos^n(theta) on (-pi/2, pi/2) by rejection
        double theta;
        do theta = pi * (rng.uniform() - 0.5);
        while (rng.uniform() > std::pow(std::cos(theta), spread));
        beta += theta;
      }
      out.amp_[i] *= scale;
      out.vel_[i] = out.amp_[i] * out.omega_[i];
      out.acc_[i] = out.vel_[i] * out.omega_[i];
      out.cos_beta_[i] = std::cos(beta);
      out.sin_beta_[i] = std::sin(beta);
      out.kx_[i] = out.k_[i] * out.cos_beta_[i];
      out.ky_[i] = out.k_[i] * out.sin_beta_[i];
      out.k_max_ = std::max(out.k_max_, out.k_[i]);
    }
    out.valid_ = true;
    out.started_ = false;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  const WaveConfig<Scalar>& config() const noexcept { return config_; }
  /// The target spectrum S(omega) the components realise.
  const SpectralDensity& spectrum() const noexcept { return spectrum_; }
  int components() const noexcept { return n_; }
  double frequency(int i) const noexcept { return omega_[i]; }  ///< w_i [rad/s]
  double amplitude(int i) const noexcept { return amp_[i]; }    ///< a_i [m]
  double wave_direction(int i) const noexcept { return std::atan2(sin_beta_[i], cos_beta_[i]); }

  /// The depth below which the model is used: 1.2 Hs, below the deepest
  /// trough of a three-hour sea but for about 1 % of them (Rayleigh
  /// amplitudes: 1000 waves * exp(-8 * 1.2^2)); add the body's own extent.
  Scalar minimum_depth() const noexcept { return Scalar(1.2) * config_.hs; }

  /// The kinematics at time t [s] and NED position p (p.z() the depth below
  /// the mean surface; above it, z = 0 is used: the linear model has no
  /// kinematics there). non_finite_input (zeros) for NaN or infinite input.
  Status evaluate(double t, const Vec3& p, WaveKinematics<Scalar>& out) const noexcept {
    out = WaveKinematics<Scalar>{};
    if (!valid_) return Status::invalid_argument;
    if (!(std::isfinite(t) && detail::all_finite(p))) return Status::non_finite_input;
    const double x = static_cast<double>(p.x()), y = static_cast<double>(p.y());
    const double z = std::max(0.0, static_cast<double>(p.z()));
    Sums s;
    for (int i = 0; i < n_; ++i) {
      const double theta = omega_[i] * t - (kx_[i] * x + ky_[i] * y) + phase_[i];
      add(s, i, std::cos(theta), std::sin(theta), std::exp(-k_[i] * z));
    }
    return store(s, out);
  }

  /// Starts following a point: kinematics() is then the field at (t0, p),
  /// and each advance() moves time on by `step` [s].
  Status start(double t0, const Vec3& p, Scalar step) noexcept {
    if (!valid_) return Status::invalid_argument;
    if (!(std::isfinite(t0) && std::isfinite(static_cast<double>(step)) && detail::all_finite(p)))
      return Status::non_finite_input;
    if (!(step > Scalar(0))) return Status::invalid_argument;
    t0_ = t0;
    step_ = static_cast<double>(step);
    steps_ = 0;
    for (int i = 0; i < n_; ++i) {
      rot_re_[i] = std::cos(omega_[i] * step_);
      rot_im_[i] = std::sin(omega_[i] * step_);
    }
    started_ = true;
    return resync(p);
  }

  /// Moves time on by one step and the point to p, and updates kinematics().
  /// invalid_argument before start(), non_finite_input for a NaN or infinite
  /// p (time and state are unchanged then); non_finite_output, with zero
  /// kinematics, if the sums overflowed.
  Status advance(const Vec3& p) noexcept {
    if (!started_) return Status::invalid_argument;
    if (!detail::all_finite(p)) return Status::non_finite_input;
    ++steps_;
    const double x = static_cast<double>(p.x()), y = static_cast<double>(p.y());
    const double z = std::max(0.0, static_cast<double>(p.z()));
    const double dx = x - x_, dy = y - y_, dz = z - z_;
    const double reach = k_max_ * std::max(std::sqrt(dx * dx + dy * dy), std::abs(dz));
    if (steps_ % resync_interval == 0 || reach > max_series_argument) return resync(p);
    const bool moved = dx != 0.0 || dy != 0.0, dived = dz != 0.0;
    Sums s;
    for (int i = 0; i < n_; ++i) {
      double re = pre_[i] * rot_re_[i] - pim_[i] * rot_im_[i];
      double im = pre_[i] * rot_im_[i] + pim_[i] * rot_re_[i];
      if (moved) {  // times e^(-i delta), delta = k_i . (dx, dy)
        double sd, cd;
        detail::small_sincos(kx_[i] * dx + ky_[i] * dy, sd, cd);
        const double r2 = re * cd + im * sd;
        im = im * cd - re * sd;
        re = r2;
      }
      if (dived) decay_[i] *= detail::small_exp(-k_[i] * dz);
      pre_[i] = re;
      pim_[i] = im;
      add(s, i, re, im, decay_[i]);
    }
    x_ = x;
    y_ = y;
    z_ = z;
    return store(s, kin_);
  }

  /// The field at the followed point after the last start() or advance().
  const WaveKinematics<Scalar>& kinematics() const noexcept { return kin_; }
  /// Time of kinematics() [s]: t0 + steps * step.
  double time() const noexcept { return t0_ + static_cast<double>(steps_) * step_; }

 private:
  struct Sums {
    double zeta = 0, vn = 0, ve = 0, vd = 0, an = 0, ae = 0, ad = 0;
  };

  void add(Sums& s, int i, double c, double sn, double decay) const noexcept {
    s.zeta += amp_[i] * c;
    const double u = vel_[i] * decay * c, du = -acc_[i] * decay * sn;
    s.vn += u * cos_beta_[i];
    s.ve += u * sin_beta_[i];
    s.vd += vel_[i] * decay * sn;
    s.an += du * cos_beta_[i];
    s.ae += du * sin_beta_[i];
    s.ad += acc_[i] * decay * c;
  }

  /// Writes the sums to `out`; non_finite_output (zeros) if any overflowed
  /// (an extreme Hs or Tp, or a float that cannot hold them).
  static Status store(const Sums& s, WaveKinematics<Scalar>& out) noexcept {
    out.elevation = static_cast<Scalar>(s.zeta);
    out.velocity = Vec3(static_cast<Scalar>(s.vn), static_cast<Scalar>(s.ve),
                        static_cast<Scalar>(s.vd));
    out.acceleration = Vec3(static_cast<Scalar>(s.an), static_cast<Scalar>(s.ae),
                            static_cast<Scalar>(s.ad));
    if (std::isfinite(static_cast<double>(out.elevation)) &&
        detail::all_finite(out.velocity, out.acceleration))
      return Status::ok;
    out = WaveKinematics<Scalar>{};
    return Status::non_finite_output;
  }

  /// Phasors, decays and kinematics() computed directly at time() and p.
  Status resync(const Vec3& p) noexcept {
    x_ = static_cast<double>(p.x());
    y_ = static_cast<double>(p.y());
    z_ = std::max(0.0, static_cast<double>(p.z()));
    const double t = time();
    Sums s;
    for (int i = 0; i < n_; ++i) {
      const double theta = omega_[i] * t - (kx_[i] * x_ + ky_[i] * y_) + phase_[i];
      pre_[i] = std::cos(theta);
      pim_[i] = std::sin(theta);
      decay_[i] = std::exp(-k_[i] * z_);
      add(s, i, pre_[i], pim_[i], decay_[i]);
    }
    return store(s, kin_);
  }

  using Array = std::array<double, static_cast<std::size_t>(Capacity)>;
  WaveConfig<Scalar> config_{};
  SpectralDensity spectrum_{};
  int n_ = 0;
  // The components (fixed at create) and the followed point's state, in
  // double whatever Scalar: a float build keeps the phases of a long run.
  Array omega_{}, k_{}, amp_{}, vel_{}, acc_{}, phase_{}, cos_beta_{}, sin_beta_{}, kx_{}, ky_{};
  Array rot_re_{}, rot_im_{}, pre_{}, pim_{}, decay_{};
  double k_max_ = 0.0;
  double t0_ = 0.0, step_ = 0.0, x_ = 0.0, y_ = 0.0, z_ = 0.0;
  std::int64_t steps_ = 0;
  WaveKinematics<Scalar> kin_{};
  bool valid_ = false, started_ = false;
};

}  // namespace neurov
