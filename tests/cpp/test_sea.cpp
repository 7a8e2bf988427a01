// The sea models' current and payload events (waves: test_sea_waves.cpp).
// The Gauss-Markov current is checked by its statistics over long seeded
// runs against the theory of a first-order Gauss-Markov process (mean,
// stationary standard deviation, autocorrelation exp(-1) at one time
// constant), at several steps; the payload events against the rigid-body
// formulas written out here.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/core/random.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/gauss_markov_current.hpp"
#include "neurov/sim/payload.hpp"
#include "neurov/sim/random_streams.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using neurov_test::record;

constexpr double kDeg = neurov_test::kPi / 180.0;

// ------------------------------------------------------------------ streams

TEST(RandomStreams, NoiseKeepsTheSeedAndTheOthersAreApartAndFixed) {
  for (const std::uint64_t seed : {0ULL, 1ULL, 42ULL, 0x9E3779B97F4A7C15ULL}) {
    EXPECT_EQ(stream_seed(seed, RandomStream::measurement_noise), seed);
    const std::uint64_t c = stream_seed(seed, RandomStream::current);
    const std::uint64_t w = stream_seed(seed, RandomStream::waves);
    EXPECT_NE(c, seed);
    EXPECT_NE(w, seed);
    EXPECT_NE(c, w);
    // Adjacent scenario seeds give unrelated stream seeds: about half the
    // bits differ (a shift by one would differ in one or two).
    const int flipped = __builtin_popcountll(c ^ stream_seed(seed + 1, RandomStream::current));
    EXPECT_GT(flipped, 12);
    EXPECT_LT(flipped, 52);
  }
}

// ------------------------------------------------------------------ current

GaussMarkovCurrentConfig<double> wandering_current() {
  GaussMarkovCurrentConfig<double> c;
  c.speed = 0.5;
  c.speed_std = 0.1;
  c.time_constant = 30.0;
  c.speed_min = 0.0;
  c.speed_max = 2.0;  // 15 sigma away: the clip never acts
  c.direction = 45.0;
  c.direction_std = 5.0;
  c.vertical_angle = 0.0;
  c.vertical_angle_std = 2.0;
  return c;
}

/// Sample mean, standard deviation and autocorrelation at `lag` samples.
struct Moments {
  double mean = 0, std = 0, rho = 0;
};
Moments moments(const std::vector<double>& x, std::size_t lag) {
  const double n = static_cast<double>(x.size());
  double mean = 0;
  for (double v : x) mean += v;
  mean /= n;
  double var = 0, cov = 0;
  for (std::size_t i = 0; i < x.size(); ++i) var += (x[i] - mean) * (x[i] - mean);
  for (std::size_t i = 0; i + lag < x.size(); ++i) cov += (x[i] - mean) * (x[i + lag] - mean);
  var /= n;
  cov /= static_cast<double>(x.size() - lag);
  return {mean, std::sqrt(var), cov / var};
}

/// Records the speed process, direction and vertical angle (degrees) of a run
/// of `duration` seconds at step h, one sample per step.
struct Record {
  std::vector<double> speed, direction, vertical, output;
};
Record run_current(const GaussMarkovCurrentConfig<double>& c, std::uint64_t seed, double h,
                   double duration) {
  GaussMarkovCurrent<double> g;
  EXPECT_TRUE(GaussMarkovCurrent<double>::create(c, seed, g).ok());
  const auto n = static_cast<std::size_t>(std::llround(duration / h));
  Record r;
  for (auto* v : {&r.speed, &r.direction, &r.vertical, &r.output}) v->reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    r.speed.push_back(g.speed_process());
    r.direction.push_back(g.direction() / kDeg);
    r.vertical.push_back(g.vertical_angle() / kDeg);
    r.output.push_back(g.speed());
    EXPECT_EQ(g.advance(h), Status::ok);
  }
  return r;
}

