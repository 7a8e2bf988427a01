// The C interface's thrust allocation (neurov_allocator_*): against an
// independent pseudo-inverse (Eigen's complete orthogonal decomposition in
// double) and an independent table interpolation; saturation keeping the
// wrench's direction; bad input refused by name and with neutral commands.
// Float throughout, so the tolerances are float's: a few ulps of the
// largest thrust (2e-5 relative), not the 1e-9 of the double tests.
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include "neurov/c_api.h"
#include "neurov/model/bluerov2_heavy.hpp"
#include "onboard_params.h"

namespace {

constexpr int kN = 8;
using MatB = Eigen::Matrix<double, 6, kN>;
using VecN = Eigen::Matrix<double, kN, 1>;
using Vec6d = Eigen::Matrix<double, 6, 1>;

/// The assumed BlueROV2 Heavy layout as C arrays (n x 3).
struct Layout {
  float positions[3 * kN];
  float directions[3 * kN];
  float min_thrust[kN];
  float max_thrust[kN];
  Layout() {
    const auto g = neurov::bluerov2_heavy_layout<float>();
    for (int i = 0; i < kN; ++i) {
      for (int k = 0; k < 3; ++k) {
        positions[3 * i + k] = g[static_cast<std::size_t>(i)].position(k);
        directions[3 * i + k] = g[static_cast<std::size_t>(i)].direction(k);
      }
      min_thrust[i] = -40.0f;
      max_thrust[i] = 50.0f;
    }
  }
  /// B in double, written out here: column i = [d; r x d].
  MatB matrix() const {
    MatB b;
    for (int i = 0; i < kN; ++i) {
      double r[3], d[3];
      for (int k = 0; k < 3; ++k) {
        r[k] = positions[3 * i + k];
        d[k] = directions[3 * i + k];
      }
      b.col(i) << d[0], d[1], d[2], r[1] * d[2] - r[2] * d[1], r[2] * d[0] - r[0] * d[2],
          r[0] * d[1] - r[1] * d[0];
    }
    return b;
  }
};

/// A T200-like table in PWM microseconds (shape only; not the manufacturer's data).
struct Table {
  std::vector<float> command{1100, 1200, 1300, 1400, 1475, 1525, 1600, 1700, 1800, 1900};
  std::vector<float> thrust{-40, -28, -15, -4.5f, 0, 0, 5.5f, 19, 36, 51};
  neurov_thruster_curve curve() const {
    neurov_thruster_curve c{};
    c.points = static_cast<uint32_t>(command.size());
    c.command = command.data();
    c.thrust = thrust.data();
    c.neutral = 1500.0f;
    c.dead_band = 25.0f;
    c.reference_voltage = 16.0f;
    c.voltage_exponent = 2.0f;
    return c;
  }
  /// The table's thrust at a command, interpolated here independently.
  double at(double c) const {
    if (std::abs(c - 1500.0) <= 25.0) return 0.0;
    for (std::size_t i = 1; i < command.size(); ++i)
      if (c <= command[i]) {
        const double w = (c - command[i - 1]) / (command[i] - command[i - 1]);
        return thrust[i - 1] + w * (thrust[i] - thrust[i - 1]);
      }
    return thrust.back();
  }
};

struct alignas(NEUROV_STORAGE_ALIGN) Storage {
  unsigned char bytes[NEUROV_ALLOCATOR_STORAGE_BYTES(kN)]{};  // zeroed: the tests compare bytes
};

/// The layout l, every thruster on `curve` (none: thrust is the command).
neurov_allocator_params heavy_params(const Layout& l, const neurov_thruster_curve* curve = nullptr) {
  return onboard_allocator_params(kN, l.positions, l.directions, l.min_thrust, l.max_thrust, curve);
}

neurov_allocator* make(Storage& s, const neurov_allocator_params& p) {
  neurov_allocator* a = nullptr;
  neurov_validation_error e{};
  const neurov_status st = neurov_allocator_create(s.bytes, sizeof s.bytes, &p, &a, &e);
  EXPECT_EQ(st, NEUROV_STATUS_OK) << (e.field ? e.field : "") << " " << (e.expected ? e.expected : "");
  return a;
}

VecN step(neurov_allocator* a, const Vec6d& tau, float voltage, VecN* commands = nullptr,
          neurov_status expected = NEUROV_STATUS_OK) {
  float t[6], c[kN], u[kN];
  for (int i = 0; i < 6; ++i) t[i] = static_cast<float>(tau(i));
  EXPECT_EQ(neurov_allocator_step(a, t, voltage, c, u), expected);
  VecN out;
  for (int i = 0; i < kN; ++i) {
    out(i) = u[i];
    if (commands != nullptr) (*commands)(i) = c[i];
  }
  return out;
}

/// The Heavy's layout with one curve, the table's, for all eight thrusters,
/// created in storage of its own.
struct OnTheTable {
  Layout l;
  Table t;
  neurov_thruster_curve curve = t.curve();
  Storage s;
  neurov_allocator* a = make(s, heavy_params(l, &curve));
};

Vec6d attainable_tau() {
  Vec6d tau;
  tau << 20, -10, 15, 1.5, -2, 3;
  return tau;
}

TEST(CAllocation, MatchesTheIndependentPseudoInverseInsideTheAttainableSet) {
  Layout l;
  Storage s;
  neurov_allocator* a = make(s, heavy_params(l));
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(neurov_allocator_thrusters(a), 8u);
  const MatB b = l.matrix();
  const Eigen::Matrix<double, kN, 6> pinv = b.completeOrthogonalDecomposition().pseudoInverse();
  const Vec6d tau = attainable_tau();
  VecN commands;
  const VecN u = step(a, tau, std::nan(""), &commands);  // no curve: the voltage is not read
  const VecN ref = pinv * tau;
  ASSERT_LT(ref.maxCoeff(), 50.0);
  ASSERT_GT(ref.minCoeff(), -40.0);
  EXPECT_LT((u - ref).cwiseAbs().maxCoeff(), 2e-5 * ref.cwiseAbs().maxCoeff());
  EXPECT_LT((b * u - tau).cwiseAbs().maxCoeff(), 2e-5 * tau.cwiseAbs().maxCoeff());
  EXPECT_EQ(commands, u);  // without a curve the commands are the thrusts
}

TEST(CAllocation, TheMatrixFormGivesTheGeometrysAllocation) {
  Layout l;
  const MatB b = l.matrix();
  float rows[6 * kN];
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < kN; ++i) rows[k * kN + i] = static_cast<float>(b(k, i));
  neurov_allocator_params p = heavy_params(l);
  p.positions = p.directions = nullptr;
  p.matrix = rows;
  Storage s1, s2;
  neurov_allocator* from_matrix = make(s1, p);
  neurov_allocator* from_geometry = make(s2, heavy_params(l));
  ASSERT_NE(from_matrix, nullptr);
  ASSERT_NE(from_geometry, nullptr);
  const VecN u1 = step(from_matrix, attainable_tau(), 0.0f);
  const VecN u2 = step(from_geometry, attainable_tau(), 0.0f);
  EXPECT_LT((u1 - u2).cwiseAbs().maxCoeff(), 2e-5 * u2.cwiseAbs().maxCoeff());
}

