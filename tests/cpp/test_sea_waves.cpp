// Linear deep-water waves: the spectra against their textbook forms, the
// realised surface elevation's estimated spectrum (Welch) against the target
// (Hs, mean periods, peak, energy quartiles), the orbital velocity and
// acceleration variances at depth against linear theory, the recursive
// evaluation against the direct one over a long moving run, and bad input.
// The target spectra and their integrals are written out here, apart from
// the header.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <memory>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/sim/waves.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::kPi;
using neurov_test::record;

constexpr double kG = 9.81;

// ------------------------------------------------------- reference spectra

/// JONSWAP as DNV-RP-C205 (3.5.5) writes it, with A_gamma left free, and
/// Pierson-Moskowitz for gamma = 1, A_gamma = 1.
double jonswap_reference(double w, double hs, double tp, double gamma, double a_gamma) {
  const double wp = 2 * kPi / tp;
  const double sigma = w <= wp ? 0.07 : 0.09;
  const double pm = 5.0 / 16.0 * hs * hs * std::pow(wp, 4) * std::pow(w, -5) *
                    std::exp(-1.25 * std::pow(w / wp, -4));
  return a_gamma * pm * std::pow(gamma, std::exp(-0.5 * std::pow((w - wp) / (sigma * wp), 2)));
}

/// integral of f over (lo, hi) by Simpson's rule on n panels.
template <typename F>
double simpson(F f, double lo, double hi, int n = 200000) {
  const double h = (hi - lo) / n;
  double s = f(lo) + f(hi);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(lo + i * h);
  return s * h / 3.0;
}

/// The test's own target: JONSWAP normalised to m0 = Hs^2 / 16. Its m0
/// without A_gamma is Hs^2 / 16 times the integral of e^(-u) gamma^r(x(u))
/// over u in (0, inf), u = 5/4 (wp / w)^4, which covers the whole tail.
struct Target {
  double hs, tp, gamma, a_gamma;
  Target(double hs_, double tp_, double gamma_) : hs(hs_), tp(tp_), gamma(gamma_), a_gamma(1.0) {
    const double shape = simpson(
        [&](double u) {
          if (u <= 0.0) return 1.0;  // x -> inf: gamma^r -> 1
          const double x = std::pow(1.25 / u, 0.25);
          const double sigma = x <= 1.0 ? 0.07 : 0.09;
          return std::exp(-u) * std::pow(gamma, std::exp(-0.5 * std::pow((x - 1) / sigma, 2)));
        },
        0.0, 60.0);
    a_gamma = 1.0 / shape;
  }
  double operator()(double w) const { return jonswap_reference(w, hs, tp, gamma, a_gamma); }
  /// integral of w^n S(w) e^(-2 k z) over (0.2, 40) wp: at the surface all
  /// but 5/4 * 40^(n - 4) / (4 - n) of it for n < 4; at the depths used
  /// below, e^(-2kz) leaves nothing above 40 wp.
  double moment(int n, double z = 0.0) const {
    const double wp = 2 * kPi / tp;
    return simpson([&](double w) { return std::pow(w, n) * (*this)(w) * std::exp(-2 * w * w / kG * z); },
                   0.2 * wp, 40 * wp);
  }
  /// Young's peak frequency: integral w S^4 / integral S^4.
  double peak_frequency() const {
    const double wp = 2 * kPi / tp;
    const auto s4 = [&](double w) { return std::pow((*this)(w), 4); };
    return simpson([&](double w) { return w * s4(w); }, 0.2 * wp, 40 * wp) /
           simpson(s4, 0.2 * wp, 40 * wp);
  }
};

