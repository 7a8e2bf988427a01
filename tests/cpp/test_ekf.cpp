// The extended Kalman filter on long seeded runs, its sensors the models of
// sim/sensors.hpp: its error against its own covariance (the normalised
// estimation error squared within chi-square bounds), the position estimate
// against the raw acoustic fixes, DVL dropouts and an acoustic blackout, a
// rejected update, and named errors.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/core/random.hpp"
#include "neurov/estimation/ekf.hpp"
#include "neurov/sim/sensors.hpp"
#include "sensor_suite.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;

/// Chi-square quantile by Wilson and Hilferty (relative error < 1e-3 for
/// k >= 100): k (1 - 2/(9k) + z sqrt(2/(9k)))^3.
double chi2_quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

constexpr double kDt = 0.02;

/// The truth: the filter's own random-walk model, integrated in double
/// with ten Euler-Maruyama substeps per filter step.
struct Truth {
  Vector6<double> eta = Vector6<double>::Zero(), nu = Vector6<double>::Zero();
  NormalRandom rng;
  double sigma_v, sigma_w;
  Truth(std::uint64_t seed, double sv, double sw) : rng(seed), sigma_v(sv), sigma_w(sw) {
    eta << 0, 0, 10, 0.05, -0.03, 0.4;
    nu << 0.3, 0.0, 0.0, 0.0, 0.0, 0.01;
  }
  void advance(double dt) {
    const double h = dt / 10;
    for (int s = 0; s < 10; ++s) {
      const auto k = EulerKinematics<double>::from_pose(eta);
      eta += h * k.apply(nu);
      for (int i = 0; i < 3; ++i) nu(i) += sigma_v * std::sqrt(h) * rng.normal();
      for (int i = 3; i < 6; ++i) nu(i) += sigma_w * std::sqrt(h) * rng.normal();
    }
  }
};

template <typename S>
struct Rig {
  EkfConfig<S> config;
  ImuSensor<S> imu;
  DvlSensor<S> dvl;
  DepthSensor<S> depth;
  UsblSensor<S> usbl;
  Ekf<S> ekf;
  double usbl_latency = 0.0;
};

template <typename S>
Rig<S> make_rig(std::uint64_t seed, double usbl_latency, double dvl_dropout, const Truth& truth) {
  Rig<S> r;
  r.config = neurov_test::ekf_noise<S>();
  auto& c = r.config;
  for (int i = 0; i < 3; ++i) {
    c.initial_std(i) = S(1);
    c.initial_std(3 + i) = S(0.02);
    c.initial_std(6 + i) = S(0.05);
    c.initial_std(9 + i) = S(0.01);
    c.initial_std(12 + i) = S(0.002);
  }
  ImuConfig<S> ic;
  ic.rate = 50.0;
  ic.attitude_noise = c.attitude_noise;
  ic.gyro_noise = c.gyro_noise;
  ic.gyro_bias_walk = c.gyro_bias_walk;
  NormalRandom init(seed ^ 0x5A5AULL);
  // The true initial bias and the initial estimate's error are draws from
  // the filter's initial covariance.
  for (int i = 0; i < 3; ++i) ic.gyro_bias(i) = static_cast<S>(0.002 * init.normal());
  DvlConfig<S> dc;
  dc.rate = 5.0;
  dc.noise = c.dvl_noise;
  dc.dropout_rate = dvl_dropout;
  DepthConfig<S> pc;
  pc.rate = 10.0;
  pc.noise = c.depth_noise;
  UsblConfig<S> uc;
  uc.rate = 1.0;
  uc.noise = c.position_noise;
  uc.latency = usbl_latency;
  r.usbl_latency = usbl_latency;
  EXPECT_TRUE(ImuSensor<S>::create(ic, seed, r.imu).ok());
  EXPECT_TRUE(DvlSensor<S>::create(dc, seed, r.dvl).ok());
  EXPECT_TRUE(DepthSensor<S>::create(pc, seed, r.depth).ok());
  EXPECT_TRUE(UsblSensor<S>::create(uc, seed, r.usbl).ok());
  Vector6<S> eta0, nu0;
  for (int i = 0; i < 6; ++i) {
    eta0(i) = static_cast<S>(truth.eta(i) + static_cast<double>(c.initial_std(i)) * init.normal());
    nu0(i) = static_cast<S>(truth.nu(i) + static_cast<double>(c.initial_std(6 + i)) * init.normal());
  }
  EXPECT_TRUE(Ekf<S>::create(c, eta0, nu0, r.ekf).ok());
  return r;
}

