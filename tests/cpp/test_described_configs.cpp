// The descriptions beside the thruster curve, the thruster layout, the
// tracking task and the vehicle's parameters (config_fields) against their validators: every rule a
// description states (and shows in the Python docstring and FIELDS) is one
// the struct's own validator enforces on that field, and check_fields names it.
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>

#include <gtest/gtest.h>

#include "neurov/model/thruster_curve.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/tracking_task.hpp"
#include "curve_tables.hpp"

namespace {

using namespace neurov;

/// For each described field with a rule: that field set to NaN in a valid
/// `good`; check_fields and `judge` (the struct's validator) must both refuse
/// it, naming the field (the validator may prefix its struct's name).
template <typename Config, typename Judge>
int expect_rules_enforced(const Config& good, Judge judge) {
  EXPECT_TRUE(judge(good).ok()) << judge(good).field;
  EXPECT_TRUE(check_fields(good).ok());
  int checked = 0;
  std::apply(
      [&](const auto&... s) {
        const auto one = [&](const auto& spec) {
          using D = typename std::decay_t<decltype(spec)>::Type;
          if (spec.check == Check::none) return;
          Config c = good;
          if constexpr (std::is_floating_point_v<D>)
            c.*(spec.member) = std::numeric_limits<D>::quiet_NaN();
          else if constexpr (std::is_base_of_v<Eigen::MatrixBase<D>, D>)
            (c.*(spec.member)).setConstant(std::numeric_limits<double>::quiet_NaN());
          else
            return;
          const std::string name = spec.name;
          const ValidationError by_fields = check_fields(c), by_validator = judge(c);
          ASSERT_FALSE(by_fields.ok()) << name;
          EXPECT_EQ(std::string(by_fields.field), name);
          ASSERT_FALSE(by_validator.ok()) << name;
          const std::string got = by_validator.field;
          EXPECT_TRUE(got == name || (got.size() > name.size() &&
                                      got.compare(got.size() - name.size() - 1, std::string::npos,
                                                  "." + name) == 0))
              << name << " refused as " << got;
          ++checked;
        };
        (one(s), ...);
      },
      config_fields(static_cast<const Config*>(nullptr)));
  return checked;
}

TEST(DescribedConfigs, TheCurvesRulesAreItsValidators) {
  const int n = expect_rules_enforced(neurov_test::pwm_test_curve<double>(),
                                      [](const ThrusterCurveConfig<double>& c) { return validate(c); });
  EXPECT_EQ(n, 5);  // dead_band, reference_voltage, voltage_exponent, time_constant, slew_rate
}

TEST(DescribedConfigs, TheLayoutsRulesAreItsValidators) {
  ThrusterConfig<double> c;
  c.matrix = ThrusterConfig<double>::Matrix::Identity(6, 6);
  c.min_thrust = Eigen::VectorXd::Constant(6, -10.0);
  c.max_thrust = Eigen::VectorXd::Constant(6, 10.0);
  const int n = expect_rules_enforced(c, [](const ThrusterConfig<double>& x) {
    Thrusters<double> t;
    return Thrusters<double>::create(x, t);
  });
  EXPECT_EQ(n, 1);  // time_constant
}

TEST(DescribedConfigs, TheTrackingTasksRulesAreItsValidators) {
  TrackingTaskConfig<double> c;
  c.thrusters = TrackingTaskConfig<double>::Allocation::Identity(6, 6);
  const int n = expect_rules_enforced(c, [](const TrackingTaskConfig<double>& x) { return validate(x); });
  EXPECT_EQ(n, 8);  // all but box_high (> box_low) and dropouts_read_zero
}

TEST(DescribedConfigs, TheVehiclesRulesAreItsValidators) {
  const int n = expect_rules_enforced(nerov_parameters<double>(),
                                      [](const VehicleParameters<double>& p) { return validate(p); });
  EXPECT_EQ(n, 9);  // all but coriolis_form (a choice)
}

std::string message(const ValidationError& e) {
  char buf[256];
  e.format(buf, sizeof buf);
  return buf;
}

TEST(DescribedConfigs, CheckFieldsCatchesEachVehicleRuleWithTheValidatorsMessage) {
  using P = VehicleParameters<double>;
  const auto refused = [](void (*change)(P&)) {
    P p = nerov_parameters<double>();
    change(p);
    const ValidationError by_fields = check_fields(p);
    EXPECT_EQ(message(by_fields), message(validate(p)));
    return message(by_fields);
  };
  EXPECT_EQ(refused([](P& p) { p.mass = 0.0; }), "mass = 0: expected > 0 and finite");
  EXPECT_EQ(refused([](P& p) { p.inertia(1, 2) = INFINITY; }), "inertia[5] = inf: expected finite");
  EXPECT_EQ(refused([](P& p) { p.centre_of_buoyancy(2) = NAN; }),
            "centre_of_buoyancy[2]: expected finite");
  EXPECT_EQ(refused([](P& p) { p.weight = -1.0; }), "weight = -1: expected >= 0 and finite");
  EXPECT_EQ(refused([](P& p) { p.buoyancy = -0.5; }), "buoyancy = -0.5: expected >= 0 and finite");
  EXPECT_EQ(refused([](P& p) { p.added_mass(0, 5) = -INFINITY; }),
            "added_mass[5] = -inf: expected finite");
  EXPECT_EQ(refused([](P& p) { p.linear_damping(2) = -1.0; }),
            "linear_damping[2] = -1: expected >= 0 and finite");
  EXPECT_EQ(refused([](P& p) { p.quadratic_damping(4) = -100.0; }),
            "quadratic_damping[4] = -100: expected >= 0 and finite");
  // What ties fields together stays the validator's own.
  P p = nerov_parameters<double>();
  p.inertia(0, 1) = 1.0;
  EXPECT_TRUE(check_fields(p).ok());
  EXPECT_EQ(std::string(validate(p).field), "inertia");
}

TEST(DescribedConfigs, TheVehiclesFormsAreInItsDescription) {
  const auto specs = config_fields(static_cast<const VehicleParameters<double>*>(nullptr));
  const auto& inertia = std::get<1>(specs);
  const auto& centre = std::get<2>(specs);
  const auto& added_mass = std::get<6>(specs);
  EXPECT_STREQ(inertia.name, "inertia");
  EXPECT_EQ(inertia.flags, unsigned{kRequired | kDiagonal});
  EXPECT_STREQ(added_mass.name, "added_mass");
  EXPECT_EQ(added_mass.flags, unsigned{kRequired | kDiagonal});
  EXPECT_STREQ(centre.name, "centre_of_gravity");
  EXPECT_EQ(centre.flags, 0u);  // optional: zero by default
}

}  // namespace
