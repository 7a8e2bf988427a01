// The control task of a vehicle computer, written as firmware writes it:
//   * parameters compiled in (on a vehicle: a calibration table in flash);
//   * every object static, sized at compile time: N is a template argument,
//     so nothing here touches the heap, not even at start-up;
//   * a fixed-rate loop, one control cycle per period: sensors -> estimator
//     (an EKF) -> reference model -> NN controller -> thrust allocation and
//     the inverse thrust curve -> thruster commands, then log; every step is
//     noexcept and returns a status that the loop acts on.
// Built with -fno-exceptions -fno-rtti in float. The "vehicle" is neurov's
// model of NEROV (the paper's vehicle) in double, integrated at 50 Hz, with a
// sinusoidal yaw disturbance like the paper's Fig. 5; its six thrusters turn
// the commands into thrust through the same curve, and its sensors are the
// true state with noise (and an acoustic fix that arrives late).
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <neurov/control/nn_controller.hpp>
#include <neurov/control/reference_model.hpp>
#include <neurov/core/random.hpp>
#include <neurov/estimation/ekf.hpp>
#include <neurov/model/integrator.hpp>
#include <neurov/model/thrust_allocation.hpp>
#include <neurov/model/thruster_curve.hpp>
#include <neurov/model/thruster_geometry.hpp>
#include <neurov/model/vehicle.hpp>
#include <neurov/version.hpp>

#ifndef FIRMWARE_CENTRES
#define FIRMWARE_CENTRES 64
#endif

