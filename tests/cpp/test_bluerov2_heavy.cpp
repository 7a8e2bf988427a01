// The BlueROV2 Heavy allocation matrix against its geometry: each column
// [d; r x d] written out component by component, full rank, the decoupling
// the X layout gives, the signs of ArduSub's motor factors for the frame,
// and port/starboard names against y.
#include <cmath>
#include <string>

#include <Eigen/Core>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include "neurov/model/bluerov2_heavy.hpp"
#include "neurov/model/thrusters.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;

NEUROV_SCALAR_SUITE(BlueRov2HeavyTest);

TYPED_TEST(BlueRov2HeavyTest, EveryColumnIsDirectionAndMomentOfItsThruster) {
  using S = TypeParam;
  const auto g = bluerov2_heavy_layout<S>();
  Eigen::Matrix<S, 6, 8> b;
  ASSERT_TRUE(allocation_matrix(g, b).ok());
  const double e = std::is_same<S, float>::value ? 1e-6 : 1e-15;
  for (int i = 0; i < 8; ++i) {
    const double rx = g[i].position.x(), ry = g[i].position.y(), rz = g[i].position.z();
    const double dx = g[i].direction.x(), dy = g[i].direction.y(), dz = g[i].direction.z();
    const double expected[6] = {dx, dy, dz, ry * dz - rz * dy, rz * dx - rx * dz, rx * dy - ry * dx};
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(static_cast<double>(b(k, i)), expected[k], e) << i << "," << k;
  }
  // Horizontal thrusters at 45 deg in the horizontal plane, vertical ones along z.
  const double h = std::sqrt(0.5);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(std::abs(static_cast<double>(b(0, i))), h, e);
    EXPECT_NEAR(std::abs(static_cast<double>(b(1, i))), h, e);
    EXPECT_EQ(b(2, i), S(0));
    EXPECT_EQ(b(2, i + 4), S(1));
  }
  Eigen::FullPivLU<Eigen::Matrix<double, 6, 8>> lu(b.template cast<double>());
  EXPECT_EQ(lu.rank(), 6);
}

TYPED_TEST(BlueRov2HeavyTest, SurgeSwayAndYawUseOnlyTheHorizontalThrusters) {
  using S = TypeParam;
  Eigen::Matrix<S, 6, 8> b;
  ASSERT_TRUE(allocation_matrix(bluerov2_heavy_layout<S>(), b).ok());
  // The horizontal thrusters at ArduSub's forward factors (-1, -1, +1, +1)
  // N: pure surge of 4 cos 45 deg plus the pitch moment of thrust acting
  // 0.085 m below the origin.
  Eigen::Matrix<S, 8, 1> u = Eigen::Matrix<S, 8, 1>::Zero();
  u.template head<4>() << S(-1), S(-1), S(1), S(1);
  const Vector6<S> tau = b * u;
  const double tol = std::is_same<S, float>::value ? 1e-6 : 1e-14;
  EXPECT_NEAR(static_cast<double>(tau(0)), 4 * std::sqrt(0.5), tol);
  EXPECT_NEAR(static_cast<double>(tau(1)), 0.0, tol);
  EXPECT_NEAR(static_cast<double>(tau(2)), 0.0, tol);
  EXPECT_NEAR(static_cast<double>(tau(3)), 0.0, tol);
  EXPECT_NEAR(static_cast<double>(tau(4)), 4 * 0.085 * std::sqrt(0.5), tol);
  EXPECT_NEAR(static_cast<double>(tau(5)), 0.0, tol);
  // The minimum-norm allocation of a pure yaw moment leaves the verticals idle.
  ThrusterConfig<S> tc;
  tc.matrix = b;
  tc.min_thrust = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(8, S(-40));
  tc.max_thrust = Eigen::Matrix<S, Eigen::Dynamic, 1>::Constant(8, S(50));
  Thrusters<S> thrusters;
  ASSERT_TRUE(Thrusters<S>::create(tc, thrusters).ok());
  Vector6<S> yaw = Vector6<S>::Zero();
  yaw(5) = S(2);
  thrusters.command(yaw);
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(static_cast<double>(thrusters.commanded()(i)), 0.0, 1e-5) << i;
  EXPECT_NEAR(static_cast<double>((b * thrusters.commanded())(5)), 2.0, 1e-5);
}

