// The real-time path must not touch the heap: kinematics, dynamics and RK4.
// The two detectors are in alloc_probe.hpp; this file defines the counting
// global operator new they rely on (one per executable) and first shows that
// both detectors do catch an allocation.
#include "alloc_probe.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"

// ------------------------------------------------ counting global operator new

void* operator new(std::size_t size) {
  if (void* p = alloc_probe::counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  if (void* p = alloc_probe::counted_malloc(size)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return alloc_probe::counted_malloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return alloc_probe::counted_malloc(size);
}
void* operator new(std::size_t size, std::align_val_t align) {
  if (void* p = alloc_probe::counted_aligned(size, align)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) {
  if (void* p = alloc_probe::counted_aligned(size, align)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return alloc_probe::counted_aligned(size, align);
}
void* operator new[](std::size_t size, std::align_val_t align, const std::nothrow_t&) noexcept {
  return alloc_probe::counted_aligned(size, align);
}
void operator delete(void* p) noexcept { alloc_probe::release(p); }
void operator delete[](void* p) noexcept { alloc_probe::release(p); }
void operator delete(void* p, std::size_t) noexcept { alloc_probe::release(p); }
void operator delete[](void* p, std::size_t) noexcept { alloc_probe::release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { alloc_probe::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { alloc_probe::release(p); }
void operator delete(void* p, std::align_val_t) noexcept { alloc_probe::release(p); }
void operator delete[](void* p, std::align_val_t) noexcept { alloc_probe::release(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { alloc_probe::release(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { alloc_probe::release(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { alloc_probe::release(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { alloc_probe::release(p); }

namespace {

using namespace neurov;

using alloc_probe::watch;
using alloc_probe::Window;

// ------------------------------------------------------ the detectors can fail

TEST(AllocDetector, CountsAStdVectorAllocation) {
  const Window w = watch([] {
    std::vector<int> v(10);
    alloc_probe::escape(v.data());
  });
  EXPECT_GE(w.new_calls, 1);
}

TEST(AllocDetector, CountsAnEigenDynamicMatrixAllocation) {
  const Window w = watch([] {
    Eigen::MatrixXd m(8, 8);
    alloc_probe::escape(m.data());
  });
  EXPECT_GE(w.eigen_failures, 1);
}

TEST(AllocDetector, QuietWindowCountsNothing) {
  const Window w = watch([] {
    Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Identity();
    alloc_probe::escape(m.data());
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
}

// ------------------------------------------------------------- the hot path

NEUROV_SCALAR_SUITE(HotPathAllocTest);

/// Everything the hot path returns is folded in here so none of it is dead code.
template <typename S, typename Derived>
void consume(volatile double& sink, const Eigen::MatrixBase<Derived>& x) {
  sink = sink + static_cast<double>(x.sum());
}

TYPED_TEST(HotPathAllocTest, KinematicsDynamicsAndRk4DoNotAllocate) {
  using S = TypeParam;
  for (const CoriolisForm form : {CoriolisForm::velocity_independent, CoriolisForm::kirchhoff}) {
    auto p = nerov_parameters<S>();
    p.coriolis_form = form;
    p.centre_of_gravity << S(0.01), S(-0.02), S(0.03);  // every C_RB term non-zero
    const Vehicle<S> vehicle(p);
    ASSERT_TRUE(vehicle.valid());

    Vector6<S> eta, nu, tau;
    eta << S(1), S(2), S(3), S(0.1), S(-0.2), S(0.3);
    nu << S(0.5), S(-0.2), S(0.1), S(0.05), S(-0.1), S(0.2);
    tau << S(10), S(-5), S(3), S(1), S(-2), S(0.5);
    const Vector3<S> current(S(0.3), S(-0.1), S(0.05));
    Status statuses[16] = {};
    volatile double sink = 0;

    const Window w = watch([&] {
      int n = 0;
      Matrix6<S> j, j_inv, j_dot;
      statuses[n++] = jacobian(eta, j);
      statuses[n++] = jacobian_inverse(eta, j_inv);
      statuses[n++] = jacobian_dot(eta, nu, j_dot);
      consume<S>(sink, j + j_inv + j_dot);

      const auto k = EulerKinematics<S>::from_pose(eta);
      statuses[n++] = k.status();
      consume<S>(sink, k.apply(nu) + k.apply_inverse(nu) + k.apply_transpose(nu) +
                           k.apply_dot(nu, tau));
      consume<S>(sink, k.jacobian() + k.jacobian_inverse() + k.jacobian_dot(nu));

      consume<S>(sink, vehicle.coriolis(nu) + vehicle.coriolis_rigid_body(nu) +
                           vehicle.coriolis_added_mass(nu) + vehicle.damping(nu));
      consume<S>(sink, vehicle.coriolis_force(nu) + vehicle.damping_diagonal(nu) +
                           vehicle.restoring(eta) + vehicle.forces(eta, nu));

      Vector6<S> nu_dot, eta_dot;
      statuses[n++] = vehicle.acceleration(eta, nu, tau, nu_dot);
      consume<S>(sink, nu_dot);
      statuses[n++] = vehicle.acceleration(eta, nu, tau, current, nu_dot);
      consume<S>(sink, nu_dot);
      statuses[n++] = vehicle.derivative(eta, nu, tau, current, eta_dot, nu_dot);
      consume<S>(sink, eta_dot + nu_dot);

      Vector6<S> eta_i = eta, nu_i = nu;
      Status worst_step = Status::ok;
      for (int i = 0; i < 1000; ++i)
        worst_step = worst(worst_step, rk4_step(vehicle, eta_i, nu_i, tau, S(0.01)));
      statuses[n++] = worst_step;
      worst_step = Status::ok;
      for (int i = 0; i < 1000; ++i)
        worst_step = worst(worst_step, rk4_step(vehicle, eta_i, nu_i, tau, S(0.01), current));
      statuses[n++] = worst_step;
      consume<S>(sink, eta_i + nu_i);
    });

    EXPECT_EQ(w.new_calls, 0) << "operator new was called in the hot path";
    EXPECT_EQ(w.eigen_failures, 0) << "Eigen allocated (or asserted) in the hot path";
    for (int i = 0; i < 9; ++i) EXPECT_EQ(statuses[i], Status::ok) << "call " << i;
    EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
  }
}

// create() is documented as never allocating, so firmware may build vehicles
// after start-up; the LLT it runs is fixed-size.
TYPED_TEST(HotPathAllocTest, CreateAndValidateDoNotAllocate) {
  using S = TypeParam;
  const auto good = nerov_parameters<S>();
  auto bad = good;
  bad.added_mass(1, 4) = S(5);
  Vehicle<S> vehicle;
  ValidationError e_good, e_bad;
  char buf[256];
  const Window w = watch([&] {
    e_good = Vehicle<S>::create(good, vehicle);
    e_bad = validate(bad);
    e_bad.format(buf, sizeof buf);
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_TRUE(e_good.ok());
  EXPECT_TRUE(vehicle.valid());
  EXPECT_FALSE(e_bad.ok());
}

}  // namespace
