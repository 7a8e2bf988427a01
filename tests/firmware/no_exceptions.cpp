// The library in firmware mode: built with -fno-exceptions -fno-rtti (or with
// NEUROV_NO_EXCEPTIONS while the compiler still has exceptions). Every header
// must compile, the throwing convenience constructors must be gone, and
// configuration errors must come back as ValidationError / Status. A plain
// program rather than GoogleTest, which itself wants exceptions and RTTI.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

#include "neurov/neurov.hpp"
#include "../cpp/curve_tables.hpp"

#if NEUROV_HAS_EXCEPTIONS
#error "this test must be built with -fno-exceptions or NEUROV_NO_EXCEPTIONS"
#endif

namespace {

using namespace neurov;

int failures = 0;

#define CHECK(cond)                                                      \
  do {                                                                   \
    if (!(cond)) {                                                       \
      std::printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);      \
      ++failures;                                                        \
    }                                                                    \
  } while (0)

bool same_field(const ValidationError& e, const char* field) {
  return e.field != nullptr && std::strcmp(e.field, field) == 0;
}

// Only the noexcept create() functions remain.
template <typename S>
constexpr bool no_throwing_constructors() {
  return !std::is_constructible<Vehicle<S>, const VehicleParameters<S>&>::value &&
         !std::is_constructible<RbfNetwork<S, kNNInputs, 8, 6>,
                                const typename RbfNetwork<S, kNNInputs, 8, 6>::CentreMatrix&,
                                const typename RbfNetwork<S, kNNInputs, 8, 6>::BasisVector&>::value &&
         !std::is_constructible<NNAdaptiveController<S, 8>,
                                const typename NNAdaptiveController<S, 8>::Network&,
                                const NNAdaptiveConfig<S>&>::value &&
         !std::is_constructible<ReferenceModel<S>, const Vector6<S>&, const Vector6<S>&>::value &&
         !std::is_constructible<PDController<S>, const PDConfig<S>&>::value &&
         !std::is_constructible<PIDController<S>, const PIDConfig<S>&>::value &&
         !std::is_constructible<SlidingModeController<S>, const SlidingModeConfig<S>&>::value &&
         !std::is_constructible<LinearAdaptiveController<S>, const LinearAdaptiveConfig<S>&>::value &&
         !std::is_constructible<ComputedTorqueController<S>, const ComputedTorqueConfig<S>&>::value;
}
static_assert(no_throwing_constructors<float>(), "throwing constructors in firmware mode");
static_assert(no_throwing_constructors<double>(), "throwing constructors in firmware mode");

constexpr int kCentres = 16;

/// Deterministic centres in the box the paper's set-up uses (docs/paper-reproduction.md),
/// from a small LCG so the test needs no <random>.
template <typename S>
typename NNAdaptiveController<S, kCentres>::Network::CentreMatrix make_centres() {
  typename NNAdaptiveController<S, kCentres>::Network::CentreMatrix c;
  unsigned state = 12345u;
  for (int j = 0; j < kCentres; ++j)
    for (int i = 0; i < kNNInputs; ++i) {
      state = state * 1664525u + 1013904223u;
      const double u = static_cast<double>(state >> 8) / 16777216.0;  // [0, 1)
      const double half = i < 18 ? 1.0 : 3.0;  // velocities, then the pose
      c(j, i) = static_cast<S>((2.0 * u - 1.0) * half);
    }
  return c;
}

