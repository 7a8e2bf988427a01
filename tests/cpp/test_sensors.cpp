// The sensor models: rates, latency through the delay line, noise and bias
// statistics, dropouts, the gyro bias walk, reproducible and independent
// streams, and named errors for bad configurations.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/sim/sensors.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;

NEUROV_SCALAR_SUITE(SensorsTest);

template <typename S>
Vector6<S> pose_at(double t) {
  Vector6<S> eta;
  eta << S(t), S(2), static_cast<S>(5 + std::sin(t)), S(0.1), S(-0.2), static_cast<S>(0.3 * t);
  return eta;
}

TYPED_TEST(SensorsTest, EachSensorSamplesAtItsRateAndDeliversAfterItsLatency) {
  using S = TypeParam;
  UsblConfig<S> c;
  c.rate = 1.0;
  c.latency = 0.5;
  c.noise = S(0);
  UsblSensor<S> usbl;
  ASSERT_TRUE(UsblSensor<S>::create(c, 1, usbl).ok());
  const double dt = 0.01;
  int delivered = 0;
  for (int k = 0; k <= 10000; ++k) {  // 100 s
    const double t = k * dt;
    ASSERT_EQ(usbl.sample(t, pose_at<S>(t), Vector6<S>::Zero()), Status::ok);
    typename UsblSensor<S>::Reading m;
    while (usbl.read(t, m)) {
      ++delivered;
      // Delivered at the first step at or after sample time + latency.
      EXPECT_NEAR(t - m.time, 0.5, 1e-9);
      EXPECT_NEAR(m.time, std::round(m.time), 1e-9);
      // Without noise, the truth at the sample time.
      EXPECT_NEAR(static_cast<double>(m.value(0)), m.time, 1e-5 * (1 + m.time));
      EXPECT_NEAR(static_cast<double>(m.value(2)), 5 + std::sin(m.time), 1e-5);
    }
  }
  // Samples at 0, 1, ..., 100 s; the one at 100 s is still in flight.
  EXPECT_EQ(delivered, 100);
}

TYPED_TEST(SensorsTest, NoiseAndBiasHaveTheirConfiguredStatistics) {
  using S = TypeParam;
  DepthConfig<S> c;
  c.rate = 10.0;
  c.noise = S(0.02);
  c.bias = S(0.3);
  DepthSensor<S> depth;
  ASSERT_TRUE(DepthSensor<S>::create(c, 42, depth).ok());
  const int n = 20000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double t = k * 0.1;
    ASSERT_EQ(depth.sample(t, pose_at<S>(t), Vector6<S>::Zero()), Status::ok);
    typename DepthSensor<S>::Reading m;
    ASSERT_TRUE(depth.read(t, m));
    const double e = static_cast<double>(m.value(0)) - (5 + std::sin(m.time));
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.3, 4 * 0.02 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.02, 0.02 * 4 / std::sqrt(2.0 * n));
}

TYPED_TEST(SensorsTest, DvlDropsTheConfiguredFractionOfSamples) {
  using S = TypeParam;
  DvlConfig<S> c;
  c.rate = 5.0;
  c.noise = S(0.01);
  c.dropout_rate = 0.1;
  DvlSensor<S> dvl;
  ASSERT_TRUE(DvlSensor<S>::create(c, 3, dvl).ok());
  Vector6<S> nu;
  nu << S(0.5), S(-0.1), S(0.05), S(0), S(0), S(0.1);
  const int n = 20000;
  int lost = 0;
  double sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double t = k * 0.2;
    ASSERT_EQ(dvl.sample(t, Vector6<S>::Zero(), nu), Status::ok);
    typename DvlSensor<S>::Reading m;
    ASSERT_TRUE(dvl.read(t, m));
    if (!m.valid) {
      ++lost;
      continue;
    }
    sum2 += static_cast<double>((m.value - nu.template head<3>()).squaredNorm());
  }
  EXPECT_NEAR(static_cast<double>(lost) / n, 0.1, 4 * std::sqrt(0.09 / n));
  EXPECT_NEAR(std::sqrt(sum2 / (3.0 * (n - lost))), 0.01, 0.01 * 4 / std::sqrt(2.0 * 3 * (n - lost)));
}

TYPED_TEST(SensorsTest, GyroBiasWalksWithTheConfiguredIntensity) {
  using S = TypeParam;
  ImuConfig<S> c;
  c.rate = 50.0;
  c.gyro_bias_walk = S(1e-3);
  c.gyro_noise = S(0);
  ImuSensor<S> imu;
  ASSERT_TRUE(ImuSensor<S>::create(c, 9, imu).ok());
  const Vector6<S> nu = Vector6<S>::Zero();
  Vector3<S> last = imu.gyro_bias();
  double sum2 = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double t = k * 0.02;
    ASSERT_EQ(imu.sample(t, Vector6<S>::Zero(), nu), Status::ok);
    typename ImuSensor<S>::Reading m;
    ASSERT_TRUE(imu.read(t, m));
    // The gyro reads the bias (zero rate, zero noise).
    for (int i = 0; i < 3; ++i) EXPECT_EQ(m.value(3 + i), imu.gyro_bias()(i));
    sum2 += static_cast<double>((imu.gyro_bias() - last).squaredNorm());
    last = imu.gyro_bias();
  }
  // Increments of variance walk^2 * period.
  const double expected = 1e-3 * std::sqrt(0.02);
  EXPECT_NEAR(std::sqrt(sum2 / (3.0 * n)), expected, expected * 4 / std::sqrt(2.0 * 3 * n));
}