/// One filter step at time t (after the truth moved there): predict, then
/// every reading the sensors deliver. Fixes are skipped inside `blackout`.
template <typename S>
void filter_step(Rig<S>& r, const Truth& truth, double t, double blackout_from = -1,
                 double blackout_to = -1, const std::vector<Vector3<double>>* history = nullptr,
                 double* fix_error2 = nullptr, int* fixes = nullptr) {
  const Vector6<S> eta = truth.eta.cast<S>(), nu = truth.nu.cast<S>();
  r.imu.sample(t, eta, nu);
  r.dvl.sample(t, eta, nu);
  r.depth.sample(t, eta, nu);
  r.usbl.sample(t, eta, nu);
  ASSERT_EQ(r.ekf.predict(S(kDt)), Status::ok);
  typename ImuSensor<S>::Reading mi;
  while (r.imu.read(t, mi)) {
    ASSERT_EQ(r.ekf.update_attitude(mi.value.template head<3>()), Status::ok);
    ASSERT_EQ(r.ekf.update_gyro(mi.value.template tail<3>()), Status::ok);
  }
  typename DvlSensor<S>::Reading md;
  while (r.dvl.read(t, md))
    if (md.valid) {
      ASSERT_EQ(r.ekf.update_dvl(md.value), Status::ok);
    }
  typename DepthSensor<S>::Reading mp;
  while (r.depth.read(t, mp)) ASSERT_EQ(r.ekf.update_depth(mp.value(0)), Status::ok);
  typename UsblSensor<S>::Reading mu;
  while (r.usbl.read(t, mu)) {
    if (t >= blackout_from && t < blackout_to) continue;
    if (history) {
      // The fix against the truth at the time it was taken (t - latency).
      const auto step = static_cast<std::size_t>(std::lround(mu.time / kDt));
      *fix_error2 += (mu.value.template cast<double>() - (*history)[step]).squaredNorm();
      ++*fixes;
    }
    ASSERT_EQ(r.ekf.update_position(mu.value, static_cast<S>(t - mu.time)), Status::ok);
  }
}

template <typename S>
double nees(const Rig<S>& r, const Truth& truth) {
  Eigen::Matrix<double, kEkfStates, 1> e;
  e.head<6>() = truth.eta - r.ekf.eta().template cast<double>();
  e.segment<6>(6) = truth.nu - r.ekf.nu().template cast<double>();
  e.tail<3>() = r.imu.gyro_bias().template cast<double>() - r.ekf.gyro_bias().template cast<double>();
  for (int i = 3; i < 6; ++i) e(i) = std::remainder(e(i), 2 * neurov_test::kPi);
  const Eigen::Matrix<double, kEkfStates, kEkfStates> p = r.ekf.covariance().template cast<double>();
  return e.dot(p.ldlt().solve(e));
}

NEUROV_SCALAR_SUITE(EkfTest);

TYPED_TEST(EkfTest, ErrorIsConsistentWithItsCovariance) {
  using S = TypeParam;
  // 20 seeded runs of 60 s; the average NEES over the runs at each second
  // lies in the two-sided 95% interval of chi2(20 * 15) / 20 at least 90%
  // of the time, and the average over the whole run within its 99% interval.
  constexpr int runs = 20, seconds = 60, steps_per_second = 50;
  double anees[seconds] = {};
  for (int run = 0; run < runs; ++run) {
    Truth truth(1000 + run, 0.02, 0.002);
    Rig<S> rig = make_rig<S>(run + 1, 0.0, 0.0, truth);
    for (int k = 1; k <= seconds * steps_per_second; ++k) {
      truth.advance(kDt);
      filter_step(rig, truth, k * kDt);
      if (k % steps_per_second == 0) anees[k / steps_per_second - 1] += nees(rig, truth) / runs;
    }
  }
  const double dof = runs * kEkfStates;
  const double lo = chi2_quantile(dof, -1.959964) / runs, hi = chi2_quantile(dof, 1.959964) / runs;
  int inside = 0;
  double mean = 0;
  for (double a : anees) {
    inside += a >= lo && a <= hi;
    mean += a / seconds;
  }
  EXPECT_GE(inside, 0.9 * seconds) << "ANEES inside [" << lo << ", " << hi << "] " << inside
                                   << " of " << seconds << " s; mean " << mean;
  const double all = dof * seconds;
  EXPECT_GE(mean, chi2_quantile(all, -2.575829) / (runs * seconds));
  EXPECT_LE(mean, chi2_quantile(all, 2.575829) / (runs * seconds));
}

