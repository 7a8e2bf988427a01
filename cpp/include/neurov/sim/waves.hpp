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
// fixed time step (the simulator's control period) and update each
// component's phasor e^(i theta_i) and decay e^(-k_i z) by the exact time
// rotation e^(i w_i step), precomputed, and by e^(-i k_i . dp) and
// e^(-k_i dz) of the point's move, from series of a scaled argument squared
// back up; the components are held as arrays so that the loops vectorise.
// Along with the kinematics they give the rate of change of the velocity
// following the point along a given path velocity, from which WaveInterval
// interpolates the flow within the step (cubic Hermite).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "neurov/core/random.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/core/vector_unit.hpp"
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
/// A move of the followed point over one step, for rotate_phasors: each
/// component's phasor times e^(i w_i step) e^(-i k_i . (dx, dy)) and decay
/// times e^(-k_i dz), from the series of the factors at the move scaled by
/// 2^-squarings (hx, hy, hz: dx, dy and -dz scaled), squared back up.
struct WaveMove {
  const double *kx, *ky, *k, *rot_re, *rot_im;
  double *pre, *pim, *decay, *c, *s, *e;  // c, s, e: scratch
  int n, squarings;
  double hx, hy, hz;
};

/// v = p[i .. i + L) for each pair (v, p) given: the loads of one step of
/// the loops below.
template <int L>
NEUROV_ALWAYS_INLINE void load_at(int) noexcept {}
template <int L, typename... Rest>
NEUROV_ALWAYS_INLINE void load_at(int i, Vec<double, L>& v, const double* p,
                                  Rest&&... rest) noexcept {
  load<double, L>(v, p + i);
  load_at<L>(i, rest...);
}

/// p[i .. i + L) = v for each pair (p, v) given.
template <int L>
NEUROV_ALWAYS_INLINE void store_at(int) noexcept {}
template <int L, typename... Rest>
NEUROV_ALWAYS_INLINE void store_at(int i, double* p, const Vec<double, L>& v,
                                   Rest&&... rest) noexcept {
  store<double, L>(p + i, v);
  store_at<L>(i, rest...);
}

// Elementwise loops on vectors of L doubles (the build's vector unit, and,
// through the dispatch of core/vector_unit.hpp, AVX2+FMA or AVX-512 where
// the CPU has them; the copies round differently in the last bits, as the
// network's loops do). They run on to a whole number of vectors: the
// arrays are zero up to their capacity.
template <int L>
NEUROV_ALWAYS_INLINE void rotate_phasors_lanes(const WaveMove& m) noexcept {
  using V = Vec<double, L>;
  const int n = (m.n + L - 1) / L * L;
  const V hx = V{} + m.hx, hy = V{} + m.hy, hz = V{} + m.hz, one = V{} + 1.0;
  // cos and sin to x^10 and x^11, exp to x^11: at |x| <= 1/8 the first
  // terms left out are below 1e-19.
  for (int i = 0; i < n; i += L) {
    V kx, ky, k;
    load_at<L>(i, kx, m.kx, ky, m.ky, k, m.k);
    const V a = kx * hx + ky * hy, x2 = a * a, x = k * hz;
    const V c = one + x2 * (-1.0 / 2 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                                                              x2 * (-1.0 / 3628800)))));
    const V s = a * (one + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 +
                                  x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
    const V e = one + x * (1.0 + x * (1.0 / 2 + x * (1.0 / 6 + x * (1.0 / 24 + x * (1.0 / 120 +
                x * (1.0 / 720 + x * (1.0 / 5040 + x * (1.0 / 40320 + x * (1.0 / 362880 +
                x * (1.0 / 3628800 + x * (1.0 / 39916800)))))))))));
    store_at<L>(i, m.c, c, m.s, s, m.e, e);
  }
  for (int j = 0; j < m.squarings; ++j) {
    for (int i = 0; i < n; i += L) {
      V c, s, e;
      load_at<L>(i, c, m.c, s, m.s, e, m.e);
      const V c2 = c * c - s * s, s2 = 2.0 * c * s, e2 = e * e;
      store_at<L>(i, m.c, c2, m.s, s2, m.e, e2);
    }
  }
  for (int i = 0; i < n; i += L) {
    V c, s, e, rr, ri, pr, pi, d;
    load_at<L>(i, c, m.c, s, m.s, e, m.e, rr, m.rot_re, ri, m.rot_im, pr, m.pre, pi, m.pim, d,
               m.decay);
    const V wr = rr * c + ri * s, wi = ri * c - rr * s;  // e^(i w step) (c - i s)
    const V pr2 = pr * wr - pi * wi, pi2 = pr * wi + pi * wr, d2 = d * e;
    store_at<L>(i, m.pre, pr2, m.pim, pi2, m.decay, d2);
  }
}