TEST(WaveSpectrum, MatchesTheReferenceFormsAndHasTheAskedHs) {
  for (const double gamma : {1.0, 2.0, 3.3, 7.0}) {
    WaveConfig<double> c;
    c.hs = 2.5;
    c.tp = 9.0;
    c.gamma = gamma;
    const auto s = SpectralDensity::from(c);
    const Target t(2.5, 9.0, gamma);
    // Both normalisations reach m0 = Hs^2 / 16, so the densities agree.
    for (double w = 0.3; w < 5.0; w += 0.01)
      ASSERT_NEAR(s(w), t(w), 1e-9 * t(2 * kPi / 9.0)) << "gamma " << gamma << " w " << w;
    // DNV's fit 1 - 0.287 ln(gamma) is within about 1 % of the exact factor.
    EXPECT_NEAR(s.normalisation, 1.0 - 0.287 * std::log(gamma), 0.012) << gamma;
    record("normalisation_gamma_" + std::to_string(gamma), s.normalisation);
    record("dnv_fit_error_gamma_" + std::to_string(gamma),
           (1.0 - 0.287 * std::log(gamma)) / s.normalisation - 1.0);
  }
  // The two-parameter form is the ITTC spectrum 173 Hs^2 T1^-4 w^-5
  // exp(-691 T1^-4 w^-4) with T1 = 0.772 Tp (to the rounding of 173 and 691).
  WaveConfig<double> c;
  c.spectrum = WaveSpectrum::pierson_moskowitz;
  c.hs = 3.0;
  c.tp = 10.0;
  c.gamma = 0.5;  // not used by pierson_moskowitz, so not checked
  ASSERT_TRUE(validate(c, 200).ok());
  const auto s = SpectralDensity::from(c);
  const double t1 = std::pow(691.0 / (1.25 * std::pow(2 * kPi, 4)), 0.25) * 10.0;
  EXPECT_NEAR(t1 / 10.0, 0.772, 0.001);
  for (double w = 0.3; w < 4.0; w += 0.01) {
    const double ittc = 173.0 * 9.0 / std::pow(t1, 4) * std::pow(w, -5) *
                        std::exp(-691.0 / std::pow(t1, 4) * std::pow(w, -4));
    ASSERT_NEAR(s(w), ittc, 2e-3 * s(2 * kPi / 10.0)) << w;
  }
}

// --------------------------------------------------------- realised record

/// In-place radix-2 FFT (n a power of two).
void fft(std::vector<std::complex<double>>& a) {
  const std::size_t n = a.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(a[i], a[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const std::complex<double> wl = std::polar(1.0, -2 * kPi / static_cast<double>(len));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w = 1.0;
      for (std::size_t k = 0; k < len / 2; ++k, w *= wl) {
        const auto u = a[i + k], v = a[i + k + len / 2] * w;
        a[i + k] = u + v;
        a[i + k + len / 2] = u - v;
      }
    }
  }
}

/// Welch's estimate of the one-sided density in w [rad/s] of a record sampled
/// every dt: Hann window, segments of `seg` samples, half overlap. Returns
/// S at w_j = j * dw, j = 0 .. seg / 2.
std::vector<double> welch(const std::vector<double>& x, double dt, std::size_t seg, double& dw) {
  std::vector<double> window(seg), s(seg / 2 + 1, 0.0);
  double u = 0;
  for (std::size_t i = 0; i < seg; ++i) {
    window[i] = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(i) / seg);
    u += window[i] * window[i];
  }
  int count = 0;
  std::vector<std::complex<double>> buf(seg);
  for (std::size_t start = 0; start + seg <= x.size(); start += seg / 2, ++count) {
    double mean = 0;
    for (std::size_t i = 0; i < seg; ++i) mean += x[start + i];
    mean /= seg;
    for (std::size_t i = 0; i < seg; ++i) buf[i] = window[i] * (x[start + i] - mean);
    fft(buf);
    for (std::size_t j = 0; j <= seg / 2; ++j) s[j] += std::norm(buf[j]);
  }
  dw = 2 * kPi / (dt * seg);
  // Periodogram in w: |X|^2 dt / (2 pi U), doubled for one side.
  for (std::size_t j = 0; j <= seg / 2; ++j)
    s[j] *= (j == 0 || j == seg / 2 ? 1.0 : 2.0) * dt / (2 * kPi * u * count);
  return s;
}

/// The elevation at the origin over `duration`, one sample every dt.
template <int Cap>
std::vector<double> elevation_record(Waves<double, Cap>& w, double duration, double dt) {
  EXPECT_EQ(w.start(0.0, Eigen::Vector3d::Zero(), dt), Status::ok);
  const auto n = static_cast<std::size_t>(duration / dt);
  std::vector<double> z(n);
  for (std::size_t i = 0; i < n; ++i) {
    z[i] = w.kinematics().elevation;
    EXPECT_EQ(w.advance(Eigen::Vector3d::Zero()), Status::ok);
  }
  return z;
}

struct Case {
  WaveSpectrum spectrum;
  double hs, tp, gamma;
  std::uint64_t seed;
};