TEST(CAllocation, WeightsGiveTheWeightedMinimumNormSolution) {
  Layout l;
  float w[kN] = {1, 1, 1, 1, 4, 4, 4, 4};
  neurov_allocator_params p = heavy_params(l);
  p.weights = w;
  Storage s;
  neurov_allocator* a = make(s, p);
  ASSERT_NE(a, nullptr);
  // min sum w_i u_i^2 subject to B u = tau: u = W^-1/2 (B W^-1/2)^+ tau.
  VecN w_inv_sqrt;
  for (int i = 0; i < kN; ++i) w_inv_sqrt(i) = 1.0 / std::sqrt(static_cast<double>(w[i]));
  const MatB bw = l.matrix() * w_inv_sqrt.asDiagonal();
  const VecN ref =
      w_inv_sqrt.asDiagonal() * (bw.completeOrthogonalDecomposition().pseudoInverse() * attainable_tau());
  const VecN u = step(a, attainable_tau(), 0.0f);
  EXPECT_LT((u - ref).cwiseAbs().maxCoeff(), 2e-5 * ref.cwiseAbs().maxCoeff());
}

TEST(CAllocation, ScaleSaturationKeepsTheDirectionAndClipFillsTheLimits) {
  Layout l;
  const MatB b = l.matrix();
  const Vec6d tau = attainable_tau() * 20.0;  // far outside the attainable set
  Storage s;
  neurov_allocator* a = make(s, heavy_params(l));
  ASSERT_NE(a, nullptr);
  const VecN u = step(a, tau, 0.0f);
  const Vec6d got = b * u;
  EXPECT_GT(got.dot(tau) / (got.norm() * tau.norm()), 1.0 - 1e-6);  // same direction
  EXPECT_LT(got.norm(), tau.norm());
  double reach = 0.0;  // some thruster sits on its limit
  for (int i = 0; i < kN; ++i) reach = std::max(reach, u(i) > 0 ? u(i) / 50.0 : u(i) / -40.0);
  EXPECT_NEAR(reach, 1.0, 1e-6);

  neurov_allocator_params p = heavy_params(l);
  p.saturation = NEUROV_SATURATION_CLIP;
  Storage s2;
  neurov_allocator* c = make(s2, p);
  ASSERT_NE(c, nullptr);
  const VecN clipped = step(c, tau, 0.0f);
  const VecN unsaturated = b.completeOrthogonalDecomposition().pseudoInverse() * tau;
  for (int i = 0; i < kN; ++i)
    EXPECT_NEAR(clipped(i), std::min(50.0, std::max(-40.0, unsaturated(i))), 2e-5 * 50.0);
}

