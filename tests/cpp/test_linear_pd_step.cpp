// The step of the linearly parameterised adaptive controller (eq. 26, 28) and
// the PD baseline, against the reference of nn_reference.hpp.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "nn_reference.hpp"

namespace {

using namespace neurov;
using namespace neurov_test::nn;

// ---------------------------------------------------- linear adaptive step

NEUROV_SCALAR_SUITE(LinearStepTest);

// tau = Phi theta_hat - J^T K_d s with the theta_hat from before the update,
// then theta_hat <- theta_hat - dt Gamma Phi^T J^-1 s. s, nu_r, nu_r_dot and J
// come from the docs/model.md formulas above; Phi from regressor(), whose identity
// Phi theta = f is tested on its own in test_linear_adaptive.cpp.
TYPED_TEST(LinearStepTest, StepMatchesEquations26And28) {
  using S = TypeParam;
  Rng rng(150);
  int discriminating = 0;
  for (int k = 0; k < 50; ++k) {
    NNCase c = random_case<S>(rng, 4);  // only the state part is used
    LinearAdaptiveConfig<S> cfg;
    cfg.lambda = c.lambda.cast<S>();
    cfg.kd = c.kd.cast<S>();
    cfg.dt = static_cast<S>(c.dt);
    Eigen::Matrix<double, kRegressorParameters, 1> gamma, theta;
    for (int i = 0; i < kRegressorParameters; ++i) {
      gamma(i) = draw<S>(rng, 0.0, 5.0);
      theta(i) = draw<S>(rng, -50.0, 200.0);
    }
    cfg.gamma = gamma.cast<S>();
    cfg.theta0 = theta.cast<S>();
    LinearAdaptiveController<S> ctl(cfg);
    for (int step = 0; step < 3; ++step) {
      const SpecTracking e = spec_tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lambda);
      const RegressorMatrix<double> phi = regressor<double>(
          e.nu_r_dot, e.nu_r, c.nu, std::sin(c.eta(3)), std::cos(c.eta(3)), std::sin(c.eta(4)),
          std::cos(c.eta(4)));
      const V6d tau_expected = phi * theta - matvec_t(e.j, c.kd.cwiseProduct(e.s));
      const Eigen::Matrix<double, kRegressorParameters, 1> theta_next =
          theta - c.dt * gamma.cwiseProduct(phi.transpose() * matvec(e.j_inv, e.s));
      Vector6<S> tau;
      ASSERT_EQ(step_case<S>(ctl, c, tau), Status::ok);
      const double scale = max_abs(phi) * max_abs(theta);
      EXPECT_TRUE(all_near(tau, tau_expected, tol<S>(scale))) << "case " << k;
      EXPECT_TRUE(all_near(ctl.theta(), theta_next, tol<S>(scale)));
      EXPECT_TRUE(all_near(ctl.model_output(), phi * theta, tol<S>(scale)));
      if ((phi * (theta_next - theta)).cwiseAbs().maxCoeff() > 10 * tol<S>(scale)) ++discriminating;
      theta = ctl.theta().template cast<double>();
      redraw_state<S>(rng, c);
    }
  }
  EXPECT_GE(discriminating, 75);  // the old and new theta_hat give visibly different tau
}

// ------------------------------------------------------------------------ PD

NEUROV_SCALAR_SUITE(PDControllerTest);

TYPED_TEST(PDControllerTest, TauIsMinusJTransposeOfThePdTermsInTheEarthFrame) {
  using S = TypeParam;
  Rng rng(140);
  for (int k = 0; k < neurov_test::kPoints; ++k) {
    const V6d eta = rng.pose<S>(1.2).template cast<double>();
    const V6d nu = rng.velocity<S>().template cast<double>();
    const V6d eta_d = rng.pose<S>(1.2).template cast<double>();
    const V6d eta_d_dot = draw6<S>(rng, -1, 1), eta_d_ddot = draw6<S>(rng, -1, 1);
    const V6d kp = draw6<S>(rng, 0, 100), kd = draw6<S>(rng, 0, 100);
    PDConfig<S> cfg;
    cfg.kp = kp.cast<S>();
    cfg.kd = kd.cast<S>();
    PDController<S> pd(cfg);
    Vector6<S> tau;
    ASSERT_EQ(pd.step(eta.cast<S>().eval(), nu.cast<S>().eval(), eta_d.cast<S>().eval(),
                      eta_d_dot.cast<S>().eval(), eta_d_ddot.cast<S>().eval(), tau),
              Status::ok);
    const V6d eta_tilde = eta - eta_d;
    const V6d eta_tilde_dot = matvec(spec_j(eta), nu) - eta_d_dot;
    const V6d expected =
        -matvec_t(spec_j(eta), kp.cwiseProduct(eta_tilde) + kd.cwiseProduct(eta_tilde_dot));
    EXPECT_TRUE(all_near(tau, expected, tol<S>(max_abs(expected))));
  }
}

TYPED_TEST(PDControllerTest, NegativeGainsNameTheParameter) {
  using S = TypeParam;
  PDConfig<S> cfg;
  cfg.kp(1) = S(-1);
  PDController<S> out;
  EXPECT_STREQ(PDController<S>::create(cfg, out).field, "kp");
  EXPECT_FALSE(out.configured());
  cfg.kp(1) = S(1);
  cfg.kd(4) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_STREQ(PDController<S>::create(cfg, out).field, "kd");
  EXPECT_THROW(PDController<S>{cfg}, std::invalid_argument);
}

}  // namespace