// Without this GoogleTest prints a parameter byte by byte, its padding
// included, which valgrind reports as a read of uninitialised memory.
void PrintTo(const Case& c, std::ostream* os) {
  *os << (c.spectrum == WaveSpectrum::jonswap ? "jonswap" : "pierson_moskowitz") << " Hs " << c.hs
      << " Tp " << c.tp << " gamma " << c.gamma << " seed " << c.seed;
}

class WaveRecord : public ::testing::TestWithParam<Case> {};

// Hs = 4 sqrt(m0), T1 = 2 pi m0 / m1, Tz = 2 pi sqrt(m0 / m2), the peak
// period (Young's estimator on both) and
// the frequencies below which 25, 50 and 75 % of m0 lie: each from the
// Welch estimate of a six-hour record against the target, within 5 %.
TEST_P(WaveRecord, EstimatedSpectrumMatchesTheTarget) {
  const Case k = GetParam();
  WaveConfig<double> c;
  c.spectrum = k.spectrum;
  c.hs = k.hs;
  c.tp = k.tp;
  c.gamma = k.gamma;
  c.components = 200;
  auto w = std::make_unique<Waves<double>>();
  ASSERT_TRUE(Waves<double>::create(c, k.seed, *w).ok());
  const double dt = 0.25;
  const std::vector<double> z = elevation_record(*w, 6 * 3600.0, dt);
  double dw = 0;
  const std::vector<double> s = welch(z, dt, 4096, dw);
  double m0 = 0, m1 = 0, m2 = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    const double wj = j * dw;
    m0 += s[j] * dw;
    m1 += wj * s[j] * dw;
    m2 += wj * wj * s[j] * dw;
  }
  // The peak frequency by Young's estimator, integral w S^4 / integral S^4,
  // which averages over the peak instead of picking one noisy bin.
  double s4 = 0, ws4 = 0;
  for (std::size_t j = 0; j < s.size(); ++j) {
    s4 += std::pow(s[j], 4);
    ws4 += j * dw * std::pow(s[j], 4);
  }
  const Target t(k.hs, k.tp, k.spectrum == WaveSpectrum::jonswap ? k.gamma : 1.0);
  const double t0 = t.moment(0), t1 = t.moment(1), t2 = t.moment(2);
  const double hs = 4 * std::sqrt(m0), T1 = 2 * kPi * m0 / m1, Tz = 2 * kPi * std::sqrt(m0 / m2);
  const double T1_target = 2 * kPi * t0 / t1, Tz_target = 2 * kPi * std::sqrt(t0 / t2);
  const double tp = 2 * kPi / (ws4 / s4), tp_target = 2 * kPi / t.peak_frequency();
  EXPECT_NEAR(hs / k.hs, 1.0, 0.05);
  EXPECT_NEAR(T1 / T1_target, 1.0, 0.05);
  EXPECT_NEAR(Tz / Tz_target, 1.0, 0.05);
  // The flat top of Pierson-Moskowitz leaves its peak ill-defined in a
  // record (6 % off for case 2): its periods are checked by T1 and Tz.
  if (k.spectrum == WaveSpectrum::jonswap) {
    EXPECT_NEAR(tp / tp_target, 1.0, 0.05);
  }
  record("hs_error", hs / k.hs - 1);
  record("t1_error", T1 / T1_target - 1);
  record("tz_error", Tz / Tz_target - 1);
  record("tp_error", tp / tp_target - 1);
  // Energy quartiles: where the cumulative m0 reaches 25, 50, 75 %.
  const double wp = 2 * kPi / k.tp;
  for (const double q : {0.25, 0.5, 0.75}) {
    double acc = 0, w_est = 0;
    for (std::size_t j = 0; j < s.size() && acc < q * m0; ++j) acc += s[j] * dw, w_est = j * dw;
    double acc_t = 0, w_t = 0;
    const double h = 1e-4 * wp;
    for (w_t = 0.2 * wp; acc_t < q * t0; w_t += h) acc_t += t(w_t) * h;
    EXPECT_NEAR(w_est / w_t, 1.0, 0.05) << "quartile " << q;
    record("quartile_" + std::to_string(q) + "_error", w_est / w_t - 1);
  }
}

INSTANTIATE_TEST_SUITE_P(
    SeaStates, WaveRecord,
    ::testing::Values(Case{WaveSpectrum::jonswap, 2.0, 8.0, 3.3, 1},
                      Case{WaveSpectrum::jonswap, 3.25, 9.7, 2.0, 2},
                      Case{WaveSpectrum::pierson_moskowitz, 0.88, 7.5, 1.0, 3}),
    [](const auto& info) { return "case" + std::to_string(info.index); });