template <typename S>
void validation_returns_errors() {
  using V6 = Vector6<S>;
  Vehicle<S> vehicle;
  VehicleParameters<S> p = nerov_parameters<S>();
  p.mass = S(-1);
  CHECK(same_field(Vehicle<S>::create(p, vehicle), "mass"));
  CHECK(!vehicle.valid());

  ReferenceModel<S> ref;
  CHECK(same_field(ReferenceModel<S>::create(V6::Ones(), V6::Zero(), V6::Zero(), ref), "omega"));
  V6 d_out = V6::Constant(S(7));
  DesiredState<S> d;
  d.eta_d = d_out;
  CHECK(ref.step(V6::Zero(), S(0.2), d) == Status::invalid_argument);

  using C = NNAdaptiveController<S, kCentres>;
  C ctrl;
  NNAdaptiveConfig<S> cfg;
  cfg.dt = S(0);
  const auto centres = make_centres<S>();
  const typename C::BasisVector widths = C::BasisVector::Constant(S(30));
  const typename C::InputVector zero = C::InputVector::Zero(), ones = C::InputVector::Ones();
  CHECK(same_field(C::create(centres, widths, zero, ones, cfg, ctrl), "dt"));
  cfg = NNAdaptiveConfig<S>{};
  typename C::BasisVector bad_widths = widths;
  bad_widths(3) = S(0);
  const ValidationError e = C::create(centres, bad_widths, zero, ones, cfg, ctrl);
  CHECK(same_field(e, "widths") && e.index == 3);
  CHECK(!ctrl.configured());
  V6 tau = V6::Ones();
  CHECK(ctrl.step(V6::Zero(), V6::Zero(), DesiredState<S>{}, tau) == Status::invalid_argument);
  CHECK(tau.isZero(S(0)));
  char buf[128];
  e.format(buf, sizeof buf);
  CHECK(std::strstr(buf, "widths[3]") != nullptr);
}

/// NEROV under the NN controller, fixed N, everything on the stack: tracks a
/// step in pose, and a NaN measurement is refused without touching the state.
/// The pose both closed loops are commanded to.
template <typename S>
Vector6<S> pose_step() {
  Vector6<S> r;
  r << S(2), S(1), S(0.5), S(0), S(0), S(0.5);
  return r;
}

/// 60 s of `ctrl` on NEROV from rest at the origin, every dt following the
/// reference model's response to pose_step(), the plant integrated by RK4 in
/// steps of `substep`; eta, nu, tau and d are left as the last step left
/// them. True if every step was taken.
template <typename S, typename Ctl>
bool track_pose_step(Ctl& ctrl, S dt, S substep, Vector6<S>& eta, Vector6<S>& nu, Vector6<S>& tau,
                     DesiredState<S>& d) {
  using V6 = Vector6<S>;
  Vehicle<S> plant;
  CHECK(Vehicle<S>::create(nerov_parameters<S>(), plant).ok());
  ReferenceModel<S> ref;
  CHECK(ReferenceModel<S>::create(V6::Ones(), V6::Constant(S(0.25)), V6::Zero(), ref).ok());
  const V6 r = pose_step<S>();
  eta.setZero();
  nu.setZero();
  tau.setZero();
  int bad = 0;
  for (int k = 0; k < 300; ++k) {  // 60 s at 5 Hz
    if (ref.step(r, dt, d) != Status::ok) ++bad;
    if (ctrl.step(eta, nu, d, tau) != Status::ok) ++bad;
    for (int i = 0; i < 10; ++i)
      if (rk4_step(plant, eta, nu, tau, substep) != Status::ok) ++bad;
  }
  return bad == 0;
}

template <typename S>
void closed_loop_and_bad_input() {
  using V6 = Vector6<S>;
  using C = NNAdaptiveController<S, kCentres>;
  NNAdaptiveConfig<S> cfg;
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  C ctrl;
  CHECK(C::create(make_centres<S>(), C::BasisVector::Constant(S(30)), C::InputVector::Zero(),
                  C::InputVector::Ones(), cfg, ctrl)
            .ok());
  const V6 r = pose_step<S>();
  V6 eta, nu, tau;
  DesiredState<S> d;
  CHECK(track_pose_step(ctrl, cfg.dt, cfg.dt / S(10), eta, nu, tau, d));
  CHECK((eta - r).norm() < S(0.05));

  const typename C::WeightMatrix w = ctrl.weights();
  V6 nan_eta = eta;
  nan_eta(1) = std::numeric_limits<S>::quiet_NaN();
  CHECK(ctrl.step(nan_eta, nu, d, tau) == Status::non_finite_input);
  CHECK(tau.isZero(S(0)));
  CHECK(ctrl.last_status() == Status::non_finite_input);
  CHECK(ctrl.weights() == w);
  V6 upright = eta;
  upright(4) = S(1.5707963267948966);
  CHECK(ctrl.step(upright, nu, d, tau) == Status::near_singularity);
  CHECK(ctrl.weights() == w);
  ctrl.reset();
  CHECK(ctrl.weight_norm() == S(0));
  std::printf("%s: |eta - r| after 60 s = %.2e m/rad, ||W|| = %.3g before reset\n",
              std::is_same<S, float>::value ? "float" : "double",
              static_cast<double>((eta - r).norm()), static_cast<double>(w.norm()));
}