namespace {

using Scalar = float;
using Vec6 = neurov::Vector6<Scalar>;
constexpr int kCentres = FIRMWARE_CENTRES;
constexpr int kInputs = neurov::kNNInputs;
using Controller = neurov::NNAdaptiveController<Scalar, kCentres>;

// ---------------------------------------------------------------- parameters
// The paper's rate (5 Hz), gain and width; the rest as in the repository's
// paper_fig3 scenario (docs/paper-reproduction.md).
constexpr Scalar kDt = 0.2f;             // control period [s]
constexpr int kPlantSubsteps = 10;       // vehicle model at 50 Hz
constexpr Scalar kGamma = 0.3f;          // learning rate
constexpr Scalar kWidth = 30.0f;         // sigma of every centre
constexpr Scalar kLambda = 0.5f;         // s = eta_tilde_dot + Lambda eta_tilde
constexpr Scalar kKd[6] = {200, 200, 200, 50, 50, 50};
constexpr Scalar kRefDamping = 0.4f;     // reference model: lambda_d
constexpr Scalar kRefStiffness = 0.04f;  // omega: critically damped, 0.2 rad/s
constexpr double kDisturbanceNm = 20.0;  // yaw moment amplitude [N m]
constexpr double kDisturbancePeriod = 20.0;  // [s]

// NEROV's six thrusters as neurov's vehicle file assumes them (the paper
// gives no layout), 250 N each way; one normalised command curve (-1..1)
// with a dead band and weaker reverse thrust, measured at 16 V; the battery
// at 15.5 V. The curve's shape is made up for the example.
constexpr int kThrusters = 6;
constexpr Scalar kPositions[kThrusters][3] = {{-0.5f, 0.3f, 0}, {-0.5f, -0.3f, 0}, {0.4f, 0, 0},
                                              {0.4f, 0, 0},     {-0.4f, 0.3f, 0}, {-0.4f, -0.3f, 0}};
constexpr Scalar kDirections[kThrusters][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                               {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
constexpr Scalar kThrustLimit = 250.0f;
constexpr int kCurvePoints = 6;
constexpr Scalar kCurveCommand[kCurvePoints] = {-1.0f, -0.5f, -0.05f, 0.05f, 0.5f, 1.0f};
constexpr Scalar kCurveThrust[kCurvePoints] = {-200.0f, -70.0f, 0.0f, 0.0f, 90.0f, 250.0f};
constexpr Scalar kSupplyVoltage = 15.5f;

// Sensors (standard deviations) and the estimator's noise model.
constexpr double kAttitudeNoise = 0.005;  // rad, AHRS, every period
constexpr double kGyroNoise = 0.001;      // rad/s, every period
constexpr double kDvlNoise = 0.01;        // m/s, every period
constexpr double kDepthNoise = 0.02;      // m, every period
constexpr double kFixNoise = 0.3;         // m, an acoustic fix every kFixEvery periods...
constexpr int kFixEvery = 5;              // (1 Hz)
constexpr int kFixDelay = 2;              // ...arriving this many periods (0.4 s) late

// A mission: a 5 m square at 2 m depth, turning to face along each leg, 50 s
// a corner; the reference model smooths each jump of the command.
constexpr int kWaypoints = 5;
constexpr Scalar kHalfPi = 1.57079632679f;
constexpr Scalar kMission[kWaypoints][6] = {
    {0, 0, 2, 0, 0, 0},
    {5, 0, 2, 0, 0, 0},
    {5, 5, 2, 0, 0, kHalfPi},
    {0, 5, 2, 0, 0, 2 * kHalfPi},
    {0, 0, 2, 0, 0, 3 * kHalfPi},
};
constexpr Scalar kWaypointTime = 50.0f;
constexpr int kSteps = static_cast<int>(kWaypoints * kWaypointTime / kDt);

// Centres: Halton points (bases: the first 24 primes) in a box around the
// mission, computed at compile time into a table that lands in read-only
// memory, as a flash-resident table would. The box is the mission's bounding
// box +- 2 m and +- 0.5 rad for eta, +- 1 m/s (rad/s) for nu and nu_r,
// +- 0.5 m/s^2 (rad/s^2) for nu_r_dot.
constexpr int kPrimes[kInputs] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31, 37,
                                  41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89};
constexpr Scalar kBoxLo[kInputs] = {-0.5f, -0.5f, -0.5f, -0.5f, -0.5f, -0.5f,  // nu_r_dot
                                    -1, -1, -1, -1, -1, -1,                    // nu_r
                                    -1, -1, -1, -1, -1, -1,                    // nu
                                    -2, -2, -2, -0.5f, -0.5f, -0.5f};
constexpr Scalar kBoxHi[kInputs] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f,
                                    1, 1, 1, 1, 1, 1,
                                    1, 1, 1, 1, 1, 1,
                                    7, 7, 4, 0.5f, 0.5f, 3 * kHalfPi + 0.5f};

constexpr double radical_inverse(int index, int base) {
  double result = 0.0, f = 1.0 / base;
  for (int i = index; i > 0; i /= base, f /= base) result += f * (i % base);
  return result;
}

struct CentreTable {
  Scalar value[kCentres * kInputs];  // row-major: centre j is value[j * kInputs ...]
};

constexpr CentreTable make_centres() {
  CentreTable t{};
  for (int j = 0; j < kCentres; ++j)
    for (int i = 0; i < kInputs; ++i) {
      // Skip the first points, which lie on a line in the large bases.
      const double u = radical_inverse(j + 1 + 2 * kInputs, kPrimes[i]);
      t.value[j * kInputs + i] = static_cast<Scalar>(kBoxLo[i] + u * (kBoxHi[i] - kBoxLo[i]));
    }
  return t;
}

constexpr CentreTable kCentreTable = make_centres();

// ---------------------------------------------------------------- state
// Static, sized at compile time; `size neurov_firmware` shows it in .bss.
using Allocator = neurov::ThrustAllocator<Scalar, kThrusters>;
Controller controller;
neurov::ReferenceModel<Scalar> reference;
neurov::Ekf<Scalar> estimator;
Allocator allocator;
neurov::ThrusterCurve<Scalar> curve;
neurov::Vehicle<double> vehicle_model;
Allocator::Matrix layout;  // B, also what the simulated thrusters push with

struct Log {
  double sum_sq_position = 0.0;  // over the second half of the mission
  int samples = 0;
  double max_position_error = 0.0;
  double sum_sq_estimate = 0.0;  // position estimate against the truth
  int refused_steps = 0;
  int refused_allocations = 0;
  double step_ns_total = 0.0;
  double cycle_ns_total = 0.0;
};
Log log_data;

// On a vehicle: the board's cycle counter.
double now_ns() {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch())
                                 .count());
}