TYPED_TEST(EkfTest, PositionBeatsTheRawFixesThroughDropoutsAndABlackout) {
  using S = TypeParam;
  // 600 s with 0.5 s of acoustic latency, 30% of DVL samples lost and no
  // acoustic fix from 300 s to 360 s.
  Truth truth(77, 0.02, 0.0005);
  Rig<S> rig = make_rig<S>(77, 0.5, 0.3, truth);
  double est2 = 0, fix2 = 0, worst_sigma = 0, blackout_growth = 0, before = 0;
  int count = 0, fixes = 0;
  std::vector<Vector3<double>> history(1, truth.eta.head<3>());
  for (int k = 1; k <= 30000; ++k) {
    const double t = k * kDt;
    truth.advance(kDt);
    history.push_back(truth.eta.head<3>());
    filter_step(rig, truth, t, 300.0, 360.0, &history, &fix2, &fixes);
    const Vector3<double> e =
        truth.eta.head<3>() - rig.ekf.eta().template head<3>().template cast<double>();
    const Matrix3<double> p =
        rig.ekf.covariance().template topLeftCorner<3, 3>().template cast<double>();
    if (t > 20) {
      est2 += e.squaredNorm();
      ++count;
      worst_sigma = std::max(worst_sigma, std::sqrt(e.dot(p.ldlt().solve(e))));
    }
    if (std::abs(t - 300.0) < 1e-9) before = std::sqrt(p.trace());
    if (std::abs(t - 359.0) < 1e-9) blackout_growth = std::sqrt(p.trace()) / before;
  }
  const double est_rms = std::sqrt(est2 / count);
  // The raw fixes err by noise * sqrt(3) in 3D rms: 0.866 m.
  EXPECT_LT(est_rms, 0.5 * 0.5 * std::sqrt(3.0)) << "estimate rms " << est_rms << " m";
  EXPECT_GT(blackout_growth, 1.0) << "the covariance must grow without fixes";
  EXPECT_LT(worst_sigma, 6.0) << "largest Mahalanobis position error";
}

TYPED_TEST(EkfTest, ARejectedUpdateLeavesTheEstimateAsItWas) {
  using S = TypeParam;
  Truth truth(1, 0.02, 0.002);
  Rig<S> rig = make_rig<S>(1, 0.0, 0.0, truth);
  const auto x = rig.ekf.state();
  const auto p = rig.ekf.covariance();
  Vector3<S> z = Vector3<S>::Zero();
  z(1) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(rig.ekf.update_dvl(z), Status::non_finite_input);
  EXPECT_EQ(rig.ekf.update_position(Vector3<S>::Zero(), S(-1)), Status::invalid_argument);
  EXPECT_EQ(rig.ekf.predict(S(0)), Status::invalid_argument);
  EXPECT_EQ(rig.ekf.predict(std::numeric_limits<S>::infinity()), Status::non_finite_input);
  EXPECT_EQ(rig.ekf.state(), x);
  EXPECT_EQ(rig.ekf.covariance(), p);
  Ekf<S> empty;
  EXPECT_EQ(empty.predict(S(0.1)), Status::invalid_argument);
  EXPECT_EQ(empty.update_depth(S(1)), Status::invalid_argument);
}

TYPED_TEST(EkfTest, BadConfigurationsAreNamedErrors) {
  using S = TypeParam;
  Truth truth(1, 0.02, 0.002);
  const EkfConfig<S> good = make_rig<S>(1, 0.0, 0.0, truth).config;
  Ekf<S> ekf;
  const auto name = [&](const EkfConfig<S>& c) {
    const ValidationError e = Ekf<S>::create(c, Vector6<S>::Zero(), Vector6<S>::Zero(), ekf);
    return std::string(e.ok() ? "ok" : e.field);
  };
  EXPECT_EQ(name(good), "ok");
  auto c = good;
  c.linear_acceleration_noise = S(-1);
  EXPECT_EQ(name(c), "estimator.linear_acceleration_noise");
  c = good;
  c.gyro_bias_walk = S(-1);
  EXPECT_EQ(name(c), "estimator.gyro_bias_walk");
  c = good;
  c.position_noise = S(0);
  EXPECT_EQ(name(c), "estimator.position_noise");
  c = good;
  c.initial_std(7) = S(0);
  EXPECT_EQ(name(c), "estimator.initial_std");
  Vector6<S> eta = Vector6<S>::Zero();
  eta(4) = std::numeric_limits<S>::infinity();
  EXPECT_STREQ(Ekf<S>::create(good, eta, Vector6<S>::Zero(), ekf).field, "estimator.initial_eta");
}

}  // namespace