TEST(CAllocation, TheInverseCurveGivesCommandsWhoseThrustIsTheAllocation) {
  OnTheTable on;
  auto& [l, t, curve, s, a] = on;
  ASSERT_NE(a, nullptr);
  EXPECT_LE(neurov_allocator_storage_size(1), NEUROV_ALLOCATOR_STORAGE_BYTES(1));
  for (const float volts : {16.0f, 14.8f}) {
    const double k = std::pow(volts / 16.0, 2.0);
    VecN commands;
    const VecN u = step(a, attainable_tau(), volts, &commands);
    for (int i = 0; i < kN; ++i) {
      EXPECT_GE(commands(i), 1100.0);
      EXPECT_LE(commands(i), 1900.0);
      EXPECT_NEAR(t.at(commands(i)) * k, u(i), 2e-5 * 51.0) << "thruster " << i << " at " << volts << " V";
    }
  }
  // No thrust: every command neutral.
  VecN commands;
  step(a, Vec6d::Zero(), 16.0f, &commands);
  for (int i = 0; i < kN; ++i) EXPECT_EQ(commands(i), 1500.0);
}

TEST(CAllocation, ALowBatteryShrinksTheThrustsTheCurveCanGive) {
  OnTheTable on;
  auto& [l, t, curve, s, a] = on;
  ASSERT_NE(a, nullptr);
  const double k = std::pow(12.0 / 16.0, 2.0);  // 51 N forward becomes 28.7 N
  const Vec6d tau = attainable_tau() * 20.0;
  VecN commands;
  const VecN u = step(a, tau, 12.0f, &commands);
  double reach = 0.0;
  for (int i = 0; i < kN; ++i) {
    EXPECT_LE(u(i), 51.0 * k * (1 + 1e-6));
    EXPECT_GE(u(i), -40.0 * k * (1 + 1e-6));
    reach = std::max(reach, u(i) > 0 ? u(i) / (51.0 * k) : u(i) / (-40.0 * k));
  }
  EXPECT_NEAR(reach, 1.0, 1e-5);
  const Vec6d got = l.matrix() * u;
  EXPECT_GT(got.dot(tau) / (got.norm() * tau.norm()), 1.0 - 1e-6);
}

TEST(CAllocation, OneCurvePerThrusterThroughCurveOf) {
  Layout l;
  Table t;
  Table strong;  // a second, stronger curve for the vertical thrusters
  for (float& v : strong.thrust) v *= 2.0f;
  const neurov_thruster_curve curves[2] = {t.curve(), strong.curve()};
  const uint8_t of[kN] = {0, 0, 0, 0, 1, 1, 1, 1};
  neurov_allocator_params p = heavy_params(l);
  p.curve_count = 2;
  p.curves = curves;
  p.curve_of = of;
  Storage s;
  neurov_allocator* a = make(s, p);
  ASSERT_NE(a, nullptr);
  VecN commands;
  const VecN u = step(a, attainable_tau(), 16.0f, &commands);
  for (int i = 0; i < kN; ++i)
    EXPECT_NEAR((i < 4 ? 1.0 : 2.0) * t.at(commands(i)), u(i), 2e-5 * 102.0) << i;
}

