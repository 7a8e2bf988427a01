// Everything of a closed-loop run except the controller, as an object that is
// stepped one control period at a time: the vehicle, the reference model and
// its command, thrusters (allocation, saturation, lag, failures), current and
// disturbances, measurement noise and sensor faults. Whoever drives it - the
// C++ loop in closed_loop.hpp, a Python controller, a learning agent - sees the
// same observations and gets the same rows for the same forces.
//
// The sources of force and flow on the plant (the sinusoidal forces, the
// current models, the waves, the payload events, the thruster failures) are
// the disturbance parts of DisturbanceParts (config.hpp), each with its own
// state in parts_ and its own hooks (sim/disturbances/part.hpp); step() calls
// the hooks at the row, at each substep and at the period's end. Without
// waves the plant step is rk4_step, as before they existed.
//
// Timing: control at dt with the force held over each control interval
// (zero-order hold); the plant integrated by RK4 at dt / substeps, thrusters
// advanced per substep; the reference model advanced at the control rate. Row
// k of the result is the instant t_k = k dt: the true state there, the
// desired state the controller was given, and the force it demanded from the
// measurement at t_k. With control_delay = n that force acts over
// [t_k+n, t_k+n+1) (the computation's delay, in whole periods); the forces
// waiting to act sit in a fixed ring, so a step allocates nothing. n = 0 is
// the force acting over [t_k, t_k+1).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "neurov/control/desired_state.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/core/random.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/flow.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/thrusters.hpp"
#include "neurov/model/vehicle.hpp"
#include "neurov/sim/config.hpp"
#include "neurov/sim/gauss_markov_current.hpp"
#include "neurov/sim/payload.hpp"
#include "neurov/sim/reference_trajectory.hpp"
#include "neurov/sim/result.hpp"
#include "neurov/sim/sea_constants.hpp"
#include "neurov/sim/sensing.hpp"
#include "neurov/sim/waves.hpp"

namespace neurov {

/// What a controller is given at t_k: the pose and velocity as measured
/// (noise, or the sensors' readings or estimate, and the sensor faults
/// applied; NaN during a dropout) and the desired state from the reference
/// model.
template <typename Scalar>
struct Observation {
  Scalar t = Scalar(0);
  Vector6<Scalar> eta = Vector6<Scalar>::Zero();
  Vector6<Scalar> nu = Vector6<Scalar>::Zero();
  DesiredState<Scalar> desired;
};

/// What the result logs of a controller's step besides its force.
template <typename Scalar>
struct ControllerReport {
  /// Anything but ok is a refused step: the run's RefusedStepPolicy decides
  /// the force applied, and the force passed is ignored.
  Status status = Status::ok;
  Vector6<Scalar> s = Vector6<Scalar>::Zero();  ///< filtered tracking error
  Scalar adaptive_norm = Scalar(0);             ///< how far the adaptive part moved
  /// parameter_count logged parameters (theta_hat of the linear adaptive
  /// controller), or nullptr and 0; the count is fixed when the simulator is
  /// created.
  const Scalar* parameters = nullptr;
  int parameter_count = 0;
};

template <typename Scalar>
class Simulator {
 public:
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;

  /// Empty: done() is true and step() refuses until create() fills it.
  Simulator() = default;