/// Start-up: validate everything once, before the loop. Returns false (and
/// says why) if a parameter is wrong; firmware would then stay in a safe mode.
bool report(const char* what, const neurov::ValidationError& e) {
  if (!e) return true;
  char msg[160];
  e.format(msg, sizeof msg);
  std::printf("%s: %s\n", what, msg);
  return false;
}

/// The layout, the curve, the allocator and the estimator.
bool init_onboard() {
  std::array<neurov::ThrusterGeometry<Scalar>, kThrusters> geometry;
  for (int i = 0; i < kThrusters; ++i) {
    geometry[i].position = Eigen::Map<const neurov::Vector3<Scalar>>(kPositions[i]);
    geometry[i].direction = Eigen::Map<const neurov::Vector3<Scalar>>(kDirections[i]);
  }
  Eigen::Matrix<Scalar, 6, kThrusters> b;
  if (!report("thruster layout", neurov::allocation_matrix(geometry, b))) return false;
  layout = b;
  const Allocator::Vector limit = Allocator::Vector::Constant(kThrusters, kThrustLimit);
  if (!report("allocation", Allocator::create(layout, -limit, limit, Allocator::Vector(),
                                              neurov::Saturation::scale, allocator)))
    return false;
  neurov::ThrusterCurveConfig<Scalar> c;
  c.points = kCurvePoints;
  for (int i = 0; i < kCurvePoints; ++i) {
    c.command[i] = kCurveCommand[i];
    c.thrust[i] = kCurveThrust[i];
  }
  c.dead_band = 0.05f;
  c.reference_voltage = 16.0f;
  if (!report("thruster curve", neurov::ThrusterCurve<Scalar>::create(c, curve))) return false;
  neurov::EkfConfig<Scalar> ec;
  ec.linear_acceleration_noise = 0.05f;
  ec.angular_acceleration_noise = 0.02f;
  ec.gyro_bias_walk = 1e-5f;
  ec.attitude_noise = static_cast<Scalar>(kAttitudeNoise);
  ec.gyro_noise = static_cast<Scalar>(kGyroNoise);
  ec.dvl_noise = static_cast<Scalar>(kDvlNoise);
  ec.depth_noise = static_cast<Scalar>(kDepthNoise);
  ec.position_noise = static_cast<Scalar>(kFixNoise);
  ec.initial_std.setConstant(0.1f);
  return report("estimator", neurov::Ekf<Scalar>::create(ec, Eigen::Map<const Vec6>(kMission[0]),
                                                         Vec6::Zero(), estimator));
}

bool init() {
  if (!report("vehicle model",
              neurov::Vehicle<double>::create(neurov::nerov_parameters<double>(), vehicle_model)))
    return false;
  const Vec6 start = Eigen::Map<const Vec6>(kMission[0]);
  if (const auto e = neurov::ReferenceModel<Scalar>::create(
          Vec6::Constant(kRefDamping), Vec6::Constant(kRefStiffness), start, reference)) {
    char msg[160];
    e.format(msg, sizeof msg);
    std::printf("reference model: %s\n", msg);
    return false;
  }
  neurov::NNAdaptiveConfig<Scalar> config;
  config.lambda = Vec6::Constant(kLambda);
  config.kd = Eigen::Map<const Vec6>(kKd);
  config.gamma = kGamma;
  config.dt = kDt;
  // The centres go from the row-major table into the controller; the network
  // is built inside the static controller, so the only copy made here is one
  // N x 24 matrix on the stack, gone when init() returns.
  using Network = Controller::Network;
  const Network::CentreMatrix centres =
      Eigen::Map<const Eigen::Matrix<Scalar, kCentres, kInputs, Eigen::RowMajor>>(
          kCentreTable.value);
  if (const auto e = Controller::create(centres, Network::BasisVector::Constant(kWidth),
                                        Network::InputVector::Zero(),
                                        Network::InputVector::Ones(), config, controller)) {
    char msg[160];
    e.format(msg, sizeof msg);
    std::printf("NN controller: %s\n", msg);
    return false;
  }
  return init_onboard();
}

