// The control task of a vehicle computer, written as firmware writes it:
//   * parameters compiled in (on a vehicle: a calibration table in flash);
//   * every object static, sized at compile time: N is a template argument,
//     so nothing here touches the heap, not even at start-up;
//   * a fixed-rate loop: read the sensors, step the reference model, step the
//     controller, write the thrusters, log; every step is noexcept and returns
//     a status that the loop acts on.
// Built with -fno-exceptions -fno-rtti in float. The "vehicle" is neurov's
// model of NEROV (the paper's vehicle) in double, integrated at 50 Hz, with a
// sinusoidal yaw disturbance like the paper's Fig. 5.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <neurov/model/integrator.hpp>
#include <neurov/control/nn_controller.hpp>
#include <neurov/control/reference_model.hpp>
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
Controller controller;
neurov::ReferenceModel<Scalar> reference;
neurov::Vehicle<double> vehicle_model;

struct Log {
  double sum_sq_position = 0.0;  // over the second half of the mission
  int samples = 0;
  double max_position_error = 0.0;
  int refused_steps = 0;
  double step_ns_total = 0.0;
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
bool init() {
  if (const auto e = neurov::Vehicle<double>::create(neurov::nerov_parameters<double>(),
                                                     vehicle_model)) {
    char msg[160];
    e.format(msg, sizeof msg);
    std::printf("vehicle model: %s\n", msg);
    return false;
  }
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
  return true;
}

}  // namespace

int main() {
  std::printf("neurov %s firmware example: float, N = %d centres, %d inputs, %.0f Hz\n",
              NEUROV_VERSION_STRING, kCentres, kInputs, 1.0 / kDt);
  std::printf("static storage: controller %zu B, reference model %zu B\n", sizeof controller,
              sizeof reference);
  if (!init()) return 2;

  // The vehicle's true state (double) and what the sensors hand the
  // controller (float).
  neurov::Vector6<double> eta = Eigen::Map<const Vec6>(kMission[0]).cast<double>();
  neurov::Vector6<double> nu = neurov::Vector6<double>::Zero();
  Vec6 tau = Vec6::Zero();
  neurov::DesiredState<Scalar> desired;

  for (int k = 0; k < kSteps; ++k) {
    const Scalar t = k * kDt;
    const int waypoint = static_cast<int>(t / kWaypointTime);
    const Vec6 command = Eigen::Map<const Vec6>(kMission[waypoint < kWaypoints ? waypoint : kWaypoints - 1]);

    // --- the control step: sensors in, thrust out
    const Vec6 eta_meas = eta.cast<Scalar>(), nu_meas = nu.cast<Scalar>();
    const double t0 = now_ns();
    const neurov::Status ref_status = reference.step(command, kDt, desired);
    neurov::Status status = controller.step(eta_meas, nu_meas, desired, tau);
    log_data.step_ns_total += now_ns() - t0;
    if (ref_status != neurov::Status::ok) status = ref_status;
    if (status != neurov::Status::ok) {
      // The controller has already set tau = 0 and kept its state; a vehicle
      // would hold station or surface after repeated refusals.
      ++log_data.refused_steps;
    }

    // --- the vehicle moves (on a vehicle: the world does this)
    neurov::Vector6<double> tau_plant = tau.cast<double>();
    tau_plant(5) += kDisturbanceNm * std::sin(2.0 * 3.14159265358979 * t / kDisturbancePeriod);
    for (int i = 0; i < kPlantSubsteps; ++i)
      neurov::rk4_step(vehicle_model, eta, nu, tau_plant, kDt / kPlantSubsteps);

    // --- log: the controller's status and its tracking error
    const auto& e = controller.tracking();
    const double position_error = e.eta_tilde.head<3>().norm();
    if (position_error > log_data.max_position_error) log_data.max_position_error = position_error;
    if (k >= kSteps / 2) {
      log_data.sum_sq_position += position_error * position_error;
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
  std::printf("RMS position error (second half): %.4f m, max %.4f m, refused steps: %d\n", rms,
              log_data.max_position_error, log_data.refused_steps);
  std::printf("mean time of reference + controller step on this host: %.2f us\n",
              log_data.step_ns_total / kSteps * 1e-3);
  // A regression guard for CI: the loop must track and never refuse a step.
  return (log_data.refused_steps == 0 && rms < 0.25) ? 0 : 1;
}
