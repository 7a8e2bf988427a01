// The controllers' real-time path must not touch the heap: every step() (also
// the refused ones), the reference model, the tracking error and the RBF
// network, in float and double, for dynamic and compile-time network sizes.
//
// The detectors are in alloc_probe.hpp; the counting global operator new is
// defined in alloc_foundation.cpp (there may be only one per executable).
#include "alloc_probe.hpp"

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "neurov/neurov.hpp"

namespace {

using namespace neurov;

using alloc_probe::watch;
using alloc_probe::Window;

template <typename Derived>
void consume(volatile double& sink, const Eigen::MatrixBase<Derived>& x) {
  sink = sink + static_cast<double>(x.sum());
}

// The counter this file reads must be the one operator new increments (the
// same inline variable as alloc_foundation.cpp's); if the two ever drifted
// apart, every test below would pass vacuously.
TEST(ControllerAllocDetector, SeesOperatorNewAndEigenMallocFromThisFile) {
  const Window w = watch([] {
    std::vector<int>* v = new std::vector<int>(16);
    Eigen::MatrixXd m(4, 4);
    m.setZero();
    volatile double s = m.sum() + static_cast<double>(v->size());
    (void)s;
    delete v;
  });
  EXPECT_GE(w.new_calls, 2);
  EXPECT_GE(w.eigen_failures, 1);
}

NEUROV_SCALAR_SUITE(ControllerAllocTest);

/// What the calls of a window returned, in order, against what each must.
template <std::size_t N>
void expect_statuses(const Status (&st)[N], std::initializer_list<Status> expected) {
  ASSERT_LE(expected.size(), N);
  std::size_t i = 0;
  for (const Status e : expected) {
    EXPECT_EQ(st[i], e) << "call " << i;
    ++i;
  }
}

constexpr int kCentres = 24;

template <typename S>
struct Inputs {
  Vector6<S> eta, nu, eta_d, eta_d_dot, eta_d_ddot, lambda, bad_eta, singular_eta, huge_nu;
  Inputs() {
    eta << S(1), S(-2), S(0.5), S(0.1), S(-0.2), S(0.3);
    nu << S(0.3), S(-0.1), S(0.05), S(0.02), S(-0.03), S(0.1);
    eta_d << S(1.2), S(-1.8), S(0.4), S(0.05), S(-0.1), S(0.4);
    eta_d_dot << S(0.1), S(0.05), S(0), S(0.01), S(0), S(0.02);
    eta_d_ddot << S(0.01), S(-0.02), S(0), S(0), S(0.001), S(0);
    lambda.setConstant(S(0.8));
    bad_eta = eta;
    bad_eta(2) = std::numeric_limits<S>::quiet_NaN();
    singular_eta = eta;
    singular_eta(4) = static_cast<S>(1.5707963267948966);
    // Finite, but K_d s overflows: refused after the network has run (the
    // path that keeps g(x) in scratch storage until the step is accepted).
    huge_nu = nu;
    huge_nu(0) = std::numeric_limits<S>::max() / S(4);
  }

  /// c's step on these inputs.
  template <typename Ctl>
  Status step(Ctl& c, Vector6<S>& tau) const {
    return step_at(c, eta, nu, tau);
  }