TEST(CAllocation, BadInputIsRefusedWithNeutralCommandsAndNothingChanged) {
  OnTheTable on;
  auto& [l, t, curve, s, a] = on;
  ASSERT_NE(a, nullptr);
  VecN before_c;
  const VecN before = step(a, attainable_tau(), 16.0f, &before_c);
  unsigned char snapshot[sizeof s.bytes];
  std::memcpy(snapshot, s.bytes, sizeof snapshot);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  struct Case {
    float tau0, voltage;
    neurov_status expected;
  };
  for (const Case c : {Case{nan, 16.0f, NEUROV_STATUS_NON_FINITE_INPUT},
                       Case{inf, 16.0f, NEUROV_STATUS_NON_FINITE_INPUT},
                       Case{1.0f, nan, NEUROV_STATUS_NON_FINITE_INPUT},
                       Case{1.0f, 0.0f, NEUROV_STATUS_INVALID_ARGUMENT},
                       Case{1.0f, -12.0f, NEUROV_STATUS_INVALID_ARGUMENT}}) {
    float tau[6] = {c.tau0, 0, 0, 0, 0, 0}, commands[kN], thrusts[kN];
    EXPECT_EQ(neurov_allocator_step(a, tau, c.voltage, commands, thrusts), c.expected);
    EXPECT_EQ(neurov_allocator_status(a), c.expected);
    for (int i = 0; i < kN; ++i) {
      EXPECT_EQ(commands[i], 1500.0f);
      EXPECT_EQ(thrusts[i], 0.0f);
    }
  }
  float commands[kN];
  EXPECT_EQ(neurov_allocator_step(a, nullptr, 16.0f, commands, nullptr), NEUROV_STATUS_INVALID_ARGUMENT);
  for (int i = 0; i < kN; ++i) EXPECT_EQ(commands[i], 1500.0f);
  // Only the recorded status differs from before the refusals.
  reinterpret_cast<neurov_status*>(s.bytes + 4)[0] = NEUROV_STATUS_OK;
  EXPECT_EQ(std::memcmp(snapshot, s.bytes, sizeof snapshot), 0);
  VecN after_c;
  EXPECT_EQ(step(a, attainable_tau(), 16.0f, &after_c), before);
  EXPECT_EQ(after_c, before_c);
}

TEST(CAllocation, CreateNamesTheBadArgument) {
  struct Case {
    const char* field;
    int index;
    void (*change)(neurov_allocator_params&, Layout&, neurov_thruster_curve&);
  };
  const Case cases[] = {
      {"thrusters", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.thrusters = 5; }},
      {"thrusters", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.thrusters = 9; }},
      {"matrix", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.positions = nullptr; }},
      {"min_thrust", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.min_thrust = nullptr; }},
      {"thrusters.direction", 3, [](neurov_allocator_params&, Layout& l, neurov_thruster_curve&) { l.directions[9] = 0.5f; }},
      {"thrusters.position", 6, [](neurov_allocator_params&, Layout& l, neurov_thruster_curve&) { l.positions[19] = NAN; }},
      {"thrusters.max_thrust", 2, [](neurov_allocator_params&, Layout& l, neurov_thruster_curve&) { l.min_thrust[2] = 1.0f; }},
      {"thrusters.min_thrust", 1, [](neurov_allocator_params&, Layout& l, neurov_thruster_curve&) { l.min_thrust[1] = NAN; }},
      {"thrusters.matrix", -1, [](neurov_allocator_params&, Layout& l, neurov_thruster_curve&) {
         for (int i = 4; i < 8; ++i) l.directions[3 * i + 2] = 0.0f, l.directions[3 * i] = 1.0f;  // no heave
       }},
      {"saturation", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.saturation = static_cast<neurov_saturation>(7); }},
      {"curve_count", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.curve_count = 9; }},
      {"curve_of", -1, [](neurov_allocator_params& p, Layout&, neurov_thruster_curve&) { p.curve_count = 2; }},
      {"thruster_curve.points", -1, [](neurov_allocator_params&, Layout&, neurov_thruster_curve& c) { c.points = 1; }},
      {"thruster_curve.reference_voltage", -1, [](neurov_allocator_params&, Layout&, neurov_thruster_curve& c) { c.reference_voltage = 0.0f; }},
      {"thruster_curve.thrust", 9, [](neurov_allocator_params&, Layout&, neurov_thruster_curve& c) {
         const_cast<float*>(c.thrust)[8] = 60.0f;  // 1800 us above 1900 us: not monotonic
       }},
  };
  for (const Case& c : cases) {
    Layout layout;
    Table table;
    neurov_thruster_curve curve = table.curve();
    std::vector<neurov_thruster_curve> curves(2, curve);
    neurov_allocator_params p = heavy_params(layout, curves.data());
    c.change(p, layout, curves[0]);
    Storage s;
    std::memset(s.bytes, 0xCD, sizeof s.bytes);
    neurov_allocator* a = reinterpret_cast<neurov_allocator*>(&p);
    neurov_validation_error e{};
    EXPECT_EQ(neurov_allocator_create(s.bytes, sizeof s.bytes, &p, &a, &e), NEUROV_STATUS_INVALID_ARGUMENT) << c.field;
    EXPECT_EQ(a, nullptr);
    ASSERT_NE(e.field, nullptr) << c.field;
    EXPECT_STREQ(e.field, c.field);
    EXPECT_EQ(e.index, c.index) << c.field;
    EXPECT_NE(e.expected, nullptr);
    float commands[kN], tau[6] = {0};
    EXPECT_EQ(neurov_allocator_step(reinterpret_cast<neurov_allocator*>(s.bytes), tau, 16.0f, commands, nullptr),
              NEUROV_STATUS_INVALID_ARGUMENT) << "a refused create leaves no object: " << c.field;
  }
}