NEUROV_ALWAYS_INLINE void rotate_phasors_body(const WaveMove& m) noexcept {
  rotate_phasors_lanes<kBuildVectorBytes >= 16 ? kBuildVectorBytes / 8 : 1>(m);
}

/// The sums of Waves::sum (see there) over the components, in one pass.
struct WaveSums {
  const double *pre, *pim, *decay, *k, *kx, *ky, *omega, *amp, *vcb, *vsb, *vel, *acb, *asb, *acc;
  int n;
  double un, ue, ud;
  double out[10];  // zeta, v (3), a (3), dv/dt following u (3)
};

template <int L>
NEUROV_ALWAYS_INLINE void wave_sums_lanes(WaveSums& w) noexcept {
  using V = Vec<double, L>;
  const int n = (w.n + L - 1) / L * L;
  const V un = V{} + w.un, ue = V{} + w.ue, ud = V{} + w.ud;
  V acc[10];
  for (V& a : acc) a = V{} + 0.0;
  for (int i = 0; i < n; i += L) {
    V pr, pi, d, k, kx, ky, om, c;
    load_at<L>(i, pr, w.pre, pi, w.pim, d, w.decay, k, w.k, kx, w.kx, ky, w.ky, om, w.omega, c,
               w.amp);
    acc[0] += c * pr;
    const V qr = pr * d, qi = pi * d;
    const V im = om - kx * un - ky * ue, re = -(k * ud);  // the rate, following u
    const V rr = re * qr - im * qi, ri = re * qi + im * qr;
    load<double, L>(c, w.vcb + i);
    acc[1] += c * qr;
    acc[7] += c * rr;
    load<double, L>(c, w.vsb + i);
    acc[2] += c * qr;
    acc[8] += c * rr;
    load<double, L>(c, w.vel + i);
    acc[3] += c * qi;
    acc[9] += c * ri;
    load<double, L>(c, w.acb + i);
    acc[4] -= c * qi;
    load<double, L>(c, w.asb + i);
    acc[5] -= c * qi;
    load<double, L>(c, w.acc + i);
    acc[6] += c * qr;
  }
  for (int j = 0; j < 10; ++j) {
    double lanes[L];
    store<double, L>(lanes, acc[j]);
    double total = 0.0;
    for (int l = 0; l < L; ++l) total += lanes[l];
    w.out[j] = total;
  }
}

NEUROV_ALWAYS_INLINE void wave_sums_body(WaveSums& w) noexcept {
  wave_sums_lanes<kBuildVectorBytes >= 16 ? kBuildVectorBytes / 8 : 1>(w);
}

#if NEUROV_RUNTIME_DISPATCH
NEUROV_TARGET_AVX2 inline void wave_sums_avx2(WaveSums& w) noexcept { wave_sums_lanes<4>(w); }
NEUROV_TARGET_AVX512 inline void wave_sums_avx512(WaveSums& w) noexcept {
  wave_sums_lanes<8>(w);
}
#endif

inline void wave_sums(WaveSums& w) noexcept {
#if NEUROV_RUNTIME_DISPATCH
  switch (kernel_isa()) {
    case KernelIsa::avx512:
      return wave_sums_avx512(w);
    case KernelIsa::avx2:
      return wave_sums_avx2(w);
    default:
      break;
  }
#endif
  wave_sums_body(w);
}

#if NEUROV_RUNTIME_DISPATCH
NEUROV_TARGET_AVX2 inline void rotate_phasors_avx2(const WaveMove& m) noexcept {
  rotate_phasors_lanes<4>(m);
}
NEUROV_TARGET_AVX512 inline void rotate_phasors_avx512(const WaveMove& m) noexcept {
  rotate_phasors_lanes<8>(m);
}
#endif

inline void rotate_phasors(const WaveMove& m) noexcept {
#if NEUROV_RUNTIME_DISPATCH
  switch (kernel_isa()) {
    case KernelIsa::avx512:
      return rotate_phasors_avx512(m);
    case KernelIsa::avx2:
      return rotate_phasors_avx2(m);
    default:
      break;
  }
#endif
  rotate_phasors_body(m);
}
}  // namespace detail