// The variance of each NED component of the orbital velocity and
// acceleration at depth z, from a three-hour record, against linear theory:
// horizontal var = integral w^2 S e^(-2kz) dw (split cos^2 / sin^2 between
// north and east for long-crested waves), vertical the same; acceleration
// with w^4. The realised energy is the target's (the band holds all but
// 0.1 % of m0 and its amplitudes are scaled to Hs).
TEST(Waves, OrbitalVelocityAndAccelerationVarianceAtDepthFollowLinearTheory) {
  WaveConfig<double> c;
  c.hs = 2.0;
  c.tp = 8.0;
  c.gamma = 3.3;
  c.direction = 30.0;
  auto w = std::make_unique<Waves<double>>();
  ASSERT_TRUE(Waves<double>::create(c, 21, *w).ok());
  const Target t(2.0, 8.0, 3.3);
  const double beta = 30.0 * kPi / 180;
  for (const double depth : {2.4, 5.0, 10.0, 20.0}) {
    SCOPED_TRACE("depth " + std::to_string(depth));
    const Eigen::Vector3d p(0, 0, depth);
    ASSERT_EQ(w->start(0.0, p, 0.25), Status::ok);
    Eigen::Vector3d v2 = Eigen::Vector3d::Zero(), a2 = Eigen::Vector3d::Zero();
    Eigen::Vector3d v1 = Eigen::Vector3d::Zero(), a1 = Eigen::Vector3d::Zero();
    const int n = static_cast<int>(3 * 3600 / 0.25);
    for (int i = 0; i < n; ++i) {
      const auto& k = w->kinematics();
      v1 += k.velocity;
      a1 += k.acceleration;
      v2 += k.velocity.cwiseAbs2();
      a2 += k.acceleration.cwiseAbs2();
      // Long-crested: every component moves the water along beta.
      ASSERT_NEAR(k.velocity.y(), std::tan(beta) * k.velocity.x(), 1e-12);
      ASSERT_EQ(w->advance(p), Status::ok);
    }
    const Eigen::Vector3d v_var = v2 / n - (v1 / n).cwiseAbs2(), a_var = a2 / n - (a1 / n).cwiseAbs2();
    const double vt = t.moment(2, depth), at = t.moment(4, depth);
    const double cb2 = std::cos(beta) * std::cos(beta), sb2 = std::sin(beta) * std::sin(beta);
    EXPECT_NEAR(v_var.x() / (vt * cb2), 1.0, 0.03);
    EXPECT_NEAR(v_var.y() / (vt * sb2), 1.0, 0.03);
    EXPECT_NEAR(v_var.z() / vt, 1.0, 0.03);
    EXPECT_NEAR(a_var.x() / (at * cb2), 1.0, 0.03);
    EXPECT_NEAR(a_var.z() / at, 1.0, 0.03);
    record("velocity_var_error_z" + std::to_string(depth), v_var.z() / vt - 1);
    record("acceleration_var_error_z" + std::to_string(depth), a_var.z() / at - 1);
  }
}

// The recursive evaluation follows a vehicle on a 20 m circle at 1 m/s that
// bobs between 3 and 7 m, for an hour at 0.05 s, and is compared with
// the direct evaluation at every tenth step: the largest error relative to the
// record's largest value is recorded. (An hour is 72 resyncs, one every
// 1000 steps; the largest error is over every checked step, so it includes
// the end of each stretch between two resyncs.)
NEUROV_SCALAR_SUITE(WaveTracking);