TEST(CAllocation, StorageTooSmallOrMisalignedIsRefused) {
  Layout l;
  const neurov_allocator_params p = heavy_params(l);
  Storage s;
  neurov_allocator* a = nullptr;
  neurov_validation_error e{};
  EXPECT_EQ(neurov_allocator_create(s.bytes, neurov_allocator_storage_size(0) - 1, &p, &a, &e),
            NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_STREQ(e.field, "size");
  Table t;
  neurov_thruster_curve curve = t.curve();
  const neurov_allocator_params pc = heavy_params(l, &curve);
  EXPECT_EQ(neurov_allocator_create(s.bytes, neurov_allocator_storage_size(0), &pc, &a, &e),
            NEUROV_STATUS_INVALID_ARGUMENT);  // room for the layout, not the curve
  EXPECT_STREQ(e.field, "size");
  EXPECT_EQ(neurov_allocator_create(s.bytes + 4, sizeof s.bytes - 4, &p, &a, &e), NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_STREQ(e.field, "storage");
  EXPECT_EQ(neurov_allocator_storage_size(9), 0u);
}

TEST(CAllocation, ABufferCreateNeverSawOrAnotherObjectIsRefused) {
  Storage s;
  float tau[6] = {1, 0, 0, 0, 0, 0}, commands[kN] = {7};
  for (const int fill : {0x00, 0xCD, 0xA5}) {
    std::memset(s.bytes, fill, sizeof s.bytes);
    auto* a = reinterpret_cast<neurov_allocator*>(s.bytes);
    EXPECT_EQ(neurov_allocator_step(a, tau, 16.0f, commands, nullptr), NEUROV_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(neurov_allocator_status(a), NEUROV_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(neurov_allocator_thrusters(a), 0u);
  }
  EXPECT_EQ(commands[0], 7.0f);  // nothing written: n is unknown
  // A reference model where an allocator is expected.
  const float ones[6] = {1, 1, 1, 1, 1, 1}, zero[6] = {0};
  neurov_reference* ref = nullptr;
  ASSERT_EQ(neurov_reference_create(s.bytes, sizeof s.bytes, ones, ones, zero, &ref, nullptr), NEUROV_STATUS_OK);
  EXPECT_EQ(neurov_allocator_step(reinterpret_cast<neurov_allocator*>(ref), tau, 16.0f, commands, nullptr),
            NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_EQ(neurov_allocator_step(nullptr, tau, 16.0f, commands, nullptr), NEUROV_STATUS_INVALID_ARGUMENT);
}

}  // namespace