// Over a record of length L >> T, a first-order Gauss-Markov process with
// standard deviation sigma and rho(tau) = e^(-|tau|/T) has (Bartlett)
//   std(sample mean)        = sigma sqrt(2 T / L),
//   std(sample std) / sigma = sqrt(T / (2 L)),
//   std(sample rho(T))      = sqrt((1 - 3 e^-2) T / L) < sqrt(2 T / L).
// The bounds below are five of those spreads; L = 20000 T.
TEST(GaussMarkovCurrent, MeanStdAndAutocorrelationMatchTheoryAtEveryStep) {
  const auto c = wandering_current();
  const double T = c.time_constant, L = 20000.0 * T;
  const double spread = std::sqrt(2.0 * T / L);  // 0.01
  for (const double h : {0.25, 1.5, 6.0}) {
    SCOPED_TRACE("h = " + std::to_string(h));
    const Record r = run_current(c, 11, h, L);
    const auto lag = static_cast<std::size_t>(std::llround(T / h));
    const struct {
      const std::vector<double>& x;
      double mean, sigma;
      const char* name;
    } series[] = {{r.speed, c.speed, c.speed_std, "speed"},
                  {r.direction, c.direction, c.direction_std, "direction"},
                  {r.vertical, c.vertical_angle, c.vertical_angle_std, "vertical_angle"}};
    for (const auto& s : series) {
      const Moments m = moments(s.x, lag);
      EXPECT_NEAR(m.mean, s.mean, 5 * spread * s.sigma) << s.name;
      EXPECT_NEAR(m.std / s.sigma, 1.0, 5 * spread / 2) << s.name;
      EXPECT_NEAR(m.rho, std::exp(-1.0), 5 * spread) << s.name;
      record(std::string(s.name) + "_rho_error_h" + std::to_string(h), m.rho - std::exp(-1.0));
      record(std::string(s.name) + "_std_error_h" + std::to_string(h), m.std / s.sigma - 1.0);
    }
  }
}

// A first-order (Euler) discretisation would pass at a small step and fail
// at h = 3 s (a = 1 - h/T = 0.9 instead of e^-0.1, std off by 2.6 %); the
// exact one keeps the autocorrelation at lags of several steps, too.
TEST(GaussMarkovCurrent, AutocorrelationFollowsTheExponentialAtManyLags) {
  const auto c = wandering_current();
  const double T = c.time_constant, L = 20000.0 * T, h = 3.0;
  const Record r = run_current(c, 5, h, L);
  for (const int lag : {1, 3, 10, 20}) {
    const Moments m = moments(r.speed, static_cast<std::size_t>(lag));
    EXPECT_NEAR(m.rho, std::exp(-lag * h / T), 5 * std::sqrt(2.0 * T / L)) << "lag " << lag;
  }
}

// The clip acts on the output only: the process keeps sigma, and the output
// sits on a bound for the fraction of time the normal distribution puts
// beyond it (1 - Phi(1) = 0.1587 at one sigma).
TEST(GaussMarkovCurrent, BoundsClipTheOutputNotTheProcess) {
  auto c = wandering_current();
  c.speed = 0.5;
  c.speed_std = 0.3;
  c.speed_min = 0.2;
  c.speed_max = 0.8;
  const double T = c.time_constant, L = 20000.0 * T, h = 1.0;
  const Record r = run_current(c, 3, h, L);
  const Moments process = moments(r.speed, 30);
  EXPECT_NEAR(process.std / c.speed_std, 1.0, 0.025);
  std::size_t low = 0, high = 0;
  for (double v : r.output) {
    ASSERT_GE(v, c.speed_min);
    ASSERT_LE(v, c.speed_max);
    low += v == c.speed_min;
    high += v == c.speed_max;
  }
  const double tail = 0.5 * std::erfc(1.0 / std::sqrt(2.0));
  // The fraction p of time beyond a level has a spread of about
  // sqrt(p (1 - p) 2 T / L) = 0.0036: the bound is five and a half of it.
  EXPECT_NEAR(static_cast<double>(low) / r.output.size(), tail, 0.02);
  EXPECT_NEAR(static_cast<double>(high) / r.output.size(), tail, 0.02);
}

TEST(GaussMarkovCurrent, VelocityPointsWhereTheAnglesSay) {
  GaussMarkovCurrent<double> g;
  ASSERT_TRUE(GaussMarkovCurrent<double>::create(wandering_current(), 2, g).ok());
  for (int i = 0; i < 1000; ++i) {
    ASSERT_EQ(g.advance(0.7), Status::ok);
    const double v = g.speed(), psi = g.direction(), gam = g.vertical_angle();
    const Eigen::Vector3d expected(v * std::cos(gam) * std::cos(psi),
                                   v * std::cos(gam) * std::sin(psi), v * std::sin(gam));
    ASSERT_TRUE(neurov_test::all_near(g.velocity(), expected, 1e-15));
  }
}

