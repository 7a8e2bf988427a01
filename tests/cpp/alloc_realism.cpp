// The realism components' create and per-step calls must not touch the heap:
// thruster curve (step, inverse), allocation matrix, the four sensors
// (sample, read) and the EKF (predict, every update). The counting operator
// new is defined in alloc_foundation.cpp.
#include "alloc_probe.hpp"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "neurov/estimation/ekf.hpp"
#include "neurov/model/bluerov2_heavy.hpp"
#include "neurov/model/thruster_curve.hpp"
#include "curve_tables.hpp"
#include "neurov/sim/sensing.hpp"
#include "neurov/sim/sensors.hpp"
#include "sensor_suite.hpp"

namespace {

using namespace neurov;
using alloc_probe::watch;
using alloc_probe::Window;

NEUROV_SCALAR_SUITE(RealismAllocTest);

TYPED_TEST(RealismAllocTest, ThrusterCurveSensorsAndEkfDoNotAllocate) {
  using S = TypeParam;
  ThrusterCurveConfig<S> tc = neurov_test::unit_test_curve<S>(-30, 40);
  tc.time_constant = S(0.05);
  tc.slew_rate = S(200);
  EkfConfig<S> ec = neurov_test::ekf_noise<S>();
  ec.initial_std.setConstant(S(0.1));
  const SensorsConfig<S> suite = neurov_test::sensor_suite<S>();
  // Sensors and the EKF hold their state inline (delay lines included).
  auto curve = std::make_unique<ThrusterCurve<S>>();
  auto imu = std::make_unique<ImuSensor<S>>();
  auto dvl = std::make_unique<DvlSensor<S>>();
  auto depth = std::make_unique<DepthSensor<S>>();
  auto usbl = std::make_unique<UsblSensor<S>>();
  auto ekf = std::make_unique<Ekf<S>>();
  ValidationError errors[7];
  Status worst_status = Status::ok;
  volatile double sink = 0;
  Vector6<S> eta = Vector6<S>::Zero(), nu = Vector6<S>::Zero();
  eta(2) = S(10);
  nu(0) = S(0.3);
  nu(5) = S(0.05);

  const Window w = watch([&] {
    errors[0] = ThrusterCurve<S>::create(tc, *curve);
    errors[1] = ImuSensor<S>::create(*suite.imu, 3, *imu);
    errors[2] = DvlSensor<S>::create(*suite.dvl, 3, *dvl);
    errors[3] = DepthSensor<S>::create(*suite.depth, 3, *depth);
    errors[4] = UsblSensor<S>::create(*suite.usbl, 3, *usbl);
    errors[5] = Ekf<S>::create(ec, eta, nu, *ekf);
    Eigen::Matrix<S, 6, 8> b;
    errors[6] = allocation_matrix(bluerov2_heavy_layout<S>(), b);
    for (int k = 1; k <= 500; ++k) {  // 10 s at 50 Hz
      const double t = k * 0.02;
      eta(0) += S(0.3 * 0.02);
      eta(5) += S(0.05 * 0.02);
      const S thrust = b.col(k % 8).template head<3>().norm() * S(10);
      const S command = curve->command_for(thrust, S(15.5));
      worst_status = worst(worst_status, curve->step(command, S(15.5), S(0.02)));
      worst_status = worst(worst_status, imu->sample(t, eta, nu));
      worst_status = worst(worst_status, dvl->sample(t, eta, nu));
      worst_status = worst(worst_status, depth->sample(t, eta, nu));
      worst_status = worst(worst_status, usbl->sample(t, eta, nu));
      worst_status = worst(worst_status, ekf->predict(S(0.02)));
      typename ImuSensor<S>::Reading mi;
      while (imu->read(t, mi)) {
        worst_status = worst(worst_status, ekf->update_attitude(mi.value.template head<3>()));
        worst_status = worst(worst_status, ekf->update_gyro(mi.value.template tail<3>()));
      }
      typename DvlSensor<S>::Reading md;
      while (dvl->read(t, md))
        if (md.valid) worst_status = worst(worst_status, ekf->update_dvl(md.value));
      typename DepthSensor<S>::Reading mp;
      while (depth->read(t, mp)) worst_status = worst(worst_status, ekf->update_depth(mp.value(0)));
      typename UsblSensor<S>::Reading mu;
      while (usbl->read(t, mu))
        worst_status =
            worst(worst_status, ekf->update_position(mu.value, static_cast<S>(t - mu.time)));
      sink = sink + static_cast<double>(curve->thrust() + ekf->state().sum());
    }
  });

  EXPECT_EQ(w.new_calls, 0) << "operator new was called";
  EXPECT_EQ(w.eigen_failures, 0) << "Eigen allocated (or asserted)";
  for (const auto& e : errors) EXPECT_TRUE(e.ok()) << (e.field ? e.field : "");
  EXPECT_EQ(worst_status, Status::ok);
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

}  // namespace