  /// Validates the vehicle and the configuration, copies them, and allocates
  /// the result rows (the only allocation), with `logged_parameters`
  /// parameter columns: the rows of the whole duration, or with `log_rows`
  /// > 0 a window of at most that many rows, which drain() empties (a run of
  /// any length then needs the memory of one window). `out` is untouched on
  /// failure. Ready at t = 0 with the configuration's seed.
  static ValidationError create(const Vehicle<Scalar>& vehicle,
                                const SimulationConfig<Scalar>& config, Simulator& out,
                                int logged_parameters = 0, Eigen::Index log_rows = 0) {
    if (!vehicle.valid()) return detail::invalid("vehicle", -1, std::nan(""), "a valid vehicle");
    if (auto e = validate(config)) return e;
    Simulator s;
    if (auto e = Parts::create(config, vehicle, s.parts_)) return e;
    if (logged_parameters < 0)
      return detail::invalid("logged_parameters", -1, static_cast<double>(logged_parameters),
                             ">= 0");
    if (log_rows < 0)
      return detail::invalid("log_rows", -1, static_cast<double>(log_rows),
                             ">= 0 (0: every row of the run)");
    // Both were checked by validate(); create() builds them.
    ReferenceModel<Scalar> reference;
    ReferenceModel<Scalar>::create(config.lambda_d, config.omega, config.eta0, reference);
    Thrusters<Scalar> thrusters;
    if (config.use_thrusters) Thrusters<Scalar>::create(config.thrusters, thrusters);
    s.vehicle_ = vehicle;
    s.vehicle0_ = vehicle;
    s.config_ = config;
    s.reference_ = std::move(reference);
    s.thrusters_ = std::move(thrusters);
    s.rows_ = static_cast<Eigen::Index>(std::llround(config.duration / config.dt)) + 1;
    s.thruster_count_ = config.use_thrusters ? s.thrusters_.count() : 0;
    s.parameter_count_ = logged_parameters;
    s.noisy_ = !(config.noise_eta.isZero(Scalar(0)) && config.noise_nu.isZero(Scalar(0)));
    s.h_ = config.dt / static_cast<Scalar>(config.substeps);
    Sensing<Scalar>::create(config.sensors, config.estimator, config.seed, s.sensing_);
    s.log_rows_ = log_rows > 0 ? std::min(log_rows, s.rows_) : s.rows_;
    s.result_.allocate(s.log_rows_, s.thruster_count_, logged_parameters);
    s.configured_ = true;
    s.reset(config.seed);
    out = std::move(s);
    return {};
  }

  /// Back to t = 0 with the seed of the last reset (the configuration's at
  /// first): the same run again. Clears the rows; allocates nothing.
  void reset() noexcept { reset(seed_); }

  /// Back to t = 0 with measurement noise drawn from `seed`.
  void reset(std::uint64_t seed) noexcept {
    if (!configured_) return;
    seed_ = seed;
    rng_.reseed(seed);
    reference_.reset(config_.eta0);
    if (config_.use_thrusters) thrusters_.reset();
    eta_ = config_.eta0;
    nu_ = config_.nu0;
    // The disturbances, each random one on its own stream of `seed`;
    // validate() has checked their configurations, so their creates succeed.
    Parts::reset(config_, parts_, seed, plant());
    // The sensors' first samples, at t = 0 (validate() checked them).
    sensing_.reset(seed, eta_, nu_);
    observation_.desired = shared_reference_ ? shared_reference_->desired(0) : reference_.desired();
    held_eta_ = eta_;
    held_nu_ = nu_;
    last_accepted_tau_.setZero();
    for (Vec6& f : pending_tau_) f.setZero();
    result_.clear();
    k_ = 0;
    log_first_ = 0;
    observe();
  }

  /// What the controller is to be given at t_k = steps() dt.
  const Observation<Scalar>& observation() const noexcept { return observation_; }
  /// fault_bits of the sensor faults and the pitch limit active in the
  /// observation (the thruster bit is set by step()).
  std::uint8_t faults() const noexcept { return faults_; }

  /// Logs row k with the controller's force `tau` (or, on a refused step, the
  /// force the refused-step policy gives) and advances the plant one control
  /// period to t_k+1, where the next observation is measured. Returns the
  /// plant's status: ok, near_singularity, or another status when the plant
  /// diverged (then the row is the last, diverged() and done()).
  /// A call that is refused returns invalid_argument (after done(); with the
  /// log window full, see log_full(); a report whose parameter_count is not
  /// the one of create) or non_finite_input (an accepted step with a
  /// non-finite force) and changes nothing.
  Status step(const Vec6& tau, const ControllerReport<Scalar>& report) noexcept {
    if (const Status refused = begin_period(tau, report); refused != Status::ok) return refused;
    for (int j = 0; j < config_.substeps; ++j) {
      Vec6 tau_s;
      const parts::Substep<Scalar> sub = begin_substep(j, tau_s);
      const Status s = sub.in_flow
                           ? rk4_step_in_flow(vehicle_, eta_, nu_, tau_s, h_, sub.start, sub.mid, sub.end)
                           : rk4_step(vehicle_, eta_, nu_, tau_s, h_, sub.current);
      if (!end_substep(j, s)) break;
    }
    return end_period();
  }