TEST(GaussMarkovCurrent, SeededFloatAndDoubleAgreeAndRefusedStepsChangeNothing) {
  GaussMarkovCurrentConfig<float> cf;
  const auto cd = wandering_current();
  cf.speed = 0.5f;
  cf.speed_std = 0.1f;
  cf.time_constant = 30.0f;
  cf.direction = 45.0f;
  cf.direction_std = 5.0f;
  cf.vertical_angle_std = 2.0f;
  GaussMarkovCurrent<float> f;
  GaussMarkovCurrent<double> d, d2;
  ASSERT_TRUE(GaussMarkovCurrent<float>::create(cf, 9, f).ok());
  ASSERT_TRUE(GaussMarkovCurrent<double>::create(cd, 9, d).ok());
  ASSERT_TRUE(GaussMarkovCurrent<double>::create(cd, 9, d2).ok());
  for (int i = 0; i < 5000; ++i) {
    ASSERT_EQ(f.advance(0.25f), Status::ok);
    ASSERT_EQ(d.advance(0.25), Status::ok);
    if (i % 100 == 0) {  // refused steps in the twin
      EXPECT_EQ(d2.advance(0.0), Status::invalid_argument);
      EXPECT_EQ(d2.advance(-1.0), Status::invalid_argument);
      EXPECT_EQ(d2.advance(std::nan("")), Status::non_finite_input);
    }
    ASSERT_EQ(d2.advance(0.25), Status::ok);
    ASSERT_TRUE(neurov_test::all_near(f.velocity(), d.velocity(), 1e-6));
    ASSERT_EQ(d.velocity(), d2.velocity());
  }
  GaussMarkovCurrent<double> empty;
  EXPECT_EQ(empty.advance(0.1), Status::invalid_argument);
  EXPECT_FALSE(empty.valid());
}

std::string field_of(const ValidationError& e) { return e.field ? e.field : "(ok)"; }

TEST(GaussMarkovCurrent, BadInputIsNamed) {
  const auto good = wandering_current();
  EXPECT_TRUE(validate(good).ok());
  const neurov_test::BadField<GaussMarkovCurrentConfig<double>> cases[] = {
      {"time_constant", [](auto& c) { c.time_constant = 0.0; }},
      {"time_constant", [](auto& c) { c.time_constant = -5.0; }},
      {"time_constant", [](auto& c) { c.time_constant = std::nan(""); }},
      {"speed_std", [](auto& c) { c.speed_std = -0.1; }},
      {"direction_std", [](auto& c) { c.direction_std = -1.0; }},
      {"vertical_angle_std", [](auto& c) { c.vertical_angle_std = std::nan(""); }},
      {"speed_min", [](auto& c) { c.speed_min = -0.5; }},
      {"speed", [](auto& c) { c.speed_max = 0.4; }},  // mean above max
      {"speed", [](auto& c) { c.speed_min = 1.0; }},   // mean below min
      {"speed_max",
       [](auto& c) {
         c.speed_min = 1.0;
         c.speed_max = 0.5;
       }},  // min > max
      {"speed_max", [](auto& c) { c.speed_max = INFINITY; }},
      {"direction", [](auto& c) { c.direction = std::nan(""); }},
      {"vertical_angle", [](auto& c) { c.vertical_angle = 95.0; }},
  };
  for (const auto& k : cases) {
    auto c = good;
    k.mutate(c);
    GaussMarkovCurrent<double> g;
    const ValidationError e = GaussMarkovCurrent<double>::create(c, 1, g);
    EXPECT_EQ(field_of(e), k.field) << "case " << (&k - cases);
    EXPECT_FALSE(g.valid());
    char buf[160];
    e.format(buf, sizeof buf);
    EXPECT_NE(std::strstr(buf, k.field), nullptr) << buf;
  }
}

// ------------------------------------------------------------------ payload