TYPED_TEST(WaveTracking, RecursiveEvaluationMatchesTheDirectSumOverALongMovingRun) {
  using S = TypeParam;
  WaveConfig<S> c;
  c.hs = S(3.25);
  c.tp = S(9.7);
  c.spreading = S(2);
  auto w = std::make_unique<Waves<S>>();
  ASSERT_TRUE(Waves<S>::create(c, 8, *w).ok());
  const double h = 0.05, radius = 20.0, omega = 1.0 / radius;
  const auto at = [&](double t) {
    return Vector3<S>(S(radius * std::cos(omega * t)), S(radius * std::sin(omega * t)),
                      S(5.0 + 2.0 * std::sin(0.1 * t)));
  };
  ASSERT_EQ(w->start(0.0, at(0.0), S(h)), Status::ok);
  double err_zeta = 0, err_v = 0, err_a = 0, max_zeta = 0, max_v = 0, max_a = 0;
  const int n = static_cast<int>(3600 / h);
  WaveKinematics<S> direct;
  for (int i = 1; i <= n; ++i) {
    const Vector3<S> p = at(i * h);
    ASSERT_EQ(w->advance(p), Status::ok);
    if (i % 10 != 0) continue;
    ASSERT_EQ(w->evaluate(w->time(), p, direct), Status::ok);
    const auto& k = w->kinematics();
    err_zeta = std::max(err_zeta, std::abs(double(k.elevation - direct.elevation)));
    err_v = std::max(err_v, double((k.velocity - direct.velocity).cwiseAbs().maxCoeff()));
    err_a = std::max(err_a, double((k.acceleration - direct.acceleration).cwiseAbs().maxCoeff()));
    max_zeta = std::max(max_zeta, std::abs(double(direct.elevation)));
    max_v = std::max(max_v, double(direct.velocity.cwiseAbs().maxCoeff()));
    max_a = std::max(max_a, double(direct.acceleration.cwiseAbs().maxCoeff()));
  }
  EXPECT_NEAR(w->time(), n * double(S(h)), 1e-9);  // the step is S(h)
  // double: the series and rotations are exact to rounding; float: the
  // outputs are rounded to float (both paths compute in double).
  const double tol = std::is_same<S, float>::value ? 1e-6 : 1e-10;
  EXPECT_LT(err_zeta / max_zeta, tol);
  EXPECT_LT(err_v / max_v, tol);
  EXPECT_LT(err_a / max_a, tol);
  record("elevation_error", err_zeta / max_zeta);
  record("velocity_error", err_v / max_v);
  record("acceleration_error", err_a / max_a);

  // A jump of the point is evaluated directly.
  const Vector3<S> far(S(500), S(-300), S(12));
  ASSERT_EQ(w->advance(far), Status::ok);
  ASSERT_EQ(w->evaluate(w->time(), far, direct), Status::ok);
  EXPECT_NEAR(double(w->kinematics().elevation), double(direct.elevation), tol * max_zeta);
  // Refused input leaves time and state as they were.
  const double t_before = w->time();
  const S zeta_before = w->kinematics().elevation;
  EXPECT_EQ(w->advance(Vector3<S>(S(0), std::numeric_limits<S>::quiet_NaN(), S(5))),
            Status::non_finite_input);
  EXPECT_EQ(w->time(), t_before);
  EXPECT_EQ(w->kinematics().elevation, zeta_before);
}

// The deepest trough of ten three-hour records stays above 1.2 Hs, the
// minimum depth the model gives (Rayleigh: exceeded in about 1 % of them).
TEST(Waves, DeepestTroughIsAboveTheMinimumDepth) {
  WaveConfig<double> c;
  c.hs = 2.0;
  c.tp = 8.0;
  auto w = std::make_unique<Waves<double>>();
  double deepest = 0;
  for (std::uint64_t seed = 100; seed < 110; ++seed) {
    ASSERT_TRUE(Waves<double>::create(c, seed, *w).ok());
    const std::vector<double> z = elevation_record(*w, 3 * 3600.0, 0.25);
    deepest = std::max(deepest, -*std::min_element(z.begin(), z.end()));
  }
  EXPECT_LT(deepest, double(w->minimum_depth()));
  EXPECT_GT(deepest, 0.7 * c.hs);  // a Rayleigh sea does reach that deep
  record("deepest_trough_over_hs", deepest / c.hs);
}