TYPED_TEST(SensorsTest, StreamsAreReproducibleAndIndependent) {
  using S = TypeParam;
  UsblConfig<S> uc;
  uc.noise = S(1);
  DvlConfig<S> dc;
  dc.rate = 1.0;
  dc.noise = S(1);
  UsblSensor<S> a, b;
  DvlSensor<S> d;
  ASSERT_TRUE(UsblSensor<S>::create(uc, 5, a).ok());
  ASSERT_TRUE(UsblSensor<S>::create(uc, 5, b).ok());
  ASSERT_TRUE(DvlSensor<S>::create(dc, 5, d).ok());
  const Vector6<S> zero = Vector6<S>::Zero();
  int same_as_dvl = 0;
  for (int k = 0; k < 50; ++k) {
    a.sample(k, zero, zero);
    b.sample(k, zero, zero);
    d.sample(k, zero, zero);
    typename UsblSensor<S>::Reading ma, mb;
    typename DvlSensor<S>::Reading md;
    ASSERT_TRUE(a.read(k, ma) && b.read(k, mb) && d.read(k, md));
    EXPECT_EQ(ma.value, mb.value);
    same_as_dvl += ma.value == md.value;
  }
  EXPECT_EQ(same_as_dvl, 0);
}

TYPED_TEST(SensorsTest, ANonFiniteTruthTakesNoSample) {
  using S = TypeParam;
  DepthConfig<S> c;
  DepthSensor<S> depth;
  ASSERT_TRUE(DepthSensor<S>::create(c, 1, depth).ok());
  Vector6<S> eta = Vector6<S>::Zero();
  eta(2) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(depth.sample(0.0, eta, Vector6<S>::Zero()), Status::non_finite_input);
  typename DepthSensor<S>::Reading m;
  EXPECT_FALSE(depth.read(1.0, m));
  // The sample at 0 s is still due on the next good call.
  EXPECT_EQ(depth.sample(0.0, Vector6<S>::Zero(), Vector6<S>::Zero()), Status::ok);
  EXPECT_TRUE(depth.read(0.0, m));
}

/// What Sensor::create names for a default Config changed by `change`
/// ("ok" when it accepts it).
template <typename Sensor, typename Config, typename Change>
std::string named_error(Change change) {
  Config c;
  change(c);
  Sensor sensor;
  const ValidationError e = Sensor::create(c, 0, sensor);
  return e.ok() ? "ok" : e.field;
}

TYPED_TEST(SensorsTest, BadConfigurationsAreNamedErrors) {
  using S = TypeParam;
  const auto usbl = [](auto change) { return named_error<UsblSensor<S>, UsblConfig<S>>(change); };
  EXPECT_EQ(usbl([](auto& c) { c.rate = -1.0; }), "sensors.usbl.rate");
  EXPECT_EQ(usbl([](auto& c) { c.latency = -0.1; }), "sensors.usbl.latency");
  // 100 samples in flight: more than the delay line holds.
  EXPECT_EQ(usbl([](auto& c) { c.latency = 100.0; }), "sensors.usbl.latency");
  EXPECT_EQ(usbl([](auto& c) { c.noise = S(-0.5); }), "sensors.usbl.noise");
  const auto dvl = [](auto change) { return named_error<DvlSensor<S>, DvlConfig<S>>(change); };
  EXPECT_EQ(dvl([](auto& c) { c.dropout_rate = 1.0; }), "sensors.dvl.dropout_rate");
  EXPECT_EQ(dvl([](auto& c) { c.noise = S(-1); }), "sensors.dvl.noise");
  EXPECT_EQ((named_error<DepthSensor<S>, DepthConfig<S>>([](auto& c) { c.rate = 0.0; })),
            "sensors.depth.rate");
  const auto imu = [](auto change) { return named_error<ImuSensor<S>, ImuConfig<S>>(change); };
  EXPECT_EQ(imu([](auto& c) { c.gyro_bias_walk = S(-1e-5); }), "sensors.imu.gyro_bias_walk");
  EXPECT_EQ(imu([](auto& c) { c.attitude_noise = S(-1); }), "sensors.imu.attitude_noise");
  EXPECT_EQ(imu([](auto&) {}), "ok");
}

}  // namespace