TEST(Payload, PickUpAtTheCentreOfGravityChangesTheMassMatrixAndTheHeaveAcceleration) {
  const auto p = nerov_parameters<double>();
  Vehicle<double> before(p), after;
  PayloadEvent<double> e;
  e.time = 300.0;
  e.mass = 10.0;
  ASSERT_TRUE(validate(e, p).ok());
  ASSERT_TRUE(apply_payload(e, before, after).ok());
  const auto& q = after.parameters();
  EXPECT_DOUBLE_EQ(q.mass, 195.0);
  EXPECT_DOUBLE_EQ(q.weight, 1800.0 + 10.0 * 9.81);
  EXPECT_DOUBLE_EQ(q.buoyancy, 1800.0);
  EXPECT_TRUE(q.centre_of_gravity.isZero(0.0));
  EXPECT_EQ(q.inertia, p.inertia);  // a point mass at the origin adds no inertia
  Eigen::Matrix<double, 6, 6> m_expected = before.mass_matrix();
  for (int i = 0; i < 3; ++i) m_expected(i, i) += 10.0;
  EXPECT_TRUE(neurov_test::all_near(after.mass_matrix(), m_expected, 1e-12));

  // At rest, level, no thrust: the vehicle starts to sink with
  // dW / (m + m_p + added mass in heave).
  Vector6<double> eta = Vector6<double>::Zero(), nu = Vector6<double>::Zero(), nu_dot;
  ASSERT_EQ(after.acceleration(eta, nu, Vector6<double>::Zero(), nu_dot), Status::ok);
  const double expected = 10.0 * 9.81 / (185.0 + 10.0 + 80.0);
  EXPECT_NEAR(nu_dot(2), expected, 1e-12 * expected);
  EXPECT_NEAR(nu_dot.head<2>().norm() + nu_dot.tail<3>().norm(), 0.0, 1e-12);
}

TEST(Payload, PointMassOffTheOriginMovesTheCentreOfGravityAndTheInertia) {
  neurov_test::Rng rng(17);
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    const auto p = neurov_test::random_vehicle_parameters<double>(rng, CoriolisForm::kirchhoff);
    PayloadEvent<double> e;
    e.mass = rng.uniform<double>(-0.3, 1.0) * 0.2 * p.mass;
    const Eigen::Vector3d r = rng.vec3<double>(-0.2, 0.2);
    e.mass_position = r;
    VehicleParameters<double> q;
    const ValidationError err = apply_payload(e, p, q);
    if (!err.ok()) {  // a dropped mass can leave an inertia that is not positive definite
      EXPECT_EQ(field_of(err), "inertia");
      continue;
    }
    const double m = p.mass + e.mass;
    EXPECT_NEAR(q.mass, m, 1e-12 * m);
    EXPECT_TRUE(neurov_test::all_near(
        q.centre_of_gravity, (p.mass * p.centre_of_gravity + e.mass * r) / m, 1e-15));
    // Parallel axes for a point mass, entry by entry.
    Eigen::Matrix3d d;
    d << r.y() * r.y() + r.z() * r.z(), -r.x() * r.y(), -r.x() * r.z(),  //
        -r.x() * r.y(), r.x() * r.x() + r.z() * r.z(), -r.y() * r.z(),   //
        -r.x() * r.z(), -r.y() * r.z(), r.x() * r.x() + r.y() * r.y();
    EXPECT_TRUE(neurov_test::all_near(q.inertia, p.inertia + e.mass * d, 1e-12 * p.inertia.norm()));
    // M_RB of the new vehicle is M_RB of the old plus that of the point mass.
    Eigen::Matrix<double, 6, 6> mp = Eigen::Matrix<double, 6, 6>::Zero();
    const Eigen::Matrix3d s = skew<double>(r);
    mp.topLeftCorner<3, 3>() = e.mass * Eigen::Matrix3d::Identity();
    mp.topRightCorner<3, 3>() = -e.mass * s;
    mp.bottomLeftCorner<3, 3>() = e.mass * s;
    mp.bottomRightCorner<3, 3>() = e.mass * d;
    EXPECT_TRUE(neurov_test::all_near(rigid_body_mass_matrix(q), rigid_body_mass_matrix(p) + mp,
                                      1e-12 * p.mass));
  }
}