/// The sensors: the true state with noise, as the estimator receives it.
struct Sensors {
  neurov::NormalRandom noise{2026};
  neurov::Vector3<double> fix_queue[kFixDelay + 1];  // positions at fix times, oldest first
  int queued = 0;

  neurov::Vector3<Scalar> with_noise(const neurov::Vector3<double>& v, double sd) {
    neurov::Vector3<Scalar> out;
    for (int i = 0; i < 3; ++i) out(i) = static_cast<Scalar>(v(i) + sd * noise.normal());
    return out;
  }

  /// Feeds period k's measurements to the estimator; worst status.
  neurov::Status feed(int k, const neurov::Vector6<double>& eta, const neurov::Vector6<double>& nu) {
    neurov::Status s = estimator.predict(kDt);
    s = neurov::worst(s, estimator.update_attitude(with_noise(eta.tail<3>(), kAttitudeNoise)));
    s = neurov::worst(s, estimator.update_gyro(with_noise(nu.tail<3>(), kGyroNoise)));
    s = neurov::worst(s, estimator.update_dvl(with_noise(nu.head<3>(), kDvlNoise)));
    s = neurov::worst(s, estimator.update_depth(with_noise(eta.head<3>(), kDepthNoise)(2)));
    // A fix is taken every kFixEvery periods and delivered kFixDelay later.
    if (k % kFixEvery == 0) fix_queue[queued++] = eta.head<3>();
    if (queued > 0 && k % kFixEvery == kFixDelay) {
      s = neurov::worst(s, estimator.update_position(with_noise(fix_queue[0], kFixNoise),
                                                     kFixDelay * kDt));
      for (int i = 1; i < queued; ++i) fix_queue[i - 1] = fix_queue[i];
      --queued;
    }
    return s;
  }
};
Sensors sensors;

}  // namespace

