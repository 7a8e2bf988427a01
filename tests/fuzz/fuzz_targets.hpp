// The fuzz targets of fuzz_step.cpp, templated on the scalar; fuzz_float.cpp
// and fuzz_double.cpp instantiate them, so the two halves build in parallel.
#pragma once

#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

#include "../cpp/controller_state.hpp"
#include "neurov/neurov.hpp"

namespace neurov_fuzz {

using namespace neurov;
using neurov_test::Bytes;
using neurov_test::nerov_thrusters;
using neurov_test::state_finite;
using neurov_test::state_of;

/// What is being fuzzed, for the crash report.
inline const char* g_target = "";
inline const char* g_scalar = "";

[[noreturn]] inline void fail(const char* what, const char* file, int line) {
  std::fprintf(stderr, "neurov fuzz: promise broken in %s<%s>: %s (%s:%d)\n", g_target, g_scalar,
               what, file, line);
  std::abort();
}

#define FUZZ_CHECK(cond) \
  do {                   \
    if (!(cond)) fail(#cond, __FILE__, __LINE__); \
  } while (0)

/// A number: mostly in a sane range (so the code past the input checks is
/// reached), sometimes any bit pattern at all.
template <typename S>
S number(FuzzedDataProvider& p) {
  const std::uint8_t mode = p.ConsumeIntegral<std::uint8_t>();
  if (mode < 48) {
    S x{};
    std::uint8_t bytes[sizeof(S)] = {};
    const std::size_t n = p.ConsumeData(bytes, sizeof(S));
    (void)n;
    std::memcpy(&x, bytes, sizeof(S));
    return x;
  }
  if (mode < 64) {
    const S special[] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                         -std::numeric_limits<S>::infinity(), std::numeric_limits<S>::max(),
                         std::numeric_limits<S>::lowest(), std::numeric_limits<S>::denorm_min(),
                         S(0), static_cast<S>(-0.0), static_cast<S>(1.5707963267948966),
                         static_cast<S>(-1.5707963267948966)};
    return special[mode % (sizeof special / sizeof special[0])];
  }
  const S scale = mode < 160 ? S(2) : mode < 240 ? S(100) : S(1e6);
  return p.ConsumeFloatingPointInRange<S>(-scale, scale);
}

/// A vector whose entries draw() gives, first to last.
template <typename S, int Rows, typename Draw>
Eigen::Matrix<S, Rows, 1> drawn(Draw draw) {
  Eigen::Matrix<S, Rows, 1> v;
  for (int i = 0; i < Rows; ++i) v(i) = draw();
  return v;
}

template <typename S>
Vector6<S> vec6(FuzzedDataProvider& p) {
  return drawn<S, 6>([&] { return number<S>(p); });
}

template <typename S>
Vector3<S> vec3(FuzzedDataProvider& p) {
  return drawn<S, 3>([&] { return number<S>(p); });
}

/// Positive gains mostly, anything sometimes: configuration must validate.
template <typename S>
S gain(FuzzedDataProvider& p) {
  return p.ConsumeBool() ? number<S>(p) : p.ConsumeFloatingPointInRange<S>(S(0.01), S(500));
}

template <typename S>
Vector6<S> gains6(FuzzedDataProvider& p) {
  return drawn<S, 6>([&] { return gain<S>(p); });
}

// --------------------------------------------------------------- controllers

/// Steps a configured (or deliberately unconfigured) controller with fuzzed
/// arguments and checks the step rules after every call.
template <typename Ctl>
void drive(Ctl& c, FuzzedDataProvider& p) {
  using S = typename Ctl::Scalar;
  for (int k = 0; k < 8 && p.remaining_bytes() > 0; ++k) {
    const Vector6<S> eta = vec6<S>(p), nu = vec6<S>(p), eta_d = vec6<S>(p),
                     eta_d_dot = vec6<S>(p), eta_d_ddot = vec6<S>(p);
    const Bytes before = state_of(c);
    Vector6<S> tau = Vector6<S>::Constant(S(7));
    const Status st = c.step(eta, nu, eta_d, eta_d_dot, eta_d_ddot, tau);
    FUZZ_CHECK(tau.allFinite());
    FUZZ_CHECK(c.last_status() == st);
    const bool inputs_finite = eta.allFinite() && nu.allFinite() && eta_d.allFinite() &&
                               eta_d_dot.allFinite() && eta_d_ddot.allFinite();
    if (!inputs_finite && c.configured()) FUZZ_CHECK(st == Status::non_finite_input);
    if (st != Status::ok) {
      FUZZ_CHECK((tau.array() == S(0)).all());
      FUZZ_CHECK(state_of(c) == before);
    } else {
      FUZZ_CHECK(c.configured());
      FUZZ_CHECK(state_finite(c));
    }
  }
}

/// A controller made from a fuzzed configuration (a refusal names a field
/// and leaves it unconfigured), then driven either way.
template <typename Ctl>
void create_and_drive(const typename Ctl::Config& cfg, FuzzedDataProvider& p) {
  Ctl c;
  if (const ValidationError e = Ctl::create(cfg, c)) FUZZ_CHECK(e.field != nullptr && !c.configured());
  drive(c, p);
}

template <typename S, int N>
void fuzz_nn(FuzzedDataProvider& p) {
  using Ctl = NNAdaptiveController<S, N>;
  const int n = N == Eigen::Dynamic ? p.ConsumeIntegralInRange<int>(0, 6) : N;
  typename Ctl::Network::CentreMatrix centres(n, kNNInputs);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < kNNInputs; ++i) centres(j, i) = p.ConsumeFloatingPointInRange<S>(-3, 3);
  typename Ctl::BasisVector widths(n);
  for (int j = 0; j < n; ++j) widths(j) = gain<S>(p);
  NNAdaptiveConfig<S> cfg;
  cfg.lambda = gains6<S>(p);
  cfg.kd = gains6<S>(p);
  cfg.gamma = gain<S>(p);
  cfg.dt = gain<S>(p);
  cfg.modification = static_cast<RobustModification>(p.ConsumeIntegralInRange<int>(0, 4));
  cfg.sigma_m = gain<S>(p);
  cfg.kappa = gain<S>(p);
  cfg.w_max = gain<S>(p);
  cfg.dead_zone = p.ConsumeBool() ? S(0) : gain<S>(p);
  Ctl c;
  const ValidationError e = Ctl::create(centres, widths, Ctl::InputVector::Zero(),
                                        Ctl::InputVector::Ones(), cfg, c);
  if (e) {
    FUZZ_CHECK(e.field != nullptr && !c.configured());
  } else {
    typename Ctl::WeightMatrix w(6, n);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < 6; ++i) w(i, j) = number<S>(p);
    // Refused: a NaN or Inf, or finite weights whose norm overflows.
    const bool acceptable = w.allFinite() && std::isfinite(w.norm());
    const Bytes before = state_of(c);
    FUZZ_CHECK(c.set_weights(w) == acceptable);
    if (!acceptable) FUZZ_CHECK(state_of(c) == before);
    FUZZ_CHECK(std::isfinite(c.weight_norm()));
  }
  drive(c, p);
}