TEST(Payload, BuoyancyDampingAndAddedMassChangeAsAsked) {
  const auto p = nerov_parameters<double>();
  PayloadEvent<double> e;
  e.buoyancy = -200.0;  // a float lost
  e.buoyancy_position = Eigen::Vector3d(0.5, 0.0, -0.3);
  e.damping_scale << 1.5, 1.0, 0.5, 1.0, 2.0, 0.0;
  e.added_mass_scale = 0.8;
  VehicleParameters<double> q;
  ASSERT_TRUE(apply_payload(e, p, q).ok());
  EXPECT_DOUBLE_EQ(q.buoyancy, 1600.0);
  const Eigen::Vector3d rb =
      (1800.0 * p.centre_of_buoyancy - 200.0 * Eigen::Vector3d(0.5, 0.0, -0.3)) / 1600.0;
  EXPECT_TRUE(neurov_test::all_near(q.centre_of_buoyancy, rb, 1e-15));
  EXPECT_EQ(q.mass, p.mass);
  EXPECT_EQ(q.weight, p.weight);
  EXPECT_TRUE(neurov_test::all_near(q.linear_damping, p.linear_damping.cwiseProduct(e.damping_scale), 0));
  EXPECT_TRUE(neurov_test::all_near(q.quadratic_damping,
                                    p.quadratic_damping.cwiseProduct(e.damping_scale), 0));
  EXPECT_TRUE(neurov_test::all_near(q.added_mass, 0.8 * p.added_mass, 1e-13));
  // Lost buoyancy: the vehicle at rest sinks with dB / (m + added mass in heave).
  Vehicle<double> v(q);
  Vector6<double> nu_dot;
  ASSERT_EQ(v.acceleration(Vector6<double>::Zero(), Vector6<double>::Zero(),
                           Vector6<double>::Zero(), nu_dot),
            Status::ok);
  EXPECT_NEAR(nu_dot(2), 200.0 / (185.0 + 0.8 * 80.0), 1e-12);
}

TEST(Payload, BadEventsAreNamedAndLeaveTheVehicleAsItWas) {
  const auto p = nerov_parameters<double>();
  const struct {
    void (*change)(PayloadEvent<double>&);
    const char* field;
  } cases[] = {
      {[](auto& e) { e.mass = -185.0; }, "mass"},  // would leave mass 0
      {[](auto& e) { e.mass = -300.0; }, "mass"},
      {[](auto& e) { e.mass = INFINITY; }, "mass"},
      {[](auto& e) { e.time = -1.0; }, "time"},
      {[](auto& e) { e.time = std::nan(""); }, "time"},
      {[](auto& e) { e.buoyancy = -1800.5; }, "buoyancy"},
      {[](auto& e) { e.mass_position = Eigen::Vector3d(0, std::nan(""), 0); }, "mass_position"},
      {[](auto& e) { e.buoyancy_position = Eigen::Vector3d(INFINITY, 0, 0); },
       "buoyancy_position"},
      {[](auto& e) { e.damping_scale(4) = -0.1; }, "damping_scale"},
      {[](auto& e) { e.added_mass_scale = -1.0; }, "added_mass_scale"},
      // 150 kg dropped from 1 m away: the inertia about the origin would go negative.
      {[](auto& e) {
         e.mass = -150.0;
         e.mass_position = Eigen::Vector3d(1.0, 0.0, 0.0);
       },
       "inertia"},
  };
  const Vehicle<double> before(p);
  for (const auto& k : cases) {
    PayloadEvent<double> e;
    k.change(e);
    EXPECT_EQ(field_of(validate(e, p)), k.field);
    VehicleParameters<double> q = p;
    q.mass = 1.0;  // a marker: must survive the refused call
    EXPECT_EQ(field_of(apply_payload(e, p, q)), k.field);
    EXPECT_EQ(q.mass, 1.0);
    Vehicle<double> after;
    EXPECT_EQ(field_of(apply_payload(e, before, after)), k.field);
    EXPECT_FALSE(after.valid());
  }
  Vehicle<double> empty, after;
  EXPECT_EQ(field_of(apply_payload(PayloadEvent<double>{}, empty, after)), "vehicle");
}

TEST(Payload, FloatBuildsTheSameVehicle) {
  PayloadEvent<float> ef;
  ef.mass = 12.5f;
  ef.mass_position = Eigen::Vector3f(0.1f, -0.05f, 0.2f);
  ef.buoyancy = 30.0f;
  PayloadEvent<double> ed;
  ed.mass = 12.5;
  ed.mass_position = Eigen::Vector3d(0.1f, -0.05f, 0.2f);
  ed.buoyancy = 30.0;
  Vehicle<float> f;
  Vehicle<double> d;
  ASSERT_TRUE(apply_payload(ef, Vehicle<float>(nerov_parameters<float>()), f).ok());
  ASSERT_TRUE(apply_payload(ed, Vehicle<double>(nerov_parameters<double>()), d).ok());
  EXPECT_TRUE(neurov_test::all_near(f.mass_matrix(), d.mass_matrix(), 1e-4));
}

}  // namespace