  /// The run is over: every row logged, or the plant diverged.
  bool done() const noexcept { return k_ >= rows_ || result_.diverged; }
  bool diverged() const noexcept { return result_.diverged; }
  /// The true state at t_k = steps() dt (the last state reached if diverged).
  const Vec6& eta() const noexcept { return eta_; }
  const Vec6& nu() const noexcept { return nu_; }
  /// Rows logged so far (drained ones included).
  Eigen::Index steps() const noexcept { return k_; }
  /// Rows the log holds at most: every row of the run, or the window of create().
  Eigen::Index log_rows() const noexcept { return log_rows_; }
  /// The run's index of the log's first row: the rows drained before it.
  Eigen::Index logged_from() const noexcept { return log_first_; }
  /// The log window is full: step() refuses until drain() empties it.
  bool log_full() const noexcept { return k_ - log_first_ >= log_rows_; }
  /// Rows of a whole run: round(duration / dt) + 1.
  Eigen::Index planned_steps() const noexcept { return rows_; }
  int logged_parameters() const noexcept { return parameter_count_; }
  Eigen::Index thruster_count() const noexcept { return thruster_count_; }
  const SimulationConfig<Scalar>& config() const noexcept { return config_; }
  const Vehicle<Scalar>& vehicle() const noexcept { return vehicle_; }
  /// The sensors and the estimator (inactive without sensors).
  const Sensing<Scalar>& sensing() const noexcept { return sensing_; }

  /// A copy of the rows in the log: the rows logged so far, or since the last
  /// drain() (allocates).
  SimulationResult<Scalar> result() const {
    SimulationResult<Scalar> out = result_;
    out.truncate(k_ - log_first_);
    return out;
  }

  /// Copies the rows in the log into `out` (allocates) and empties the log,
  /// so that stepping can go on past a full window; returns how many rows.
  /// `out.diverged` says whether the run has diverged.
  Eigen::Index drain(SimulationResult<Scalar>& out) {
    const Eigen::Index n = k_ - log_first_;
    out = result_;
    out.truncate(n);
    const bool diverged = result_.diverged;
    result_.clear();
    result_.diverged = diverged;
    log_first_ = k_;
    return n;
  }

  /// The log itself, without a copy: its first steps() - logged_from() rows
  /// are the rows logged since the last drain or discard.
  const SimulationResult<Scalar>& log() const noexcept { return result_; }

  /// Empties the log as drain() does, without handing its rows over (who
  /// read them through log() is done with them); allocates nothing.
  void discard() noexcept {
    const bool diverged = result_.diverged;
    result_.clear();
    result_.diverged = diverged;
    log_first_ = k_;
  }

  /// Moves the rows in the log into `out` without a copy; the simulator is
  /// empty afterwards (create it again to run again).
  void release_result(SimulationResult<Scalar>& out) {
    const Eigen::Index n = k_ - log_first_;
    out = std::move(result_);
    if (n < out.t.size()) out.truncate(n);
    *this = Simulator();
  }