template <typename S>
void fuzz_linear(FuzzedDataProvider& p) {
  LinearAdaptiveConfig<S> cfg;
  cfg.lambda = gains6<S>(p);
  cfg.kd = gains6<S>(p);
  cfg.gamma = drawn<S, kRegressorParameters>([&] { return gain<S>(p); });
  cfg.dt = gain<S>(p);
  cfg.theta0 = drawn<S, kRegressorParameters>([&] { return number<S>(p); });
  create_and_drive<LinearAdaptiveController<S>>(cfg, p);
}

template <typename S>
void fuzz_pd_pid_smc(FuzzedDataProvider& p, int which) {
  if (which == 0) {
    PDConfig<S> cfg;
    cfg.kp = gains6<S>(p);
    cfg.kd = gains6<S>(p);
    create_and_drive<PDController<S>>(cfg, p);
  } else if (which == 1) {
    PIDConfig<S> cfg;
    cfg.kp = gains6<S>(p);
    cfg.ki = gains6<S>(p);
    cfg.kd = gains6<S>(p);
    cfg.integral_limit = gains6<S>(p);
    cfg.dt = gain<S>(p);
    create_and_drive<PIDController<S>>(cfg, p);
  } else {
    SlidingModeConfig<S> cfg;
    cfg.lambda = gains6<S>(p);
    cfg.kd = gains6<S>(p);
    cfg.k = gains6<S>(p);
    cfg.phi = gains6<S>(p);
    cfg.theta = drawn<S, kRegressorParameters>([&] { return number<S>(p); });
    create_and_drive<SlidingModeController<S>>(cfg, p);
  }
}

// ---------------------------------------------------------- reference model