/// The rate of change of the orbital velocity seen from a point moving
/// with a given velocity u: d/dt = partial/partial t + (u . grad).
template <typename Scalar>
struct WaveRates {
  Vector3<Scalar> velocity = Vector3<Scalar>::Zero();  ///< NED [m/s^2]
};

/// The orbital flow over one step [0, duration] of a moving point, from the
/// velocity and its rate along the point's path at both ends: the velocity
/// by cubic Hermite in time (exact to O(duration^4) for each component as
/// the path is followed), the acceleration its derivative, the rate of the
/// flow along the path. That is the acceleration the plant takes: a body
/// carried by the water meets exactly the flow it moves with (it differs
/// from the local partial dv/dt by (u . grad) v, second order in the wave
/// slope for a body moving with the water, which linear theory drops).
template <typename Scalar>
struct WaveInterval {
  using Vec3 = Vector3<Scalar>;
  Scalar duration = Scalar(0);
  Vec3 start_velocity = Vec3::Zero(), end_velocity = Vec3::Zero();
  Vec3 start_rate = Vec3::Zero(), end_rate = Vec3::Zero();

  /// The velocity and acceleration at s in [0, duration].
  void at(Scalar s, Vec3& velocity, Vec3& acceleration) const noexcept {
    const Scalar h = duration, tau = h > Scalar(0) ? s / h : Scalar(0);
    const Scalar t2 = tau * tau, t3 = t2 * tau;
    const Scalar h00 = Scalar(2) * t3 - Scalar(3) * t2 + Scalar(1), h01 = Scalar(1) - h00;
    const Scalar h10 = h * (t3 - Scalar(2) * t2 + tau), h11 = h * (t3 - t2);
    velocity = h00 * start_velocity + h01 * end_velocity + h10 * start_rate + h11 * end_rate;
    // d/ds of the above: dh00/ds = 6 (t2 - tau) / h, dh10/ds = 3 t2 - 4 tau + 1, ...
    const Scalar d00 = h > Scalar(0) ? Scalar(6) * (t2 - tau) / h : Scalar(0);
    acceleration = d00 * (start_velocity - end_velocity) +
                   (Scalar(3) * t2 - Scalar(4) * tau + Scalar(1)) * start_rate +
                   (Scalar(3) * t2 - Scalar(2) * tau) * end_rate;
  }
};