 private:
  /// The measurement at t_k = k_ dt: noise for this row, then the sensor
  /// faults in their order (a noise burst draws after the measurement noise).
  void observe() noexcept {
    const Scalar t = ReferenceTrajectory<Scalar>::row_time(k_, config_.dt);
    Vec6 eta_m = eta_, nu_m = nu_;
    if (sensing_.active()) sensing_.measurement(eta_, nu_, eta_m, nu_m);
    if (noisy_) {
      for (int i = 0; i < 6; ++i) {
        eta_m(i) += config_.noise_eta(i) * static_cast<Scalar>(rng_.normal());
        nu_m(i) += config_.noise_nu(i) * static_cast<Scalar>(rng_.normal());
      }
    }
    // The desired state (this row's eta_d) is from the last accepted reference step.
    const bool pitch_limited =
        shared_reference_ ? shared_reference_->pitch_limited(k_) : reference_.pitch_limited();
    std::uint8_t faults = pitch_limited ? fault_bits::pitch_limited : std::uint8_t(0);
    bool freeze_eta = false, freeze_nu = false;
    const Scalar nan = std::numeric_limits<Scalar>::quiet_NaN();
    for (const auto& f : config_.sensor_faults) {
      if (!(t >= f.start && t < f.end)) continue;
      if (f.kind == SensorFaultKind::freeze) {
        faults |= fault_bits::freeze;
        freeze_eta = freeze_eta || f.eta;
        freeze_nu = freeze_nu || f.nu;
      } else if (f.kind == SensorFaultKind::dropout) {
        faults |= fault_bits::dropout;
        if (f.eta) eta_m.setConstant(nan);
        if (f.nu) nu_m.setConstant(nan);
      } else {
        faults |= fault_bits::noise_burst;
        for (int i = 0; i < 6; ++i) {
          if (f.eta) eta_m(i) += f.noise_eta(i) * static_cast<Scalar>(rng_.normal());
          if (f.nu) nu_m(i) += f.noise_nu(i) * static_cast<Scalar>(rng_.normal());
        }
      }
    }
    // A freeze repeats the last measurement delivered unfrozen.
    if (freeze_eta)
      eta_m = held_eta_;
    else if (eta_m.allFinite())
      held_eta_ = eta_m;
    if (freeze_nu)
      nu_m = held_nu_;
    else if (nu_m.allFinite())
      held_nu_ = nu_m;
    faults_ = faults;
    observation_.t = t;
    observation_.eta = eta_m;
    observation_.nu = nu_m;
  }

  // step() in its parts, so that a batch (sim/batch.hpp) can integrate the
  // substeps of many runs' plants together between them: begin_period()
  // (validate, log the row, the disturbances' and thrusters' share before
  // the plant), then per substep begin_substep() (its force and flow) and,
  // once the plant has moved, end_substep() (its status, the sensors), and
  // end_period() (the row's totals, the reference, the next observation).

  /// ok, or the refusal that step() returns (nothing changed then).
  Status begin_period(const Vec6& tau, const ControllerReport<Scalar>& report) noexcept {
    if (done() || log_full()) return Status::invalid_argument;
    if (report.parameter_count != parameter_count_ ||
        (parameter_count_ > 0 && report.parameters == nullptr))
      return Status::invalid_argument;
    if (report.status == Status::ok && !tau.allFinite()) return Status::non_finite_input;
    Period& p = period_;
    p.k = k_;
    p.row = k_ - log_first_;  // in the log window
    p.t = observation_.t;
    const Vec6 applied_tau = policy_force(tau, report.status);
    log_row(p.row, applied_tau, report);
    const parts::Plant<Scalar> plant = this->plant();
    // The disturbances' events due now, then their force and flow at t_k.
    const parts::Substep<Scalar> at = Parts::row(config_, parts_, p.t, plant, p.row, result_);
    p.acting_tau = delayed(p.k, applied_tau);
    if (config_.use_thrusters) thrusters_.command(p.acting_tau);
    Parts::follow(config_, parts_, plant,
                  (config_.use_thrusters ? Vec6(thrusters_.wrench()) : p.acting_tau) + at.force, at);
    p.faults = faults_;
    p.status = Status::ok;
    p.applied_mean.setZero();
    return Status::ok;
  }