  /// c's step with the measurements swapped (bad_eta, singular_eta, huge_nu).
  template <typename Ctl>
  Status step_at(Ctl& c, const Vector6<S>& eta_at, const Vector6<S>& nu_at, Vector6<S>& tau) const {
    return c.step(eta_at, nu_at, eta_d, eta_d_dot, eta_d_ddot, tau);
  }
};

/// Centres around the inputs so g(x) is not all zeros and the update does work.
template <typename S, typename CentreMatrix>
void fill_centres(CentreMatrix& c) {
  for (int j = 0; j < c.rows(); ++j)
    for (int i = 0; i < c.cols(); ++i)
      c(j, i) = static_cast<S>(0.1 * std::sin(1.3 * j + 0.7 * i));
}

/// kCentres centres from fill_centres, every width 2, whether the network's
/// centre count is fixed at compile time or not (built outside any window).
template <typename Net>
Net network_of_width_2() {
  using S = typename Net::Scalar;
  typename Net::CentreMatrix c(kCentres, kNNInputs);
  fill_centres<S>(c);
  return Net(c, Net::BasisVector::Constant(kCentres, S(2)));
}

template <typename Ctl>
NNAdaptiveConfig<typename Ctl::Scalar> nn_config(RobustModification m) {
  using S = typename Ctl::Scalar;
  NNAdaptiveConfig<S> cfg;
  cfg.kd.setConstant(S(20));
  cfg.gamma = S(0.5);
  cfg.dt = S(0.05);
  cfg.modification = m;
  cfg.sigma_m = S(0.1);
  cfg.kappa = S(0.1);
  cfg.w_max = S(0.01);  // small, so the projection actually rescales
  cfg.dead_zone = S(0);
  return cfg;
}

/// Builds (allocating, outside the window) then steps inside it: accepted
/// steps with every modification, a dead-zone step, and refused steps.
template <typename Ctl>
void expect_nn_step_does_not_allocate(const typename Ctl::Network& net) {
  using S = typename Ctl::Scalar;
  const Inputs<S> in;
  for (const RobustModification m : {RobustModification::none, RobustModification::sigma,
                                     RobustModification::e_modification,
                                     RobustModification::projection}) {
    Ctl ctl;
    ASSERT_TRUE(Ctl::create(net, nn_config<Ctl>(m), ctl).ok());
    auto dz_cfg = nn_config<Ctl>(m);
    dz_cfg.dead_zone = S(1e6);
    Ctl dead;
    ASSERT_TRUE(Ctl::create(net, dz_cfg, dead).ok());
    typename Ctl::BasisVector rates = ctl.learning_rates();
    rates.setConstant(S(0.7));
    Status st[7] = {};
    volatile double sink = 0;
    Vector6<S> tau;
    const Window w = watch([&] {
      st[0] = in.step(ctl, tau);
      consume(sink, tau);
      st[1] = ctl.set_learning_rates(rates) ? Status::ok : Status::invalid_argument;
      for (int k = 0; k < 100; ++k) {
        st[2] = worst(st[2], in.step(ctl, tau));
        consume(sink, tau);
      }
      st[3] = in.step(dead, tau);
      st[4] = in.step_at(ctl, in.bad_eta, in.nu, tau);
      st[5] = in.step_at(ctl, in.singular_eta, in.nu, tau);
      st[6] = in.step_at(ctl, in.eta, in.huge_nu, tau);
      consume(sink, ctl.weights());
      consume(sink, ctl.basis());
      ctl.reset();
    });
    EXPECT_EQ(w.new_calls, 0) << to_string(m);
    EXPECT_EQ(w.eigen_failures, 0) << to_string(m);
    expect_statuses(st, {Status::ok, Status::ok, Status::ok, Status::ok, Status::non_finite_input,
                         Status::near_singularity, Status::non_finite_output});
    EXPECT_FALSE(dead.adapted());
    EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
  }
}

TYPED_TEST(ControllerAllocTest, NNStepWithDynamicCentresDoesNotAllocateAfterCreate) {
  using Ctl = NNAdaptiveController<TypeParam>;
  expect_nn_step_does_not_allocate<Ctl>(network_of_width_2<typename Ctl::Network>());
}

TYPED_TEST(ControllerAllocTest, NNStepWithCompileTimeCentresDoesNotAllocate) {
  using Ctl = NNAdaptiveController<TypeParam, kCentres>;
  expect_nn_step_does_not_allocate<Ctl>(network_of_width_2<typename Ctl::Network>());
}

// Firmware with a fixed N may build everything after start-up.
TYPED_TEST(ControllerAllocTest, CompileTimeNetworkAndControllerCreateDoNotAllocate) {
  using S = TypeParam;
  using Ctl = NNAdaptiveController<S, kCentres>;
  typename Ctl::Network::CentreMatrix c;
  fill_centres<S>(c);
  const Eigen::Matrix<S, kCentres, 1> widths = Eigen::Matrix<S, kCentres, 1>::Constant(S(2));
  typename Ctl::Network net;
  Ctl ctl;
  ValidationError e1, e2;
  const Window w = watch([&] {
    e1 = Ctl::Network::create(c, widths, net);
    e2 = Ctl::create(net, nn_config<Ctl>(RobustModification::none), ctl);
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_TRUE(e1.ok());
  EXPECT_TRUE(e2.ok());
}

TYPED_TEST(ControllerAllocTest, LinearAndPDStepsDoNotAllocate) {
  using S = TypeParam;
  const Inputs<S> in;
  LinearAdaptiveConfig<S> lcfg;
  lcfg.kd.setConstant(S(20));
  lcfg.dt = S(0.05);
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), lcfg.theta0).ok());
  PDConfig<S> pcfg;
  pcfg.kp.setConstant(S(50));
  pcfg.kd.setConstant(S(10));
  LinearAdaptiveController<S> lin;
  PDController<S> pd;
  Status st[8] = {};
  ValidationError e1, e2;
  volatile double sink = 0;
  const Window w = watch([&] {
    // create() is noexcept and fixed-size for both: also heap-free.
    e1 = LinearAdaptiveController<S>::create(lcfg, lin);
    e2 = PDController<S>::create(pcfg, pd);
    Vector6<S> tau;
    for (int k = 0; k < 100; ++k) {
      st[0] = worst(st[0], in.step(lin, tau));
      consume(sink, tau);
      st[1] = worst(st[1], in.step(pd, tau));
      consume(sink, tau);
    }
    st[2] = in.step_at(lin, in.bad_eta, in.nu, tau);
    st[3] = in.step_at(lin, in.singular_eta, in.nu, tau);
    st[4] = in.step_at(pd, in.bad_eta, in.nu, tau);
    st[5] = in.step_at(pd, in.singular_eta, in.nu, tau);
    consume(sink, lin.theta());
    ParameterVector<S> theta;
    st[6] = regressor_parameters(nerov_parameters<S>(), theta).ok() ? Status::ok
                                                                    : Status::invalid_argument;
    consume(sink, theta);
    consume(sink, regressor<S>(in.nu, in.nu, in.nu, S(0.1), S(0.99), S(0.2), S(0.98)));
    lin.reset();
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_TRUE(e1.ok());
  EXPECT_TRUE(e2.ok());
  expect_statuses(st, {Status::ok, Status::ok, Status::non_finite_input, Status::near_singularity,
                       Status::non_finite_input, Status::near_singularity, Status::ok});
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

/// create(), accepted and refused steps and reset() of a controller whose
/// create() takes only its configuration, all inside the watch window.
template <typename Ctl>
void expect_fixed_size_controller_does_not_allocate(const typename Ctl::Config& cfg) {
  using S = typename Ctl::Scalar;
  const Inputs<S> in;
  Ctl ctl;
  ValidationError e;
  Status st[4] = {};
  volatile double sink = 0;
  const Window w = watch([&] {
    e = Ctl::create(cfg, ctl);
    Vector6<S> tau;
    DesiredState<S> d;
    d.eta_d = in.eta_d;
    for (int k = 0; k < 100; ++k) {
      st[0] = worst(st[0], in.step(ctl, tau));
      consume(sink, tau);
    }
    st[1] = ctl.step(in.eta, in.nu, d, tau);
    consume(sink, tau);
    st[2] = in.step_at(ctl, in.bad_eta, in.nu, tau);
    st[3] = in.step_at(ctl, in.singular_eta, in.nu, tau);
    sink = sink + static_cast<double>(ctl.adaptive_norm());
    consume(sink, ctl.logged_parameters());
    ctl.reset();
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_TRUE(e.ok());
  expect_statuses(st, {Status::ok, Status::ok, Status::non_finite_input, Status::near_singularity});
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

TYPED_TEST(ControllerAllocTest, PidSlidingModeAndComputedTorqueDoNotAllocate) {
  using S = TypeParam;
  PIDConfig<S> pid;
  pid.kp.setConstant(S(50));
  pid.ki.setConstant(S(5));
  pid.kd.setConstant(S(10));
  expect_fixed_size_controller_does_not_allocate<PIDController<S>>(pid);
  SlidingModeConfig<S> smc;
  smc.kd.setConstant(S(20));
  smc.k.setConstant(S(5));
  ASSERT_TRUE(regressor_parameters(nerov_parameters<S>(), smc.theta).ok());
  expect_fixed_size_controller_does_not_allocate<SlidingModeController<S>>(smc);
  ComputedTorqueConfig<S> ct;
  ct.kd.setConstant(S(20));
  ct.vehicle = nerov_parameters<S>();
  ct.vehicle.coriolis_form = CoriolisForm::kirchhoff;
  expect_fixed_size_controller_does_not_allocate<ComputedTorqueController<S>>(ct);
}

TYPED_TEST(ControllerAllocTest, ReferenceModelAndTrackingErrorDoNotAllocate) {
  using S = TypeParam;
  const Inputs<S> in;
  ReferenceModel<S> ref;
  Status st[5] = {};
  ValidationError e;
  volatile double sink = 0;
  const Window w = watch([&] {
    e = ReferenceModel<S>::create(Vector6<S>::Constant(S(2)), Vector6<S>::Constant(S(1)),
                                  Vector6<S>::Zero(), ref);
    DesiredState<S> d;
    for (int k = 0; k < 200; ++k) st[0] = worst(st[0], ref.step(in.eta_d, S(0.05), d));
    consume(sink, d.eta_d + d.eta_d_dot + d.eta_d_ddot);
    st[1] = ref.step(in.bad_eta, S(0.05), d);
    st[2] = ref.step(in.eta_d, S(-1), d);
    TrackingError<S> te;
    st[3] = compute_tracking_error(in.eta, in.nu, in.eta_d, in.eta_d_dot, in.eta_d_ddot,
                                   in.lambda, te);
    consume(sink, te.s + te.nu_r + te.nu_r_dot);
    st[4] = compute_tracking_error(in.singular_eta, in.nu, in.eta_d, in.eta_d_dot, in.eta_d_ddot,
                                   in.lambda, te);
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  EXPECT_TRUE(e.ok());
  expect_statuses(st, {Status::ok, Status::non_finite_input, Status::invalid_argument, Status::ok,
                       Status::near_singularity});
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

template <typename Net>
void expect_network_eval_does_not_allocate(const Net& net, const typename Net::InputVector& x,
                                           typename Net::BasisVector& g) {
  using S = typename Net::Scalar;
  typename Net::OutputVector y;
  Status st[3] = {};
  volatile double sink = 0;
  typename Net::InputVector bad = x;
  bad(0) = std::numeric_limits<S>::infinity();
  const Window w = watch([&] {
    st[0] = net.basis(x, g);
    consume(sink, g);
    st[1] = net.output(x, g, y);
    consume(sink, y);
    st[2] = net.output(bad, g, y);
  });
  EXPECT_EQ(w.new_calls, 0);
  EXPECT_EQ(w.eigen_failures, 0);
  expect_statuses(st, {Status::ok, Status::ok, Status::non_finite_input});
  EXPECT_TRUE(std::isfinite(static_cast<double>(sink)));
}

TYPED_TEST(ControllerAllocTest, RbfNetworkBasisAndOutputDoNotAllocate) {
  using S = TypeParam;
  {
    using Net = RbfNetwork<S>;
    typename Net::CentreMatrix c(kCentres, kNNInputs);
    fill_centres<S>(c);
    Net net(c, Net::BasisVector::Constant(kCentres, S(2)));
    net.set_weights(Net::WeightMatrix::Constant(6, kCentres, S(0.5)));
    const typename Net::InputVector x = Net::InputVector::Constant(kNNInputs, S(0.05));
    typename Net::BasisVector g(kCentres);  // caller storage, sized once
    expect_network_eval_does_not_allocate(net, x, g);
  }
  {
    using Net = RbfNetwork<S, kNNInputs, kCentres, 6>;
    typename Net::CentreMatrix c;
    fill_centres<S>(c);
    Net net(c, Net::BasisVector::Constant(S(2)));
    net.set_weights(Net::WeightMatrix::Constant(S(0.5)));
    const typename Net::InputVector x = Net::InputVector::Constant(S(0.05));
    typename Net::BasisVector g;
    expect_network_eval_does_not_allocate(net, x, g);
  }
}

}  // namespace