template <typename S>
void fuzz_reference(FuzzedDataProvider& p) {
  ReferenceModel<S> r;
  if (const ValidationError e = ReferenceModel<S>::create(gains6<S>(p), gains6<S>(p), vec6<S>(p), r)) {
    FUZZ_CHECK(e.field != nullptr);
    return;
  }
  for (int k = 0; k < 8 && p.remaining_bytes() > 0; ++k) {
    const Vector6<S> cmd = vec6<S>(p);
    const S dt = gain<S>(p);
    const Bytes before = state_of(r);
    DesiredState<S> out;
    const Status st = r.step(cmd, dt, out);
    FUZZ_CHECK(out.eta_d.allFinite() && out.eta_d_dot.allFinite() && out.eta_d_ddot.allFinite());
    if (st != Status::ok) FUZZ_CHECK(state_of(r) == before);
    // A step the reference model takes (0 < dt <= kMaxStep) with a NaN command
    // is refused for the command; a step it does not take, for dt first.
    if (!cmd.allFinite() && std::isfinite(dt) && dt > S(0) && static_cast<double>(dt) <= kMaxStep)
      FUZZ_CHECK(st == Status::non_finite_input);
  }
}

// ------------------------------------------------------------- vehicle, RK4

template <typename S>
void fuzz_dynamics(FuzzedDataProvider& p) {
  VehicleParameters<S> params = nerov_parameters<S>();
  if (p.ConsumeBool()) {
    // Perturb some parameters with anything at all; create() must sort it out.
    const int n = p.ConsumeIntegralInRange<int>(1, 6);
    for (int k = 0; k < n; ++k) {
      const S v = number<S>(p);
      switch (p.ConsumeIntegralInRange<int>(0, 8)) {
        case 0: params.mass = v; break;
        case 1: params.inertia(p.ConsumeIntegralInRange<int>(0, 2), p.ConsumeIntegralInRange<int>(0, 2)) = v; break;
        case 2: params.added_mass(p.ConsumeIntegralInRange<int>(0, 5), p.ConsumeIntegralInRange<int>(0, 5)) = v; break;
        case 3: params.linear_damping(p.ConsumeIntegralInRange<int>(0, 5)) = v; break;
        case 4: params.quadratic_damping(p.ConsumeIntegralInRange<int>(0, 5)) = v; break;
        case 5: params.centre_of_gravity(p.ConsumeIntegralInRange<int>(0, 2)) = v; break;
        case 6: params.centre_of_buoyancy(p.ConsumeIntegralInRange<int>(0, 2)) = v; break;
        case 7: params.weight = v; break;
        default: params.buoyancy = v; break;
      }
    }
    params.coriolis_form = static_cast<CoriolisForm>(p.ConsumeIntegralInRange<int>(0, 2));
  }
  Vehicle<S> vehicle;
  if (const ValidationError e = Vehicle<S>::create(params, vehicle)) {
    FUZZ_CHECK(e.field != nullptr && !vehicle.valid());
  }
  for (int k = 0; k < 6 && p.remaining_bytes() > 0; ++k) {
    const Vector6<S> eta = vec6<S>(p), nu = vec6<S>(p), tau = vec6<S>(p);
    const Vector3<S> current = vec3<S>(p);
    const S dt = gain<S>(p);
    Vector6<S> eta_dot, nu_dot;
    (void)vehicle.derivative(eta, nu, tau, current, eta_dot, nu_dot);
    FUZZ_CHECK(eta_dot.allFinite() && nu_dot.allFinite());
    (void)vehicle.acceleration(eta, nu, tau, nu_dot);
    FUZZ_CHECK(nu_dot.allFinite());
    Vector6<S> e = eta, n = nu;
    const Status st = rk4_step(vehicle, e, n, tau, dt, current);
    if (st != Status::ok && st != Status::near_singularity) {
      FUZZ_CHECK(std::memcmp(e.data(), eta.data(), sizeof(S) * 6) == 0);
      FUZZ_CHECK(std::memcmp(n.data(), nu.data(), sizeof(S) * 6) == 0);
    } else {
      FUZZ_CHECK(e.allFinite() && n.allFinite());
    }
    Matrix6<S> m;
    (void)jacobian(eta, m);
    FUZZ_CHECK(m.allFinite());
    (void)jacobian_inverse(eta, m);
    FUZZ_CHECK(m.allFinite());
  }
}

// ----------------------------------------------------------------- thrusters