/// The computed-torque controller on the exact NEROV model: a bad gain is
/// named, and the pose step is tracked with everything on the stack.
template <typename S>
void computed_torque() {
  using V6 = Vector6<S>;
  ComputedTorqueConfig<S> cfg;
  cfg.vehicle = nerov_parameters<S>();
  cfg.kd << S(200), S(200), S(200), S(50), S(50), S(50);
  cfg.kd(2) = S(-1);
  ComputedTorqueController<S> ctrl;
  CHECK(same_field(ComputedTorqueController<S>::create(cfg, ctrl), "kd"));
  CHECK(!ctrl.configured());
  cfg.kd(2) = S(200);
  CHECK(ComputedTorqueController<S>::create(cfg, ctrl).ok());
  const V6 r = pose_step<S>();
  V6 eta, nu, tau;
  DesiredState<S> d;
  CHECK(track_pose_step(ctrl, S(0.2), S(0.02), eta, nu, tau, d));
  CHECK((eta - r).norm() < S(0.05));
  std::printf("%s: computed torque, |eta - r| after 60 s = %.2e m/rad\n",
              std::is_same<S, float>::value ? "float" : "double",
              static_cast<double>((eta - r).norm()));
}

/// Thrust allocation for eight vectored thrusters with an inverse curve:
/// inside the attainable set the thrusts give tau back, the commands give
/// the thrusts back through the table, and a NaN tau gets neutral commands.
template <typename S>
void thrust_allocation() {
  using Alloc = ThrustAllocator<S, 8>;
  Eigen::Matrix<S, 6, 8> b8;
  CHECK(allocation_matrix(bluerov2_heavy_layout<S>(), b8).ok());
  const typename Alloc::Vector lo = Alloc::Vector::Constant(8, S(-40)), hi = Alloc::Vector::Constant(8, S(50));
  Alloc alloc;
  typename Alloc::Matrix singular = b8;
  singular.row(2).setZero();  // no heave
  CHECK(same_field(Alloc::create(singular, lo, hi, typename Alloc::Vector(), Saturation::scale, alloc),
                   "thrusters.matrix"));
  CHECK(!alloc.valid());
  CHECK(Alloc::create(b8, lo, hi, typename Alloc::Vector(), Saturation::scale, alloc).ok());
  const ThrusterCurveConfig<S> tc = neurov_test::unit_test_curve<S>(-40, 51);
  ThrusterCurve<S> curve;
  CHECK(ThrusterCurve<S>::create(tc, curve).ok());
  const ThrusterCurve<S>* curves[8] = {&curve, &curve, &curve, &curve, &curve, &curve, &curve, &curve};
  Vector6<S> tau;
  tau << S(20), S(-10), S(15), S(1.5), S(-2), S(3);
  typename Alloc::Vector u, command;
  CHECK(alloc.allocate(tau, S(16), curves, u, command) == Status::ok);
  const S tol = std::is_same<S, float>::value ? S(1e-4) : S(1e-10);
  CHECK((b8 * u - tau).cwiseAbs().maxCoeff() < tol * S(20));
  for (int i = 0; i < 8; ++i) CHECK(std::abs(curve.static_thrust(command(i), S(16)) - u(i)) < tol * S(51));
  tau(0) = std::numeric_limits<S>::quiet_NaN();
  CHECK(alloc.allocate(tau, S(16), curves, u, command) == Status::non_finite_input);
  CHECK(u.isZero(0) && command.isZero(0));
  std::printf("%s: thrust allocation, 8 thrusters with an inverse curve\n",
              std::is_same<S, float>::value ? "float" : "double");
}

}  // namespace

int main() {
  validation_returns_errors<float>();
  validation_returns_errors<double>();
  closed_loop_and_bad_input<float>();
  closed_loop_and_bad_input<double>();
  computed_torque<float>();
  computed_torque<double>();
  thrust_allocation<float>();
  thrust_allocation<double>();
  std::printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
