// The plant's RK4 step in SIMD lanes (model/plant_block.hpp): on every
// kernel path this CPU runs, each lane of a block is rk4_step of that lane's
// run alone, bit for bit in a GCC build for the x86-64 baseline (the lanes
// are compiled without fused multiply-adds, as the scalar step is), and to
// 1e-12 of the state's magnitude elsewhere; with the same status, including
// lanes at the pitch singularity, with a non-finite force, that overflow at
// the first stage or a later one, in a current, at angles past the
// polynomial's range, and part-full blocks. The statuses are also those of
// core/rk4.hpp's stages over Vehicle::derivative, which checks every stage.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "neurov/core/vector_unit.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/plant_block.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"

// A named namespace: the unity build (NEUROV_TEST_UNITY) puts test files in
// one translation unit, where another file's anonymous helpers share names.
namespace plant_block_test {

using namespace neurov;
using neurov::detail::KernelIsa;

struct KernelGuard {
  KernelIsa saved = detail::kernel_isa();
  ~KernelGuard() { detail::set_kernel_isa(saved); }
};

#if defined(__GNUC__) && !defined(__clang__) && !defined(__FMA__)
constexpr bool kBitForBit = true;
#else
constexpr bool kBitForBit = false;  // the scalar step may fuse where the lanes do not
#endif

template <typename S>
struct Lane {
  Vehicle<S> vehicle;
  Vector6<S> eta, nu, tau;
  Vector3<S> current;
  S h;
};

/// Lane j of a varied block: two vehicles with their parameters scaled per
/// lane, states and forces drawn per lane, and the special cases at fixed
/// lanes.
template <typename S>
Lane<S> make_lane(int j, neurov_test::Rng& rng) {
  VehicleParameters<S> p = nerov_parameters<S>();
  if (j % 2) {  // a small, slightly buoyant vehicle with its buoyancy off the z axis
    p.mass = S(13.5);
    p.inertia = Vector3<S>(S(0.26), S(0.23), S(0.37)).asDiagonal();
    p.weight = S(132.4);
    p.buoyancy = S(135.0);
    p.centre_of_buoyancy << S(0.01), S(-0.005), S(-0.06);
    p.added_mass *= S(0.05);
  }
  p.linear_damping *= S(1) + S(0.1) * static_cast<S>(j % 5);
  p.added_mass *= S(1) - S(0.05) * static_cast<S>(j % 3);
  Lane<S> l;
  if (Vehicle<S>::create(p, l.vehicle)) ADD_FAILURE() << "vehicle " << j;
  for (int i = 0; i < 6; ++i) {
    l.eta(i) = rng.uniform<S>(-3.0, 3.0);
    l.nu(i) = rng.uniform<S>(-1.0, 1.0);
    l.tau(i) = rng.uniform<S>(-200.0, 200.0);
  }
  l.current.setZero();
  if (j % 3 == 1) l.current << S(0.3), S(-0.2), S(0.05);
  l.h = S(0.02);
  switch (j) {
    case 2: l.eta(4) = static_cast<S>(M_PI / 2); break;                    // singular pitch
    case 5: l.tau(3) = std::numeric_limits<S>::quiet_NaN(); break;        // bad input
    case 7: l.nu.setConstant(std::numeric_limits<S>::max() / S(4)); break;  // overflows
    case 8: l.nu.setConstant(std::sqrt(std::numeric_limits<S>::max()) / S(64)); break;  // later stage
    case 9: l.eta(5) = S(5000); break;                                     // past |x| <= 1024
    case 11: l.h = S(0.005); break;                                        // another step
    default: break;
  }
  return l;
}

/// The step as core/rk4.hpp takes it over Vehicle::derivative, every stage
/// checked (rk4_step's rules for which status a failure gives).
template <typename S>
Status checked_rk4(const Lane<S>& l, Vector6<S>& eta, Vector6<S>& nu) {
  Vector6<S> eta_next, nu_next;
  const detail::Rk4Outcome r = detail::rk4(
      eta, nu, l.h,
      [&](const Vector6<S>& e, const Vector6<S>& n, Vector6<S>& e_dot, Vector6<S>& n_dot) {
        return l.vehicle.derivative(e, n, l.tau, l.current, e_dot, n_dot);
      },
      [](Status s) { return s == Status::ok || s == Status::near_singularity; }, eta_next, nu_next);
  if (r.stage == 1) return r.status;
  if (r.stage > 1 || !(eta_next.allFinite() && nu_next.allFinite())) return Status::non_finite_output;
  eta = eta_next;
  nu = nu_next;
  return r.status;
}

template <typename S>
void expect_lanes_are_runs_alone(int lanes) {
  neurov_test::Rng rng(11);
  std::vector<Lane<S>> runs;
  for (int j = 0; j < lanes; ++j) runs.push_back(make_lane<S>(j, rng));
  namespace pc = detail::plant_coef;
  PlantBlock<S> block;
  block.lanes = lanes;
  for (int j = 0; j < lanes; ++j) {
    const Lane<S>& l = runs[j];
    for (int f = 0; f < pc::count; ++f) block.coefficients[f][j] = l.vehicle.plant_coefficients()[f];
    for (int i = 0; i < 6; ++i) {
      block.eta[i][j] = l.eta(i);
      block.nu[i][j] = l.nu(i);
      block.tau[i][j] = l.tau(i);
    }
    for (int i = 0; i < 3; ++i) block.current[i][j] = l.current(i);
    block.h[j] = l.h;
  }
  plant_rk4_block(block);
  for (int j = 0; j < lanes; ++j) {
    Lane<S> l = runs[j];
    const Status alone = rk4_step(l.vehicle, l.eta, l.nu, l.tau, l.h, l.current);
    EXPECT_EQ(static_cast<int>(block.status[j]), static_cast<int>(alone)) << "lane " << j;
    Lane<S> ref = runs[j];
    EXPECT_EQ(static_cast<int>(checked_rk4(ref, ref.eta, ref.nu)), static_cast<int>(alone))
        << "lane " << j;
    const S rel = std::is_same_v<S, float> ? S(1e-5) : S(1e-12);
    EXPECT_TRUE(((ref.eta - l.eta).cwiseAbs().array() <= rel * (S(1) + ref.eta.cwiseAbs().array())).all())
        << "lane " << j;
    const double scale = std::max(1.0, static_cast<double>(std::max(l.eta.cwiseAbs().maxCoeff(),
                                                                    l.nu.cwiseAbs().maxCoeff())));
    for (int i = 0; i < 6; ++i) {
      if (kBitForBit) {
        EXPECT_EQ(block.eta[i][j], l.eta(i)) << "lane " << j << " eta " << i;
        EXPECT_EQ(block.nu[i][j], l.nu(i)) << "lane " << j << " nu " << i;
      } else {
        const double tol = (std::is_same_v<S, float> ? 1e-5 : 1e-12) * scale;
        EXPECT_NEAR(block.eta[i][j], l.eta(i), tol) << "lane " << j << " eta " << i;
        EXPECT_NEAR(block.nu[i][j], l.nu(i), tol) << "lane " << j << " nu " << i;
      }
    }
  }
  EXPECT_EQ(static_cast<Status>(block.status[2]), Status::near_singularity);
  EXPECT_EQ(static_cast<Status>(block.status[5]), Status::non_finite_input);
  if (lanes > 7) {
    EXPECT_EQ(static_cast<Status>(block.status[7]), Status::non_finite_output);
    EXPECT_EQ(static_cast<Status>(block.status[8]), Status::non_finite_output);
    EXPECT_EQ(block.nu[0][8], runs[8].nu(0));  // kept as it was
  }
}

template <typename S>
void on_every_path() {
  KernelGuard guard;
  for (KernelIsa isa : {KernelIsa::build, KernelIsa::avx2, KernelIsa::avx512}) {
    if (detail::set_kernel_isa(isa) != isa) continue;
    SCOPED_TRACE(detail::kernel_isa_name());
    for (int lanes : {kPlantBlockWidth, 13, 6}) {
      SCOPED_TRACE(lanes);
      expect_lanes_are_runs_alone<S>(lanes);
    }
  }
}

TEST(PlantBlock, EveryLaneIsItsRunAloneOnEveryPathDouble) { on_every_path<double>(); }
TEST(PlantBlock, EveryLaneIsItsRunAloneOnEveryPathFloat) { on_every_path<float>(); }

TEST(PlantBlock, AFailedLaneKeepsItsStateExactly) {
  neurov_test::Rng rng(3);
  Lane<double> l = make_lane<double>(5, rng);  // NaN force
  const Vector6<double> eta = l.eta, nu = l.nu;
  EXPECT_EQ(rk4_step(l.vehicle, l.eta, l.nu, l.tau, l.h, l.current), Status::non_finite_input);
  EXPECT_EQ(l.eta, eta);
  EXPECT_EQ(l.nu, nu);
}

}  // namespace plant_block_test