  /// Substep j's disturbances and flow; tau_s is the force on the plant.
  parts::Substep<Scalar> begin_substep(int j, Vec6& tau_s) noexcept {
    Period& p = period_;
    const Scalar offset = static_cast<Scalar>(j) * h_;
    const parts::Substep<Scalar> sub =
        Parts::substep(config_, parts_, p.t + offset, offset, h_, plant());
    // The row's tau_applied is the substeps' mean, summed term by term (as the
    // thrusts are): a sum first would overflow to inf in float when the forces
    // are finite but near the largest float.
    const Scalar substeps = static_cast<Scalar>(config_.substeps);
    const Vec6 applied = config_.use_thrusters ? thrust(p.row, substeps) : p.acting_tau;
    p.applied_mean += applied / substeps;
    p.faults |= sub.faults;
    tau_s = applied + sub.force;
    return sub;
  }

  /// The plant's status over substep j, its state now at the substep's end;
  /// false when it diverged (the period's substeps end there).
  bool end_substep(int j, Status plant_status) noexcept {
    Period& p = period_;
    p.status = worst(p.status, plant_status);
    if (p.status != Status::ok && p.status != Status::near_singularity) return false;
    // The sensors sample the state at the end of each substep (times in
    // double: a float clock loses milliseconds within hours).
    sensing_.sense(static_cast<double>(p.k) * static_cast<double>(config_.dt) +
                       static_cast<double>(j + 1) * static_cast<double>(h_),
                   eta_, nu_);
    return true;
  }

  /// What step() returns.
  Status end_period() noexcept {
    Period& p = period_;
    Parts::advance(config_, parts_, config_.dt);
    result_.tau_applied.row(p.row) = p.applied_mean.transpose();
    result_.plant_status(p.row) = static_cast<std::uint8_t>(p.status);
    result_.faults(p.row) = p.faults;
    k_ = p.k + 1;
    result_.steps = p.row + 1;
    if (p.status != Status::ok && p.status != Status::near_singularity) {
      result_.diverged = true;
      return p.status;
    }
    // The desired state for t_k+1; on a refused reference step it stays.
    if (shared_reference_)
      observation_.desired = shared_reference_->desired(k_);
    else
      reference_.step(config_.command.at(p.t), config_.dt, observation_.desired);
    if (k_ < rows_) observe();
    return p.status;
  }

  /// The plant's state and step, for a batch that integrates it.
  Vec6& plant_eta() noexcept { return eta_; }
  Vec6& plant_nu() noexcept { return nu_; }
  Scalar substep_length() const noexcept { return h_; }

  /// The force a step applies: the controller's, or on a refused step the
  /// one the refused-step policy gives.
  Vec6 policy_force(const Vec6& tau, Status status) noexcept {
    if (status == Status::ok) {
      last_accepted_tau_ = tau;
      return tau;
    }
    return config_.refused_step_policy == RefusedStepPolicy::hold ? last_accepted_tau_
                                                                  : Vec6::Zero().eval();
  }

  /// The force demanded at row k waits control_delay periods; returns the
  /// one due now (zero before the first one is due), which acts over this
  /// control interval.
  Vec6 delayed(Eigen::Index k, const Vec6& demanded) noexcept {
    const int n = config_.control_delay;
    pending_tau_[static_cast<std::size_t>(k % kPendingSlots)] = demanded;
    return k >= n ? pending_tau_[static_cast<std::size_t>((k - n) % kPendingSlots)]
                  : Vec6::Zero().eval();
  }

  /// The thrusters over one substep: their wrench, and their thrusts added
  /// to the row's mean.
  Vec6 thrust(Eigen::Index row, Scalar substeps) noexcept {
    thrusters_.advance(h_);
    if (thruster_count_ > 0)
      result_.thrusts.row(row) +=
          thrusters_.efficiency().cwiseProduct(thrusters_.thrust()).transpose() / substeps;
    return thrusters_.wrench();
  }