TEST(Waves, SpreadingFollowsCosNAndLeavesFrequenciesAndPhasesAlone) {
  WaveConfig<double> c;
  c.components = 2000;
  c.direction = 60.0;
  auto a = std::make_unique<Waves<double, 2048>>();
  auto b = std::make_unique<Waves<double, 2048>>();
  ASSERT_TRUE((Waves<double, 2048>::create(c, 4, *a).ok()));
  c.spreading = 2.0;
  ASSERT_TRUE((Waves<double, 2048>::create(c, 4, *b).ok()));
  // E[cos^2 theta] under cos^n is (n + 1) / (n + 2); its spread over 2000
  // draws is 0.005 for n = 2.
  double c2 = 0;
  for (int i = 0; i < c.components; ++i) {
    ASSERT_EQ(a->frequency(i), b->frequency(i));
    ASSERT_EQ(a->amplitude(i), b->amplitude(i));
    EXPECT_NEAR(a->wave_direction(i), kPi / 3, 1e-12);
    const double theta = b->wave_direction(i) - kPi / 3;
    ASSERT_LT(std::abs(theta), kPi / 2);
    c2 += std::cos(theta) * std::cos(theta);
  }
  EXPECT_NEAR(c2 / c.components, 3.0 / 4.0, 0.025);
  // The same seed gives the same sea; another seed another one.
  auto d = std::make_unique<Waves<double, 2048>>();
  ASSERT_TRUE((Waves<double, 2048>::create(c, 4, *d).ok()));
  WaveKinematics<double> kb, kd;
  const Eigen::Vector3d p(3, 4, 6);
  ASSERT_EQ(b->evaluate(123.4, p, kb), Status::ok);
  ASSERT_EQ(d->evaluate(123.4, p, kd), Status::ok);
  EXPECT_EQ(kb.velocity, kd.velocity);
  ASSERT_TRUE((Waves<double, 2048>::create(c, 5, *d).ok()));
  ASSERT_EQ(d->evaluate(123.4, p, kd), Status::ok);
  EXPECT_NE(kb.velocity, kd.velocity);
}

TEST(Waves, BadInputIsNamed) {
  const neurov_test::BadField<WaveConfig<double>> cases[] = {
      {"hs", [](auto& c) { c.hs = 0.0; }},
      {"hs", [](auto& c) { c.hs = -1.0; }},
      {"tp", [](auto& c) { c.tp = 0.0; }},
      {"tp", [](auto& c) { c.tp = std::nan(""); }},
      {"gamma", [](auto& c) { c.gamma = 0.9; }},
      {"gamma", [](auto& c) { c.gamma = INFINITY; }},
      {"direction", [](auto& c) { c.direction = std::nan(""); }},
      {"spreading", [](auto& c) { c.spreading = -2.0; }},
      {"components", [](auto& c) { c.components = 0; }},
      {"components", [](auto& c) { c.components = 513; }},
      {"spectrum", [](auto& c) { c.spectrum = static_cast<WaveSpectrum>(7); }},
  };
  auto w = std::make_unique<Waves<double>>();
  for (const auto& k : cases) {
    WaveConfig<double> c;
    k.mutate(c);
    const ValidationError e = Waves<double>::create(c, 1, *w);
    EXPECT_STREQ(e.field ? e.field : "(ok)", k.field) << "case " << (&k - cases);
    EXPECT_FALSE(w->valid());
  }
  WaveKinematics<double> out;
  EXPECT_EQ(w->evaluate(0.0, Eigen::Vector3d::Zero(), out), Status::invalid_argument);
  EXPECT_EQ(w->advance(Eigen::Vector3d::Zero()), Status::invalid_argument);
  ASSERT_TRUE(Waves<double>::create(WaveConfig<double>{}, 1, *w).ok());
  EXPECT_EQ(w->start(0.0, Eigen::Vector3d::Zero(), 0.0), Status::invalid_argument);
  const double nan = std::nan("");
  EXPECT_EQ(w->start(nan, Eigen::Vector3d::Zero(), 0.1), Status::non_finite_input);
  EXPECT_EQ(w->evaluate(0.0, Eigen::Vector3d(nan, 0, 0), out), Status::non_finite_input);
  EXPECT_EQ(out.velocity, Eigen::Vector3d::Zero());
}

// A valid but absurd float sea whose kinematics do not fit in a float:
// zeros and non_finite_output, never an infinity.
TEST(Waves, OverflowGivesZerosAndAStatus) {
  WaveConfig<float> c;
  c.hs = 3e38f;
  c.tp = 0.1f;  // omega_p = 63 rad/s: a omega is far above the float range
  auto w = std::make_unique<Waves<float>>();
  ASSERT_TRUE(Waves<float>::create(c, 1, *w).ok());
  WaveKinematics<float> out;
  EXPECT_EQ(w->evaluate(10.0, Eigen::Vector3f::Zero(), out), Status::non_finite_output);
  EXPECT_EQ(out.elevation, 0.0f);
  EXPECT_EQ(out.acceleration, Eigen::Vector3f::Zero());
  EXPECT_EQ(w->start(10.0, Eigen::Vector3f::Zero(), 0.1f), Status::non_finite_output);
  EXPECT_EQ(w->kinematics().velocity, Eigen::Vector3f::Zero());
}

}  // namespace
