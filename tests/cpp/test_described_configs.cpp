// The descriptions beside the thruster curve, the thruster layout and the
// tracking task (config_fields) against their validators: every rule a
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

}  // namespace
