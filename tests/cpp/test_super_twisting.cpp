// The super-twisting controller: its implicit discretisation does not chatter
// at the 5 Hz control period where an explicit Euler step of the same law
// does, its integral term does not wind up under a force it cannot match,
// and a bad configuration names its field. (The contract every controller
// keeps runs over the list in test_controller_contract.cpp.)
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/control/super_twisting_controller.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/regressor.hpp"
#include "neurov/model/vehicle.hpp"
#include "test_support.hpp"

namespace {

using namespace neurov;
using V6 = Vector6<double>;
using Config = SuperTwistingConfig<double>;

/// The same law stepped by explicit Euler: sgn(s_k) and v_{k+1} = v_k + h beta
/// sgn(s_k), which chatters when h is not small against the gains.
class ExplicitSuperTwisting
    : public VectorStateControllerBase<ExplicitSuperTwisting, double, Config> {
  friend ControllerBase<ExplicitSuperTwisting, double, Config>;

 public:
  explicit ExplicitSuperTwisting(const Config& c) { EXPECT_TRUE(create(c, *this).ok()); }

 private:
  bool control(const TrackingError<double>& e, const V6& nu, V6& tau) noexcept {
    const auto& c = config_;
    const auto& trig = e.kinematics.trig;
    const V6 f_hat = regressor<double>(e.nu_r_dot, e.nu_r, nu, trig.sin_phi, trig.cos_phi,
                                       trig.sin_theta, trig.cos_theta) *
                     c.theta;
    const V6 m = detail::nominal_inertia(c.theta);
    V6 force;
    for (int i = 0; i < 6; ++i) {
      const double s = e.s(i), sgn = s > 0 ? 1.0 : (s < 0 ? -1.0 : 0.0);
      force(i) = m(i) * (c.kd(i) / m(i) * s + c.alpha(i) * std::sqrt(std::abs(s)) * sgn +
                         state_(i));
      state_(i) += c.dt * c.beta(i) * sgn;
    }
    tau = f_hat - e.kinematics.apply_transpose(force);
    return tau.allFinite();
  }
};

Config nerov_config() {
  Config c;
  c.lambda.setConstant(0.5);
  c.kd.setZero();
  c.alpha.setConstant(2.0);
  c.beta.setConstant(1.0);
  c.force_limit.setConstant(1e4);
  c.dt = 0.2;
  EXPECT_TRUE(regressor_parameters(nerov_parameters<double>(), c.theta).ok());
  return c;
}

struct Trace {
  std::vector<V6> tau, eta;
  std::vector<V6> integral;  // the implicit controller's v, when it is the one run
};

/// A step to eta_d from rest on the nominal plant (the controller's own
/// model) under a constant unmodelled force `d` from t_on to t_off, the force
/// held over each 0.2 s period and the plant integrated in 20 RK4 substeps.
template <typename Controller>
Trace step_response(Controller& ctl, const V6& eta_d, const V6& d, double t_end, double t_on = 0,
                  double t_off = 1e9) {
  const Vehicle<double> plant(nerov_parameters<double>());
  const double h = 0.2;
  V6 eta = V6::Zero(), nu = V6::Zero(), tau;
  const V6 zero = V6::Zero();
  Trace run;
  for (int k = 0; k * h < t_end; ++k) {
    EXPECT_EQ(ctl.step(eta, nu, eta_d, zero, zero, tau), Status::ok) << "step " << k;
    run.tau.push_back(tau);
    run.eta.push_back(eta);
    if constexpr (std::is_same_v<Controller, SuperTwistingController<double>>)
      run.integral.push_back(ctl.state());
    const double t = k * h;
    const V6 applied = tau + ((t >= t_on && t < t_off) ? d : zero);
    for (int sub = 0; sub < 20; ++sub) EXPECT_EQ(rk4_step(plant, eta, nu, applied, h / 20), Status::ok);
  }
  return run;
}

/// Sum over rows k >= from of |tau_k - tau_{k-1}| in surge: how much the
/// force moves once the vehicle has arrived.
double total_variation(const std::vector<V6>& tau, std::size_t from, int dof = 0) {
  double tv = 0;
  for (std::size_t k = std::max<std::size_t>(from, 1); k < tau.size(); ++k)
    tv += std::abs(tau[k](dof) - tau[k - 1](dof));
  return tv;
}

V6 surge(double x) {
  V6 v = V6::Zero();
  v(0) = x;
  return v;
}

TEST(SuperTwisting, ImplicitStepDoesNotChatterAtFiveHertzWhereExplicitEulerDoes) {
  const Config cfg = nerov_config();
  SuperTwistingController<double> implicit(cfg);
  ExplicitSuperTwisting explicit_euler(cfg);
  const V6 eta_d = surge(2.0), d = surge(50.0);  // 2 m step against an unmodelled 50 N
  const Trace a = step_response(implicit, eta_d, d, 60.0);
  const Trace b = step_response(explicit_euler, eta_d, d, 60.0);
  const std::size_t last_third = a.tau.size() * 2 / 3;
  const double tv_implicit = total_variation(a.tau, last_third);
  const double tv_explicit = total_variation(b.tau, last_third);
  neurov_test::record("super_twisting_tv_implicit_N", tv_implicit);
  neurov_test::record("super_twisting_tv_explicit_N", tv_explicit);
  // The implicit step settles where the force balances d, with the offset
  // its one-step prediction leaves (docs/model.md): s = h d / M at most, so
  // eta_tilde <= h d / (M lambda), 9 cm here (the nominal model's damping on
  // nu_r takes a little of it).
  const double m_surge = detail::nominal_inertia(cfg.theta)(0);
  const double offset = a.eta.back()(0) - 2.0, bound = 0.2 * d(0) / (m_surge * 0.5);
  EXPECT_LE(offset, bound);
  EXPECT_GT(offset, 0.9 * bound);
  // The explicit step's force keeps switching by tens of newtons every
  // period, while the implicit one's stands still.
  EXPECT_LT(tv_implicit, 1.0);
  EXPECT_GT(tv_explicit, 1000.0);
  EXPECT_NEAR(a.tau.back()(0), -d(0), 0.5);
}

TEST(SuperTwisting, IntegralTermDoesNotWindUpAgainstAForceBeyondItsLimit) {
  Config cfg = nerov_config();
  cfg.force_limit.setConstant(100.0);
  SuperTwistingController<double> ctl(cfg);
  const double m_surge = detail::nominal_inertia(cfg.theta)(0);
  // 300 N pushes the vehicle off its pose for 30 s; the controller may give 100.
  const Trace run = step_response(ctl, V6::Zero(), surge(300.0), 90.0, 0.0, 30.0);
  const std::size_t released = static_cast<std::size_t>(30.0 / 0.2);
  for (std::size_t k = 0; k < run.integral.size(); ++k)
    ASSERT_LE(m_surge * std::abs(run.integral[k](0)), 100.0 + 1e-9) << "row " << k;
  // While the force is at its limit the integral term does not move.
  for (std::size_t k = 10; k < released; ++k)
    EXPECT_EQ(run.integral[k](0), run.integral[9](0)) << "row " << k;
  double overshoot = 0;  // the push was +x: back past the pose is -x
  for (std::size_t k = released; k < run.eta.size(); ++k)
    overshoot = std::max(overshoot, -run.eta[k](0));
  neurov_test::record("super_twisting_windup_push_m", run.eta[released](0));
  neurov_test::record("super_twisting_windup_overshoot_m", overshoot);
  EXPECT_GT(run.eta[released](0), 1.0);  // the force did win meanwhile
  EXPECT_LT(overshoot, 0.1 * run.eta[released](0));
  EXPECT_NEAR(run.eta.back()(0), 0.0, 0.01);
}

TEST(SuperTwisting, BadConfigurationNamesTheField) {
  const std::vector<std::pair<std::string, std::function<void(Config&)>>> cases = {
      {"lambda", [](Config& c) { c.lambda(0) = 0; }},
      {"kd", [](Config& c) { c.kd(3) = -1; }},
      {"alpha", [](Config& c) { c.alpha(2) = 0; }},
      {"beta", [](Config& c) { c.beta(1) = std::nan(""); }},
      {"force_limit", [](Config& c) { c.force_limit(5) = -3; }},
      {"dt", [](Config& c) { c.dt = 0; }},
      {"theta", [](Config& c) { c.theta.setZero(); }},
  };
  for (const auto& [field, spoil] : cases) {
    Config c = nerov_config();
    spoil(c);
    SuperTwistingController<double> ctl;
    const ValidationError e = SuperTwistingController<double>::create(c, ctl);
    ASSERT_FALSE(e.ok()) << field;
    EXPECT_EQ(std::string(e.field), field);
    EXPECT_FALSE(ctl.configured());
  }
  // Float has the same validator.
  SuperTwistingConfig<float> f;
  SuperTwistingController<float> ctl;
  EXPECT_EQ(std::string(SuperTwistingController<float>::create(f, ctl).field), "theta");
}

}  // namespace