/// A seeded realisation of a wave spectrum with at most Capacity components,
/// held inline (no heap: the object is about 200 bytes per component).
template <typename ScalarT, int Capacity = kMaxWaveComponents>
class Waves {
 public:
  using Scalar = ScalarT;
  using Vec3 = Vector3<Scalar>;
  static constexpr int capacity = Capacity;
  static_assert(Capacity % 8 == 0, "a whole number of the widest vectors (8 doubles)");
  /// Steps of advance() between two direct evaluations (the rounding of
  /// the rotations grows as a random walk, about 1e-15 over them).
  static constexpr int resync_interval = 1000;
  /// advance() scales the move's largest phase or decay exponent change
  /// down by 2^m to at most series_argument, where the series below are
  /// exact to rounding, and squares the factors m times back up;
  /// a move of more than max_move_argument (m > 6, where the squarings
  /// would have doubled the rounding six times) is evaluated directly.
  static constexpr double series_argument = 0.125, max_move_argument = 8.0;
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
    for (Array* a : {&out.omega_, &out.k_, &out.amp_, &out.phase_, &out.cos_beta_, &out.sin_beta_,
                     &out.kx_, &out.ky_, &out.vel_, &out.acc_, &out.vcb_, &out.vsb_, &out.acb_,
                     &out.asb_, &out.rot_re_, &out.rot_im_, &out.pre_, &out.pim_, &out.decay_,
                     &out.work_[0], &out.work_[1], &out.work_[2]})
    {
      a->resize(Capacity);  // zero up to the capacity: the vector loops run on
      a->setZero();
      a->resize(n);
    }
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
    for (int i = 0; i < n; ++i) {
      double beta = main;
      if (spread > 0.0) {  // cos^n(theta) on (-pi/2, pi/2) by rejection
        double theta;
        do theta = pi * (rng.uniform() - 0.5);
        while (rng.uniform() > std::pow(std::cos(theta), spread));
        beta += theta;
      }
      out.amp_[i] *= scale;
      out.cos_beta_[i] = std::cos(beta);
      out.sin_beta_[i] = std::sin(beta);
    }
    out.vel_ = out.amp_ * out.omega_;
    out.acc_ = out.vel_ * out.omega_;
    out.kx_ = out.k_ * out.cos_beta_;
    out.ky_ = out.k_ * out.sin_beta_;
    out.vcb_ = out.vel_ * out.cos_beta_;
    out.vsb_ = out.vel_ * out.sin_beta_;
    out.acb_ = out.acc_ * out.cos_beta_;
    out.asb_ = out.acc_ * out.sin_beta_;
    out.k_max_ = out.k_.maxCoeff();
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
    double zeta = 0, vn = 0, ve = 0, vd = 0, an = 0, ae = 0, ad = 0;
    for (int i = 0; i < n_; ++i) {
      const double theta = omega_[i] * t - (kx_[i] * x + ky_[i] * y) + phase_[i];
      const double c = std::cos(theta), sn = std::sin(theta), decay = std::exp(-k_[i] * z);
      zeta += amp_[i] * c;
      const double u = vel_[i] * decay * c, du = -acc_[i] * decay * sn;
      vn += u * cos_beta_[i];
      ve += u * sin_beta_[i];
      vd += vel_[i] * decay * sn;
      an += du * cos_beta_[i];
      ae += du * sin_beta_[i];
      ad += acc_[i] * decay * c;
    }
    WaveRates<Scalar> unused;
    return store(zeta, Eigen::Vector3d(vn, ve, vd), Eigen::Vector3d(an, ae, ad),
                 Eigen::Vector3d::Zero(), out, unused);
  }

  /// Starts following a point: kinematics() is then the field at (t0, p),
  /// rates() the velocity's rate following the path velocity u (NED [m/s]),
  /// and each
  /// advance() moves time on by `step` [s].
  Status start(double t0, const Vec3& p, Scalar step, const Vec3& u = Vec3::Zero()) noexcept {
    if (!valid_) return Status::invalid_argument;
    if (!(std::isfinite(t0) && std::isfinite(static_cast<double>(step)) &&
          detail::all_finite(p, u)))
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
    return resync(p, u);
  }

  /// Moves time on by one step and the point to p, and updates kinematics()
  /// and rates() (following the path velocity u there). invalid_argument
  /// before start(), non_finite_input for a NaN or infinite p or u (time
  /// and state are unchanged then); non_finite_output, with zero
  /// kinematics, if the sums overflowed.
  Status advance(const Vec3& p, const Vec3& u = Vec3::Zero()) noexcept {
    if (!started_) return Status::invalid_argument;
    if (!detail::all_finite(p, u)) return Status::non_finite_input;
    ++steps_;
    const double x = static_cast<double>(p.x()), y = static_cast<double>(p.y());
    const double z = std::max(0.0, static_cast<double>(p.z()));
    const double dx = x - x_, dy = y - y_, dz = z - z_;
    const double reach = k_max_ * std::max(std::sqrt(dx * dx + dy * dy), std::abs(dz));
    if (steps_ % resync_interval == 0 || !(reach <= max_move_argument)) return resync(p, u);
    rotate(dx, dy, dz, reach);
    x_ = x;
    y_ = y;
    z_ = z;
    return sum(u);
  }

  /// The field at the followed point after the last start() or advance().
  const WaveKinematics<Scalar>& kinematics() const noexcept { return kin_; }
  /// The rate of kinematics().velocity following the path velocity given
  /// there.
  const WaveRates<Scalar>& rates() const noexcept { return rates_; }
  /// Time of kinematics() [s]: t0 + steps * step.
  double time() const noexcept { return t0_ + static_cast<double>(steps_) * step_; }

 private:
  using Array = Eigen::Array<double, Eigen::Dynamic, 1, Eigen::ColMajor, Capacity, 1>;

  /// Each phasor and decay moved on by a step and the move (dx, dy, dz),
  /// whose largest phase or exponent change is `reach` (see WaveMove).
  void rotate(double dx, double dy, double dz, double reach) noexcept {
    detail::WaveMove m;
    m.squarings = 0;
    for (double r = reach; r > series_argument; r *= 0.5) ++m.squarings;
    m.hx = std::ldexp(dx, -m.squarings);
    m.hy = std::ldexp(dy, -m.squarings);
    m.hz = std::ldexp(-dz, -m.squarings);
    m.n = n_;
    m.kx = kx_.data();
    m.ky = ky_.data();
    m.k = k_.data();
    m.rot_re = rot_re_.data();
    m.rot_im = rot_im_.data();
    m.pre = pre_.data();
    m.pim = pim_.data();
    m.decay = decay_.data();
    m.c = work_[0].data();
    m.s = work_[1].data();
    m.e = work_[2].data();
    detail::rotate_phasors(m);
  }

  /// kinematics() and rates() from the phasors and decays: with
  /// Q_i = e^(-k_i z) e^(i theta_i), v = sum vel_i [cos b_i Re Q_i,
  /// sin b_i Re Q_i, Im Q_i], a = sum acc_i [-cos b_i Im Q_i, -sin b_i Im Q_i,
  /// Re Q_i], and following u, dQ_i/dt = (-k_i u_D + i (w_i - k_i . u)) Q_i.
  Status sum(const Vec3& u) noexcept {
    detail::WaveSums w;
    w.un = static_cast<double>(u.x());
    w.ue = static_cast<double>(u.y());
    // Above the surface z stays 0, as do the decays.
    w.ud = z_ > 0.0 ? static_cast<double>(u.z()) : 0.0;
    w.n = n_;
    w.pre = pre_.data();
    w.pim = pim_.data();
    w.decay = decay_.data();
    w.k = k_.data();
    w.kx = kx_.data();
    w.ky = ky_.data();
    w.omega = omega_.data();
    w.amp = amp_.data();
    w.vcb = vcb_.data();
    w.vsb = vsb_.data();
    w.vel = vel_.data();
    w.acb = acb_.data();
    w.asb = asb_.data();
    w.acc = acc_.data();
    detail::wave_sums(w);
    const double* o = w.out;
    return store(o[0], Eigen::Vector3d(o[1], o[2], o[3]), Eigen::Vector3d(o[4], o[5], o[6]),
                 Eigen::Vector3d(o[7], o[8], o[9]), kin_, rates_);
  }

  /// Writes the sums out; non_finite_output (zeros) if any overflowed (an
  /// extreme Hs or Tp, or a float that cannot hold them).
  static Status store(double zeta, const Eigen::Vector3d& v, const Eigen::Vector3d& a,
                      const Eigen::Vector3d& dv, WaveKinematics<Scalar>& out,
                      WaveRates<Scalar>& rates) noexcept {
    out.elevation = static_cast<Scalar>(zeta);
    out.velocity = v.cast<Scalar>();
    out.acceleration = a.cast<Scalar>();
    rates.velocity = dv.cast<Scalar>();
    if (std::isfinite(static_cast<double>(out.elevation)) &&
        detail::all_finite(out.velocity, out.acceleration, rates.velocity))
      return Status::ok;
    out = WaveKinematics<Scalar>{};
    rates = WaveRates<Scalar>{};
    return Status::non_finite_output;
  }

  /// Phasors, decays, kinematics() and rates() computed directly at time()
  /// and p.
  Status resync(const Vec3& p, const Vec3& u) noexcept {
    x_ = static_cast<double>(p.x());
    y_ = static_cast<double>(p.y());
    z_ = std::max(0.0, static_cast<double>(p.z()));
    const double t = time();
    for (int i = 0; i < n_; ++i) {
      const double theta = omega_[i] * t - (kx_[i] * x_ + ky_[i] * y_) + phase_[i];
      pre_[i] = std::cos(theta);
      pim_[i] = std::sin(theta);
    }
    decay_ = (k_ * -z_).exp();
    return sum(u);
  }

  WaveConfig<Scalar> config_{};
  SpectralDensity spectrum_{};
  int n_ = 0;
  // The components (fixed at create) and the followed point's state, in
  // double whatever Scalar: a float build keeps the phases of a long run.
  Array omega_, k_, amp_, phase_, cos_beta_, sin_beta_, kx_, ky_;
  Array vel_, acc_, vcb_, vsb_, acb_, asb_;  // a w, a w^2, and times cos b, sin b
  Array rot_re_, rot_im_, pre_, pim_, decay_;
  Array work_[3];  // scratch of rotate(), kept here off the stack
  double k_max_ = 0.0;
  double t0_ = 0.0, step_ = 0.0, x_ = 0.0, y_ = 0.0, z_ = 0.0;
  std::int64_t steps_ = 0;
  WaveKinematics<Scalar> kin_{};
  WaveRates<Scalar> rates_{};
  bool valid_ = false, started_ = false;
};

}  // namespace neurov