template <typename S>
void fuzz_thrusters(FuzzedDataProvider& p) {
  ThrusterConfig<S> cfg = nerov_thrusters<S>();
  cfg.saturation = p.ConsumeBool() ? Saturation::clip : Saturation::scale;
  Thrusters<S> t;
  FUZZ_CHECK(Thrusters<S>::create(cfg, t).ok());
  for (int k = 0; k < 8 && p.remaining_bytes() > 0; ++k) {
    const Vector6<S> tau = vec6<S>(p);
    (void)t.set_efficiency(p.ConsumeIntegralInRange<int>(-1, 6), number<S>(p));
    t.command(tau);
    t.advance(S(0.02));
    // The loop only hands the thrusters a finite tau (a controller's).
    if (!tau.allFinite()) continue;
    FUZZ_CHECK(t.commanded().allFinite());
    FUZZ_CHECK((t.commanded().array() <= cfg.max_thrust.array()).all());
    FUZZ_CHECK((t.commanded().array() >= cfg.min_thrust.array()).all());
    FUZZ_CHECK(t.wrench().allFinite());
    FUZZ_CHECK((t.efficiency().array() >= S(0)).all() && (t.efficiency().array() <= S(1)).all());
  }
}

// --------------------------------------------------------------- closed loop

template <typename S>
void fuzz_loop(FuzzedDataProvider& p) {
  SimulationConfig<S> c;
  c.dt = gain<S>(p);
  c.duration = gain<S>(p);
  c.substeps = p.ConsumeIntegralInRange<int>(0, 4);
  // Keep a run short: the result is allocated whole.
  if (!(c.duration / c.dt <= S(50))) return;
  c.eta0 = vec6<S>(p);
  c.nu0 = vec6<S>(p);
  const int k = p.ConsumeIntegralInRange<int>(1, 3);
  c.command.times.resize(k);
  c.command.poses.resize(k, 6);
  for (int i = 0; i < k; ++i) {
    c.command.times(i) = number<S>(p);
    c.command.poses.row(i) = vec6<S>(p).transpose();
  }
  c.noise_eta = vec6<S>(p).cwiseAbs();
  c.seed = p.ConsumeIntegral<std::uint64_t>();
  if (p.ConsumeBool()) {
    SensorFault<S> f;
    f.kind = static_cast<SensorFaultKind>(p.ConsumeIntegralInRange<int>(0, 3));
    f.start = number<S>(p);
    f.end = number<S>(p);
    f.eta = p.ConsumeBool();
    f.nu = p.ConsumeBool();
    f.noise_nu = vec6<S>(p);
    c.sensor_faults.push_back(f);
  }
  if (p.ConsumeBool()) {
    c.use_thrusters = true;
    c.thrusters = nerov_thrusters<S>();
    c.thruster_failures.push_back({p.ConsumeIntegralInRange<int>(-1, 6), number<S>(p), number<S>(p)});
  }
  c.refused_step_policy = p.ConsumeBool() ? RefusedStepPolicy::hold : RefusedStepPolicy::zero;
  PDConfig<S> pd;
  pd.kp.setConstant(S(100));
  pd.kd.setConstant(S(200));
  PDController<S> ctl(pd);
  SimulationResult<S> r;
  const ValidationError e = simulate(Vehicle<S>(nerov_parameters<S>()), ctl, c, r);
  if (e) {
    FUZZ_CHECK(e.field != nullptr && r.steps == 0);
    return;
  }
  FUZZ_CHECK(r.steps >= 1);
  FUZZ_CHECK(r.tau_demanded.allFinite() && r.tau_applied.allFinite() && r.thrusts.allFinite());
  FUZZ_CHECK(r.eta.allFinite() && r.nu.allFinite() && r.eta_d.allFinite());
}

template <typename S>
void fuzz_one(FuzzedDataProvider& p) {
  g_scalar = sizeof(S) == sizeof(float) ? "float" : "double";
  static const char* const names[] = {"NNAdaptiveController", "NNAdaptiveController<3 centres>",
                                      "LinearAdaptiveController", "PDController", "PIDController",
                                      "SlidingModeController", "ReferenceModel", "Vehicle/rk4_step",
                                      "Thrusters", "simulate"};
  const int which = p.ConsumeIntegralInRange<int>(0, 9);
  g_target = names[which];
  switch (which) {
    case 0: fuzz_nn<S, Eigen::Dynamic>(p); break;
    case 1: fuzz_nn<S, 3>(p); break;
    case 2: fuzz_linear<S>(p); break;
    case 3: fuzz_pd_pid_smc<S>(p, 0); break;
    case 4: fuzz_pd_pid_smc<S>(p, 1); break;
    case 5: fuzz_pd_pid_smc<S>(p, 2); break;
    case 6: fuzz_reference<S>(p); break;
    case 7: fuzz_dynamics<S>(p); break;
    case 8: fuzz_thrusters<S>(p); break;
    default: fuzz_loop<S>(p); break;
  }
}

}  // namespace neurov_fuzz
