// The RBF neural-network controller's step (eq. 30, 35, 37) against the plain
// double reference of nn_reference.hpp: the step, a compile-time centre count,
// per-centre learning rates, the robust modifications and reset.
#include <cmath>
#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "nn_reference.hpp"

namespace {

using namespace neurov;
using namespace neurov_test::nn;

NEUROV_SCALAR_SUITE(NNControllerTest);

/// Weights another law would give differ from the expected ones far beyond
/// the tolerance, so the comparison with the reference tells the laws apart.
template <typename S>
void expect_distinguishable(const MatXd& other, const MatXd& expected) {
  EXPECT_GT((other - expected).cwiseAbs().maxCoeff(), 100 * tol<S>(max_abs(expected)));
}

// The reference J_dot is itself a hand transcription: check it against a
// central difference of the reference J along eta_dot = J nu before trusting it.
TEST(SpecReference, JacobianDotMatchesCentralDifferenceOfJacobian) {
  Rng rng(11);
  for (int k = 0; k < 50; ++k) {
    const V6d eta = rng.pose<double>(1.2);
    const V6d nu = rng.velocity<double>();
    const double h = 1e-6;
    const V6d eta_dot = spec_j(eta) * nu;
    const M6d fd = (spec_j(eta + h * eta_dot) - spec_j(eta - h * eta_dot)) / (2 * h);
    EXPECT_TRUE(all_near(spec_j_dot(eta, nu), fd, 1e-6 * (1 + max_abs(fd))));
    EXPECT_TRUE(all_near(spec_j(eta) * spec_j_inv(eta), M6d::Identity(), 1e-12));
  }
}

TYPED_TEST(NNControllerTest, StepMatchesPlainLoopEquationsWithWeightsFromBeforeTheUpdate) {
  using S = TypeParam;
  Rng rng(101);
  int discriminating = 0;
  for (int k = 0; k < 25; ++k) {
    NNCase c = random_case<S>(rng);
    auto ctl = make_nn<S>(c);
    MatXd w = c.weights;
    const VecXd rates = uniform_rates(c);
    // Several steps in a row, so the weights the step starts from are the
    // ones the previous update produced.
    for (int step = 0; step < 3; ++step) {
      const NNExpected ex = nn_reference(c, w, rates, {});
      Vector6<S> tau;
      ASSERT_EQ(step_case<S>(ctl, c, tau), Status::ok);
      const double scale = max_abs(ex.tau) + max_abs(w);
      EXPECT_TRUE(all_near(tau, ex.tau, tol<S>(scale))) << "case " << k << " step " << step;
      EXPECT_TRUE(all_near(ctl.network_output(), ex.f_hat, tol<S>(scale)));
      EXPECT_TRUE(all_near(ctl.basis(), ex.g, tol<S>(1.0)));
      EXPECT_TRUE(all_near(ctl.weights(), ex.weights, tol<S>(max_abs(ex.weights))));
      EXPECT_TRUE(all_near(ctl.tracking().s, ex.e.s, tol<S>(max_abs(ex.e.s))));
      EXPECT_TRUE(all_near(ctl.tracking().nu_r, ex.e.nu_r, tol<S>(max_abs(ex.e.nu_r))));
      EXPECT_TRUE(all_near(ctl.tracking().nu_r_dot, ex.e.nu_r_dot, tol<S>(max_abs(ex.e.nu_r_dot))));
      EXPECT_NEAR(static_cast<double>(ctl.weight_norm()), ex.weights.norm(),
                  tol<S>(ex.weights.norm()));
      EXPECT_TRUE(ctl.adapted());
      // Had tau used the updated weights it would differ by (W_new - W) g;
      // count the cases where that difference is far above the tolerance, so
      // the comparison above really tells the two apart.
      if (((ex.weights - w) * ex.g).cwiseAbs().maxCoeff() > 100 * tol<S>(scale)) ++discriminating;
      w = ex.weights;
      redraw_state<S>(rng, c);
    }
  }
  EXPECT_GE(discriminating, 50);
}

TYPED_TEST(NNControllerTest, CompileTimeCentreCountGivesTheSameStep) {
  using S = TypeParam;
  Rng rng(102);
  for (int k = 0; k < 10; ++k) {
    NNCase c = random_case<S>(rng, 12);
    auto dynamic_ctl = make_nn<S>(c);
    auto fixed_ctl = make_nn<S, 12>(c);
    for (int step = 0; step < 3; ++step) {
      Vector6<S> tau_d, tau_f;
      ASSERT_EQ(step_case<S>(dynamic_ctl, c, tau_d), Status::ok);
      ASSERT_EQ(step_case<S>(fixed_ctl, c, tau_f), Status::ok);
      // Same operations, possibly different vectorisation: a few ulps apart.
      EXPECT_TRUE(all_near(tau_f, tau_d, 64 * eps<S>() * (1 + max_abs(tau_d))));
      EXPECT_TRUE(all_near(fixed_ctl.weights(), dynamic_ctl.weights(),
                           64 * eps<S>() * (1 + max_abs(dynamic_ctl.weights()))));
      redraw_state<S>(rng, c);
    }
  }
}

TYPED_TEST(NNControllerTest, PerCentreLearningRatesScaleEachColumnOfTheUpdate) {
  using S = TypeParam;
  Rng rng(103);
  for (int k = 0; k < 20; ++k) {
    const NNCase c = random_case<S>(rng);
    auto ctl = make_nn<S>(c);
    VecXd rates(c.centres.rows());
    for (int j = 0; j < rates.size(); ++j) rates(j) = draw<S>(rng, 0.0, 3.0);
    rates(1) = 0.0;  // a frozen centre
    ASSERT_TRUE(ctl.set_learning_rates(rates.cast<S>()));
    const NNExpected ex = nn_reference(c, c.weights, rates, {});
    Vector6<S> tau;
    ASSERT_EQ(step_case<S>(ctl, c, tau), Status::ok);
    EXPECT_TRUE(all_near(tau, ex.tau, tol<S>(max_abs(ex.tau) + max_abs(c.weights))));
    EXPECT_TRUE(all_near(ctl.weights(), ex.weights, tol<S>(max_abs(ex.weights))));
    // Rate 0: that column is not touched at all.
    const MatXd col = c.weights.col(1);
    EXPECT_TRUE(all_near(ctl.weights().col(1), col, 0.0));
    // The uniform-gamma law would have given something else.
    const NNExpected uniform = nn_reference(c, c.weights, uniform_rates(c), {});
    expect_distinguishable<S>(uniform.weights, ex.weights);
  }
}

TYPED_TEST(NNControllerTest, SetLearningRatesRefusesBadVectorsAndKeepsTheOldOnes) {
  using S = TypeParam;
  Rng rng(104);
  const NNCase c = random_case<S>(rng);
  auto ctl = make_nn<S>(c);
  using BV = typename NNAdaptiveController<S>::BasisVector;
  const BV before = ctl.learning_rates();
  BV negative = BV::Ones(c.centres.rows());
  negative(3) = S(-0.1);
  BV nan = BV::Ones(c.centres.rows());
  nan(0) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_FALSE(ctl.set_learning_rates(negative));
  EXPECT_FALSE(ctl.set_learning_rates(nan));
  EXPECT_FALSE(ctl.set_learning_rates(BV::Ones(c.centres.rows() + 1)));
  EXPECT_TRUE(all_near(ctl.learning_rates(), before, 0.0));
}

/// One step of case c under the modification `mod` by a controller made into
/// `ctl`: its tau and weights against the reference's, which it returns.
template <typename S>
NNExpected step_against_reference(NNAdaptiveController<S>& ctl, const NNCase& c,
                                  const Modification& mod) {
  ctl = make_nn<S>(c, mod);
  const NNExpected ex = nn_reference(c, c.weights, uniform_rates(c), mod);
  Vector6<S> tau;
  EXPECT_EQ(step_case<S>(ctl, c, tau), Status::ok);
  EXPECT_TRUE(all_near(tau, ex.tau, tol<S>(max_abs(ex.tau) + max_abs(c.weights))));
  EXPECT_TRUE(all_near(ctl.weights(), ex.weights, tol<S>(max_abs(ex.weights))));
  return ex;
}

/// `check(c, rng)` on 20 random cases drawn from seed (rng goes on after each case).
template <typename S, typename Check>
void for_random_cases(std::uint32_t seed, Check check) {
  Rng rng(seed);
  for (int k = 0; k < 20; ++k) check(random_case<S>(rng), rng);
}

/// A leaking modification drawn by draw_mod(rng) on 20 random cases: the step
/// matches the reference, and the reference under rival(mod), the law a
/// mistake would most likely give instead, is told apart from it.
template <typename S, typename DrawMod, typename Rival>
void expect_leak_told_apart(std::uint32_t seed, DrawMod draw_mod, Rival rival) {
  for_random_cases<S>(seed, [&](const NNCase& c, Rng& rng) {
    const Modification mod = draw_mod(rng);
    NNAdaptiveController<S> ctl;
    const NNExpected ex = step_against_reference(ctl, c, mod);
    const NNExpected other = nn_reference(c, c.weights, uniform_rates(c), rival(mod));
    expect_distinguishable<S>(other.weights, ex.weights);
  });
}

TYPED_TEST(NNControllerTest, SigmaModificationLeaksTheWeights) {
  using S = TypeParam;
  expect_leak_told_apart<S>(
      105, [](Rng& rng) { return Modification::sigma(draw<S>(rng, 0.2, 2.0)); },
      [](const Modification&) { return Modification{}; });  // no modification at all
}

TYPED_TEST(NNControllerTest, EModificationLeaksInProportionToTheError) {
  using S = TypeParam;
  // A sigma-modification with sigma_m = kappa would leak by a different amount.
  expect_leak_told_apart<S>(
      106, [](Rng& rng) { return Modification::e_modification(draw<S>(rng, 0.1, 1.0)); },
      [](const Modification& mod) { return Modification::sigma(mod.kappa); });
}

TYPED_TEST(NNControllerTest, ProjectionKeepsTheFrobeniusNormWithinTheBound) {
  using S = TypeParam;
  for_random_cases<S>(107, [](const NNCase& c, Rng&) {
    const VecXd rates = uniform_rates(c);
    const double unprojected = nn_reference(c, c.weights, rates, {}).weights.norm();
    // Active: the bound is below the norm the plain step would reach.
    const Modification active = Modification::projection(0.5 * unprojected);
    NNAdaptiveController<S> ctl;
    step_against_reference(ctl, c, active);
    const double norm = ctl.weights().template cast<double>().norm();
    EXPECT_LE(norm, static_cast<double>(static_cast<S>(active.w_max)) * (1 + 16 * eps<S>()));
    EXPECT_NEAR(norm, active.w_max, tol<S>(active.w_max));
    EXPECT_NEAR(static_cast<double>(ctl.weight_norm()), active.w_max, tol<S>(active.w_max));

    // Inactive: a bound above the new norm leaves the plain step alone.
    auto ctl2 = make_nn<S>(c, Modification::projection(2.0 * unprojected));
    Vector6<S> tau;
    ASSERT_EQ(step_case<S>(ctl2, c, tau), Status::ok);
    const NNExpected plain = nn_reference(c, c.weights, rates, {});
    EXPECT_TRUE(all_near(ctl2.weights(), plain.weights, tol<S>(max_abs(plain.weights))));
  });
}

TYPED_TEST(NNControllerTest, DeadZoneStopsAdaptationWhileTheErrorIsSmall) {
  using S = TypeParam;
  for_random_cases<S>(108, [](const NNCase& c, Rng&) {
    const VecXd rates = uniform_rates(c);
    const double s_norm = spec_tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lambda)
                              .s.norm();
    const Modification inside = Modification::with_dead_zone(1.5 * s_norm);
    auto ctl = make_nn<S>(c, inside);
    Vector6<S> tau;
    ASSERT_EQ(step_case<S>(ctl, c, tau), Status::ok);
    const NNExpected ex = nn_reference(c, c.weights, rates, inside);
    ASSERT_FALSE(ex.adapted);
    EXPECT_FALSE(ctl.adapted());
    // No update at all: the stored weights are the initial ones, bit for bit.
    const MatXd w0 = c.weights.cast<S>().template cast<double>();
    EXPECT_TRUE(all_near(ctl.weights(), w0, 0.0));
    // The control law still runs.
    EXPECT_TRUE(all_near(tau, ex.tau, tol<S>(max_abs(ex.tau) + max_abs(c.weights))));

    const Modification outside = Modification::with_dead_zone(0.5 * s_norm);
    auto ctl2 = make_nn<S>(c, outside);
    ASSERT_EQ(step_case<S>(ctl2, c, tau), Status::ok);
    const NNExpected ex2 = nn_reference(c, c.weights, rates, outside);
    EXPECT_TRUE(ex2.adapted);
    EXPECT_TRUE(ctl2.adapted());
    EXPECT_TRUE(all_near(ctl2.weights(), ex2.weights, tol<S>(max_abs(ex2.weights))));
  });
}

TYPED_TEST(NNControllerTest, ResetRestoresTheInitialWeights) {
  using S = TypeParam;
  Rng rng(109);
  NNCase c = random_case<S>(rng);
  auto ctl = make_nn<S>(c);
  const auto w0 = ctl.weights();
  Vector6<S> tau;
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(step_case<S>(ctl, c, tau), Status::ok);
    redraw_state<S>(rng, c);
  }
  ASSERT_GT((ctl.weights() - w0).cwiseAbs().maxCoeff(), S(0));
  ctl.reset();
  EXPECT_TRUE(all_near(ctl.weights(), w0, 0.0));
  EXPECT_EQ(ctl.weight_norm(), w0.norm());
}

}  // namespace
