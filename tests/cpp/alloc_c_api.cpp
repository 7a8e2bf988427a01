// The on-board chain without a heap: ThrustAllocator (create and allocate,
// with inverse curves) watched by both detectors in float and double, and
// the C interface's allocator and estimator (create, every call) watched by
// the counting operator new. neurov_c is compiled apart, without
// EIGEN_RUNTIME_NO_MALLOC, so Eigen's own check cannot see inside it there;
// its image is checked for heap symbols instead (the Cortex-M7 build's
// check_image.cmake). The counting operator new is in alloc_foundation.cpp.
#include "alloc_probe.hpp"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "neurov/c_api.h"
#include "neurov/model/bluerov2_heavy.hpp"
#include "neurov/model/thrust_allocation.hpp"
#include "neurov/model/thruster_curve.hpp"
#include "curve_tables.hpp"
#include "onboard_params.h"

namespace {

using namespace neurov;
using alloc_probe::watch;
using alloc_probe::Window;

NEUROV_SCALAR_SUITE(OnboardAllocTest);

const double kCommand[] = {-1, -0.1, 0.1, 1}, kThrust[] = {-30, 0, 0, 40};

TYPED_TEST(OnboardAllocTest, ThrustAllocatorDoesNotAllocate) {
  using S = TypeParam;
  using Alloc = ThrustAllocator<S, 8>;
  const ThrusterCurveConfig<S> tc = neurov_test::unit_test_curve<S>(kThrust[0], kThrust[3]);
  auto curve = std::make_unique<ThrusterCurve<S>>();
  auto alloc = std::make_unique<Alloc>();
  ValidationError errors[3];
  Status worst_status = Status::ok;
  volatile double sink = 0;
  const Window w = watch([&] {
    errors[0] = ThrusterCurve<S>::create(tc, *curve);
    Eigen::Matrix<S, 6, 8> b8;
    errors[1] = allocation_matrix(bluerov2_heavy_layout<S>(), b8);
    const typename Alloc::Matrix b = b8;
    const typename Alloc::Vector lo = Alloc::Vector::Constant(8, S(-30)),
                                 hi = Alloc::Vector::Constant(8, S(40));
    errors[2] = Alloc::create(b, lo, hi, typename Alloc::Vector(), Saturation::scale, *alloc);
    const ThrusterCurve<S>* curves[8];
    for (auto& c : curves) c = curve.get();
    typename Alloc::Vector u, command;
    for (int k = 0; k < 200; ++k) {
      Vector6<S> tau;
      tau << S(k), S(-k) / S(2), S(10), S(1), S(-1), S(k) / S(10);
      worst_status = worst(worst_status, alloc->allocate(tau, S(15.5), curves, u, command));
      worst_status = worst(worst_status, alloc->allocate(tau, S(0), nullptr, u, command));
      sink = sink + static_cast<double>(u.sum() + command.sum());
    }
  });
  EXPECT_EQ(w.new_calls, 0) << "operator new was called";
  EXPECT_EQ(w.eigen_failures, 0) << "Eigen allocated (or asserted)";
  for (const auto& e : errors) EXPECT_TRUE(e.ok()) << (e.field ? e.field : "");
  EXPECT_EQ(worst_status, Status::ok);
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

struct alignas(NEUROV_STORAGE_ALIGN) OnboardStorage {
  unsigned char allocator[NEUROV_ALLOCATOR_STORAGE_BYTES(1)];
  unsigned char ekf[NEUROV_EKF_STORAGE_BYTES];
};

TEST(OnboardAllocTestC, TheCAllocatorAndEstimatorDoNotCallOperatorNew) {
  const auto g = bluerov2_heavy_layout<float>();
  float pos[24], dir[24], lo[8], hi[8];
  for (int i = 0; i < 8; ++i) {
    for (int k = 0; k < 3; ++k) {
      pos[3 * i + k] = g[static_cast<std::size_t>(i)].position(k);
      dir[3 * i + k] = g[static_cast<std::size_t>(i)].direction(k);
    }
    lo[i] = -30.0f;
    hi[i] = 40.0f;
  }
  float cmd[4], thr[4];
  for (int i = 0; i < 4; ++i) {
    cmd[i] = static_cast<float>(kCommand[i]);
    thr[i] = static_cast<float>(kThrust[i]);
  }
  neurov_thruster_curve curve{4, cmd, thr, 0.0f, 0.1f, 16.0f, 2.0f};
  const neurov_allocator_params p = onboard_allocator_params(8, pos, dir, lo, hi, &curve);
  const neurov_ekf_params ep = onboard_ekf_params(0.5f);
  auto storage = std::make_unique<OnboardStorage>();
  neurov_allocator* alloc = nullptr;
  neurov_ekf* ekf = nullptr;
  int bad = 0;
  volatile double sink = 0;
  const Window w = watch([&] {
    const float zero6[6] = {0};
    if (neurov_allocator_create(storage->allocator, sizeof storage->allocator, &p, &alloc, nullptr) != NEUROV_STATUS_OK) ++bad;
    if (neurov_ekf_create(storage->ekf, sizeof storage->ekf, &ep, zero6, zero6, &ekf, nullptr) != NEUROV_STATUS_OK) ++bad;
    for (int k = 0; k < 100; ++k) {
      const float tau[6] = {static_cast<float>(k), 5, -3, 1, 0, 2}, z3[3] = {0.01f, 0, 0};
      float commands[8], thrusts[8], eta[6], nu[6], var[NEUROV_EKF_STATES];
      if (neurov_allocator_step(alloc, tau, 15.0f, commands, thrusts) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_predict(ekf, 0.02f) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_update_attitude(ekf, z3) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_update_gyro(ekf, z3) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_update_dvl(ekf, z3) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_update_depth(ekf, 0.1f) != NEUROV_STATUS_OK) ++bad;
      if (neurov_ekf_update_position(ekf, z3, 0.5f) != NEUROV_STATUS_OK) ++bad;
      neurov_ekf_estimate(ekf, eta, nu);
      neurov_ekf_covariance_diagonal(ekf, var);
      sink = sink + static_cast<double>(commands[k % 8] + eta[0] + var[0]);
    }
    if (neurov_ekf_reset(ekf, zero6, zero6) != NEUROV_STATUS_OK) ++bad;
  });
  EXPECT_EQ(w.new_calls, 0) << "operator new was called";
  EXPECT_EQ(bad, 0);
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

}  // namespace