int main() {
  std::printf("neurov %s firmware example: float, N = %d centres, %d inputs, %.0f Hz\n",
              NEUROV_VERSION_STRING, kCentres, kInputs, 1.0 / kDt);
  std::printf("static storage: controller %zu B, reference model %zu B, estimator %zu B, "
              "allocation %zu B + curve %zu B\n",
              sizeof controller, sizeof reference, sizeof estimator, sizeof allocator, sizeof curve);
  if (!init()) return 2;

  // The vehicle's true state (double) and what the sensors hand the
  // controller (float).
  neurov::Vector6<double> eta = Eigen::Map<const Vec6>(kMission[0]).cast<double>();
  neurov::Vector6<double> nu = neurov::Vector6<double>::Zero();
  Vec6 tau = Vec6::Zero();
  neurov::DesiredState<Scalar> desired;
  const neurov::ThrusterCurve<Scalar>* curves[kThrusters];
  for (auto& c : curves) c = &curve;
  Allocator::Vector thrusts, commands;

  for (int k = 0; k < kSteps; ++k) {
    const Scalar t = k * kDt;
    const int waypoint = static_cast<int>(t / kWaypointTime);
    const Vec6 command = Eigen::Map<const Vec6>(kMission[waypoint < kWaypoints ? waypoint : kWaypoints - 1]);

    // --- one control cycle: sensors in, thruster commands out
    const double t0 = now_ns();
    const neurov::Status sensed = sensors.feed(k, eta, nu);
    Vec6 eta_est = estimator.eta();
    const Vec6 nu_est = estimator.nu();
    const double t1 = now_ns();
    const neurov::Status ref_status = reference.step(command, kDt, desired);
    // The estimator keeps the yaw in (-pi, pi]; the mission turns through
    // 270 deg, so the yaw handed on is the one nearest the desired yaw.
    eta_est(5) = desired.eta_d(5) + std::remainder(eta_est(5) - desired.eta_d(5), 2 * 3.14159265f);
    neurov::Status status = controller.step(eta_est, nu_est, desired, tau);
    const double t2 = now_ns();
    const neurov::Status allocated = allocator.allocate(tau, kSupplyVoltage, curves, thrusts, commands);
    log_data.step_ns_total += t2 - t1;
    log_data.cycle_ns_total += now_ns() - t0;
    if (ref_status != neurov::Status::ok) status = ref_status;
    if (sensed != neurov::Status::ok) status = sensed;
    if (status != neurov::Status::ok) {
      // The controller has already set tau = 0 and kept its state; a vehicle
      // would hold station or surface after repeated refusals.
      ++log_data.refused_steps;
    }
    if (allocated != neurov::Status::ok) ++log_data.refused_allocations;  // neutral commands

    // --- the vehicle moves (on a vehicle: the world does this): each
    // thruster gives its curve's thrust for its command, pushing along B.
    neurov::Vector6<double> tau_plant = neurov::Vector6<double>::Zero();
    for (int i = 0; i < kThrusters; ++i)
      tau_plant += layout.col(i).cast<double>() *
                   static_cast<double>(curve.static_thrust(commands(i), kSupplyVoltage));
    tau_plant(5) += kDisturbanceNm * std::sin(2.0 * 3.14159265358979 * t / kDisturbancePeriod);
    for (int i = 0; i < kPlantSubsteps; ++i)
      neurov::rk4_step(vehicle_model, eta, nu, tau_plant, kDt / kPlantSubsteps);

    // --- log: the controller's status and the tracking error
    // (the true error: the controller sees only the estimate)
    const auto& e = controller.tracking();
    const double position_error = (eta.head<3>() - desired.eta_d.head<3>().cast<double>()).norm();
    const double estimate_error = (eta.head<3>() - eta_est.head<3>().cast<double>()).norm();
    if (position_error > log_data.max_position_error) log_data.max_position_error = position_error;
    if (k >= kSteps / 2) {
      log_data.sum_sq_position += position_error * position_error;
      log_data.sum_sq_estimate += estimate_error * estimate_error;
      ++log_data.samples;
    }
    if (k % 50 == 0 || k == kSteps - 1)
      std::printf("t = %5.1f s  status %-16s |eta~ xyz| = %.3f m  yaw~ = %+6.2f deg  "
                  "|s| = %.3f  ||W|| = %.3f\n",
                  static_cast<double>(t), neurov::to_string(status), position_error,
                  static_cast<double>(e.eta_tilde(5)) * 57.2957795, static_cast<double>(e.s.norm()),
                  static_cast<double>(controller.weight_norm()));
  }

  const double rms = std::sqrt(log_data.sum_sq_position / log_data.samples);
  const double rms_estimate = std::sqrt(log_data.sum_sq_estimate / log_data.samples);
  std::printf("RMS position error (second half, true state): %.4f m, max %.4f m, refused steps: %d, "
              "refused allocations: %d\n",
              rms, log_data.max_position_error, log_data.refused_steps, log_data.refused_allocations);
  std::printf("RMS error of the position estimate (second half): %.4f m (acoustic fixes: %.2f m)\n",
              rms_estimate, kFixNoise);
  std::printf("mean time of reference + controller step on this host: %.2f us\n",
              log_data.step_ns_total / kSteps * 1e-3);
  std::printf("mean time of a whole control cycle (estimator, reference, controller, allocation) "
              "on this host: %.2f us\n",
              log_data.cycle_ns_total / kSteps * 1e-3);
  // A regression guard for CI: the loop must track and never refuse a step.
  return (log_data.refused_steps == 0 && log_data.refused_allocations == 0 && rms < 0.25 &&
          rms_estimate < kFixNoise)
             ? 0
             : 1;
}