TYPED_TEST(BlueRov2HeavyTest, ColumnsHaveTheSignsOfArduSubsMotorFactors) {
  using S = TypeParam;
  Eigen::Matrix<S, 6, 8> b;
  ASSERT_TRUE(allocation_matrix(bluerov2_heavy_layout<S>(), b).ok());
  // ArduPilot AP_Motors6DOF.cpp, SUB_FRAME_VECTORED_6DOF, per motor: roll,
  // pitch, yaw, throttle, forward, lateral. Throttle is positive up (-z), so
  // heave's sign is -throttle. Zero factors are where the column's entry is
  // zero or (roll and pitch of a horizontal thruster) only the small moment
  // of its 0.085 m depth.
  const int factors[8][6] = {{0, 0, 1, 0, -1, 1},  {0, 0, -1, 0, -1, -1}, {0, 0, -1, 0, 1, 1},
                             {0, 0, 1, 0, 1, -1},  {1, -1, 0, -1, 0, 0},  {-1, -1, 0, -1, 0, 0},
                             {1, 1, 0, -1, 0, 0},  {-1, 1, 0, -1, 0, 0}};
  for (int i = 0; i < 8; ++i) {
    const int sign[6] = {factors[i][4], factors[i][5], -factors[i][3],
                         factors[i][0], factors[i][1], factors[i][2]};
    for (int k = 0; k < 6; ++k) {
      const double v = static_cast<double>(b(k, i));
      // Braced: EXPECT_* expand to an if-else of their own.
      if (sign[k] != 0) {
        EXPECT_GT(v * sign[k], 0.0) << "motor " << i + 1 << ", DOF " << k;
      } else if (k < 3 || i >= 4) {
        EXPECT_EQ(v, 0.0) << "motor " << i + 1 << ", DOF " << k;
      }
    }
  }
}

TYPED_TEST(BlueRov2HeavyTest, PortAndStarboardNamesMatchTheSignOfY) {
  using S = TypeParam;
  const auto g = bluerov2_heavy_layout<S>();
  for (int i = 0; i < 8; ++i) {
    const std::string name = kBlueRov2HeavyThrusterNames[i];
    const bool starboard = name.find("starboard") != std::string::npos;
    const bool port = name.find("port") != std::string::npos && !starboard;
    EXPECT_TRUE(starboard != port) << name;
    EXPECT_EQ(starboard, g[i].position.y() > S(0)) << name;
    EXPECT_EQ(name.find("bow") != std::string::npos, g[i].position.x() > S(0)) << name;
    EXPECT_EQ(name.find("vertical") != std::string::npos, g[i].direction.z() != S(0)) << name;
  }
}

TYPED_TEST(BlueRov2HeavyTest, BadLayoutsAreNamedErrors) {
  using S = TypeParam;
  auto g = bluerov2_heavy_layout<S>();
  Eigen::Matrix<S, 6, 8> b = Eigen::Matrix<S, 6, 8>::Constant(S(7));
  g[3].direction = Vector3<S>(S(1), S(1), S(0));
  ValidationError e = allocation_matrix(g, b);
  EXPECT_STREQ(e.field, "thrusters.direction");
  EXPECT_EQ(e.index, 3);
  EXPECT_EQ(b(0, 0), S(7)) << "out must stay untouched";
  g = bluerov2_heavy_layout<S>();
  g[6].position.y() = std::numeric_limits<S>::quiet_NaN();
  e = allocation_matrix(g, b);
  EXPECT_STREQ(e.field, "thrusters.position");
  EXPECT_EQ(e.index, 6);
}

TYPED_TEST(BlueRov2HeavyTest, ALayoutOfAnySizeGivesTheSameMatrix) {
  using S = TypeParam;
  const auto g = bluerov2_heavy_layout<S>();
  Eigen::Matrix<S, 6, 8> fixed;
  ASSERT_TRUE(allocation_matrix(g, fixed).ok());
  Eigen::Matrix<S, 6, Eigen::Dynamic> dynamic(6, 8);
  ASSERT_TRUE(allocation_matrix(g.data(), g.size(), dynamic).ok());
  EXPECT_TRUE((dynamic.array() == fixed.array()).all());
}

}  // namespace