  /// Row `row`'s instant, states and what the controller gave.
  void log_row(Eigen::Index row, const Vec6& applied_tau,
               const ControllerReport<Scalar>& report) noexcept {
    SimulationResult<Scalar>& r = result_;
    const DesiredState<Scalar>& desired = observation_.desired;
    r.t(row) = observation_.t;
    r.eta.row(row) = eta_.transpose();
    r.nu.row(row) = nu_.transpose();
    r.eta_estimate.row(row) = observation_.eta.transpose();
    r.nu_estimate.row(row) = observation_.nu.transpose();
    r.eta_d.row(row) = desired.eta_d.transpose();
    r.eta_d_dot.row(row) = desired.eta_d_dot.transpose();
    r.tau_demanded.row(row) = applied_tau.transpose();
    r.s.row(row) = report.s.transpose();
    r.adaptive_norm(row) = report.adaptive_norm;
    r.controller_status(row) = static_cast<std::uint8_t>(report.status);
    if (parameter_count_ > 0)
      r.theta.row(row) =
          Eigen::Map<const Eigen::Matrix<Scalar, 1, Eigen::Dynamic>>(report.parameters,
                                                                     parameter_count_);
  }

  /// Follow `shared` (ReferenceTrajectory) instead of stepping reference_,
  /// when it is this run's reference (false otherwise, nothing changed). Set
  /// by a batch between steps; the rows are those of reference_ to the bit.
  bool follow_reference(const std::shared_ptr<const ReferenceTrajectory<Scalar>>& shared) noexcept {
    if (!shared || !shared->matches(config_, rows_)) return false;
    shared_reference_ = shared;
    return true;
  }

  /// The plant as the disturbance parts see and change it.
  parts::Plant<Scalar> plant() noexcept {
    return parts::Plant<Scalar>{vehicle_, vehicle0_, thrusters_, eta_, nu_};
  }

  template <typename S>
  friend class BatchSimulator;
  template <typename S, typename C>
  friend class BatchRun;
  using Parts = DisturbanceParts<Scalar>;
  static constexpr Eigen::Index kPendingSlots = kMaxControlDelay + 1;

  /// The control period step() is in (begin_period() to end_period()).
  struct Period {
    Eigen::Index k = 0, row = 0;
    Scalar t = Scalar(0);
    Vec6 acting_tau = Vec6::Zero();
    Vec6 applied_mean = Vec6::Zero();
    std::uint8_t faults = 0;
    Status status = Status::ok;
  };

  Vehicle<Scalar> vehicle_;   ///< the plant, changed by the payload events
  Vehicle<Scalar> vehicle0_;  ///< the plant at t = 0
  /// The disturbance parts' states (payload, current, waves, ...).
  typename Parts::States parts_;
  SimulationConfig<Scalar> config_;
  ReferenceModel<Scalar> reference_;
  /// This run's reference precomputed and shared with a batch's other lanes
  /// (sim/reference_trajectory.hpp); null: reference_ is stepped.
  std::shared_ptr<const ReferenceTrajectory<Scalar>> shared_reference_;
  Thrusters<Scalar> thrusters_;
  Sensing<Scalar> sensing_;
  NormalRandom rng_;
  std::uint64_t seed_ = 0;
  bool configured_ = false;
  bool noisy_ = false;
  Scalar h_ = Scalar(0);
  Eigen::Index rows_ = 0;
  Eigen::Index log_rows_ = 0;   // rows the log holds at most
  Eigen::Index log_first_ = 0;  // the run's index of the log's row 0
  Eigen::Index k_ = 0;
  Eigen::Index thruster_count_ = 0;
  int parameter_count_ = 0;
  Vec6 eta_ = Vec6::Zero(), nu_ = Vec6::Zero();
  // The last measurements delivered unfrozen, which a freeze keeps repeating.
  Vec6 held_eta_ = Vec6::Zero(), held_nu_ = Vec6::Zero();
  Vec6 last_accepted_tau_ = Vec6::Zero();
  /// Forces demanded and not yet acting: row k's at slot k mod kPendingSlots.
  std::array<Vec6, kPendingSlots> pending_tau_{};
  Observation<Scalar> observation_;
  std::uint8_t faults_ = 0;
  Period period_;
  SimulationResult<Scalar> result_;
};

}  // namespace neurov
