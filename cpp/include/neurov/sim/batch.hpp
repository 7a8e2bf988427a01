// K independent runs: each lane its own vehicle and
// configuration (seeds, disturbances, thrusters, sensors, estimator) and, in
// run_batch, its own built-in controller. A lane that diverges or ends early
// stops while the others go on. BatchSimulator::step steps every lane one
// control period (lockstep, one call for all lanes from Python).
//
// Each lane is a Simulator (simulator.hpp), stepped through the same parts
// of a control period that Simulator::step calls; between them the batch
// integrates the plants of up to kPlantBlockWidth lanes at a time in SIMD
// lanes (model/plant_block.hpp), the same RK4 kernel a run alone goes
// through on one lane. So a lane gives exactly the result of the same run
// alone (statuses, faults, divergence step, every series; the tests check
// it). Lanes whose plant the kernel does not cover (a vehicle with r_g != 0
// or off-diagonal mass, waves) take the scalar step inside the same loop.
// Lanes with the same reference (gains, start, command, period, length)
// read one ReferenceTrajectory (sim/reference_trajectory.hpp) made once by
// the batch, instead of each integrating the same reference model.
//
// step_threaded and run_batch split the lanes over worker threads
// (std::thread, or a WorkerPool's for step_threaded), each stepping a
// contiguous share; the lanes share only read-only trajectories, so the
// split changes no result.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <cstddef>
#include <cstdint>
#include <system_error>
#include <thread>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "neurov/control/built_in_controllers.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/flow.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/plant_block.hpp"
#include "neurov/sim/closed_loop.hpp"
#include "neurov/sim/config.hpp"
#include "neurov/sim/reference_trajectory.hpp"
#include "neurov/sim/result.hpp"
#include "neurov/sim/simulator.hpp"
#include "neurov/sim/window_sums.hpp"
#include "neurov/sim/worker_pool.hpp"

namespace neurov {

/// The status step() reports for a lane it did not step (masked out, or
/// already done): not a neurov::Status value.
inline constexpr std::uint8_t kLaneNotStepped = 255;

template <typename Scalar>
class BatchSimulator {
 public:
  using Vec6 = Vector6<Scalar>;
  using Sim = Simulator<Scalar>;

  BatchSimulator() = default;

  /// One lane per (vehicles[i], configs[i]), each created as
  /// Simulator::create would with `logged_parameters` parameter columns. On
  /// failure `out` is untouched, and `failed_lane` (if given) says which lane
  /// was refused.
  static ValidationError create(const std::vector<Vehicle<Scalar>>& vehicles,
                                const std::vector<SimulationConfig<Scalar>>& configs,
                                BatchSimulator& out, int logged_parameters = 0,
                                Eigen::Index log_rows = 0, std::size_t* failed_lane = nullptr) {
    return create_lanes(vehicles, configs, out, std::vector<int>(vehicles.size(), logged_parameters),
                        log_rows, failed_lane);
  }

  /// The same with lane i logging logged_parameters[i] parameters (lanes of
  /// different controller types); step() then takes no parameters.
  static ValidationError create_lanes(const std::vector<Vehicle<Scalar>>& vehicles,
                                      const std::vector<SimulationConfig<Scalar>>& configs,
                                      BatchSimulator& out, const std::vector<int>& logged_parameters,
                                      Eigen::Index log_rows = 0, std::size_t* failed_lane = nullptr) {
    if (vehicles.size() != configs.size())
      return detail::invalid("configs", -1, static_cast<double>(configs.size()),
                             "one configuration per vehicle");
    BatchSimulator b;
    b.lanes_.resize(vehicles.size());
    for (std::size_t i = 0; i < vehicles.size(); ++i) {
      if (auto e = Sim::create(vehicles[i], configs[i], b.lanes_[i], logged_parameters[i], log_rows)) {
        if (failed_lane) *failed_lane = i;
        return e;
      }
    }
    const bool uniform = std::adjacent_find(logged_parameters.begin(), logged_parameters.end(),
                                            std::not_equal_to<int>()) == logged_parameters.end();
    b.logged_parameters_ = uniform && !logged_parameters.empty() ? logged_parameters[0] : 0;
    b.log_rows_ = log_rows;
    b.share_references();
    out = std::move(b);
    return {};
  }

  std::size_t size() const noexcept { return lanes_.size(); }
  int logged_parameters() const noexcept { return logged_parameters_; }
  /// Rows each lane's log holds: 0 for every row of a run, else the window
  /// of create() (a batch whose rows are read from its observations, a
  /// vector environment's, keeps a window of one row: its memory is the
  /// lanes' state, not a run's rows per lane).
  Eigen::Index log_rows() const noexcept { return log_rows_; }

  /// Lane i's log emptied (Simulator::discard): its rows were read elsewhere.
  void discard(std::size_t i) noexcept { lanes_[i].discard(); }

  /// Lane i re-created from a new vehicle and configuration (a new episode's
  /// plant); on failure lane i is untouched.
  ValidationError replace(std::size_t i, const Vehicle<Scalar>& vehicle,
                          const SimulationConfig<Scalar>& config) {
    Sim s;
    if (auto e = Sim::create(vehicle, config, s, lanes_[i].logged_parameters(), log_rows_)) return e;
    // The new lane joins a trajectory another lane follows, if one is its reference.
    for (std::size_t j = 0; j < lanes_.size(); ++j)
      if (j != i && s.follow_reference(lanes_[j].shared_reference_)) break;
    lanes_[i] = std::move(s);
    return {};
  }

  /// Whether lane i follows a reference trajectory shared with other lanes
  /// (sim/reference_trajectory.hpp) instead of stepping its own reference.
  bool shares_reference(std::size_t i) const noexcept {
    return lanes_[i].shared_reference_ != nullptr;
  }

  /// Lane i back to t = 0 with noise from `seed`.
  void reset(std::size_t i, std::uint64_t seed) noexcept { lanes_[i].reset(seed); }

  /// Every lane i with mask[i] (mask nullptr: every lane) back to t = 0 with
  /// noise from seeds[i].
  void reset(const std::uint64_t* seeds, const bool* mask) noexcept {
    for (std::size_t i = 0; i < lanes_.size(); ++i)
      if (!mask || mask[i]) lanes_[i].reset(seeds[i]);
  }

  /// Steps every lane i with mask[i] (mask nullptr: every lane) that is not
  /// done, with the force tau[6 i .. 6 i + 5] (row i of a row-major (K, 6)
  /// block) and, with logged parameters, parameters[P i .. P i + P - 1]
  /// (P = logged_parameters(); nullptr: none given, refused when P > 0).
  /// statuses[i] is the lane's plant status (Simulator::step's, e.g.
  /// non_finite_input for a non-finite force, which changes nothing), or
  /// kLaneNotStepped for a lane not stepped.
  void step(const Scalar* tau, const bool* mask, std::uint8_t* statuses,
            const Scalar* parameters = nullptr) noexcept {
    step_lanes(0, lanes_.size(), tau, mask, statuses, parameters);
  }

  /// step() for the lanes i in [begin, end) only (the arrays still indexed
  /// by lane over the whole batch): lanes share nothing, so ranges stepped
  /// on different threads give the results of one step().
  void step_lanes(std::size_t begin, std::size_t end, const Scalar* tau, const bool* mask,
                  std::uint8_t* statuses, const Scalar* parameters = nullptr) noexcept {
    step_blocks(
        begin, std::min(end, lanes_.size()),
        [&](std::size_t i, Sim& sim) noexcept {
          if ((mask && !mask[i]) || sim.done()) {
            statuses[i] = kLaneNotStepped;
            return false;
          }
          ControllerReport<Scalar> report;
          report.parameter_count = sim.logged_parameters();
          report.parameters =
              parameters ? parameters + static_cast<std::ptrdiff_t>(i) * logged_parameters_ : nullptr;
          const Status refused =
              sim.begin_period(Eigen::Map<const Vec6>(tau + 6 * static_cast<std::ptrdiff_t>(i)), report);
          if (refused != Status::ok) statuses[i] = static_cast<std::uint8_t>(refused);
          return refused == Status::ok;
        },
        [&](std::size_t i, Sim&, Status s) noexcept { statuses[i] = static_cast<std::uint8_t>(s); });
  }

  /// Lane i's queries (observation, faults, state, done, steps, result, ...).
  const Sim& lane(std::size_t i) const noexcept { return lanes_[i]; }

 private:
  template <typename S, typename C>
  friend class BatchRun;
  Sim& lane_mut(std::size_t i) noexcept { return lanes_[i]; }

  /// One control period of the lanes in [begin, end), kPlantBlockWidth lanes
  /// at a time: `start(i, sim)` begins lane i's period (Simulator::
  /// begin_period) and returns whether it did; the substeps' plants then
  /// move together, and `finish(i, sim, status)` gets what Simulator::step
  /// would have returned. Returns how many lanes were stepped.
  template <typename Start, typename Finish>
  std::size_t step_blocks(std::size_t begin, std::size_t end, Start&& start,
                          Finish&& finish) noexcept {
    namespace pc = detail::plant_coef;
    PlantBlock<Scalar> block;
    std::size_t stepped = 0;
    for (std::size_t b0 = begin; b0 < end; b0 += kPlantBlockWidth) {
      const std::size_t b1 = std::min(end, b0 + kPlantBlockWidth);
      std::size_t active[kPlantBlockWidth];
      bool running[kPlantBlockWidth];
      int slot[kPlantBlockWidth];
      // Which active lane's coefficients block slot b holds (-1: none): a
      // lane keeps its slot from substep to substep unless one before it
      // drops out, and its vehicle changes only by a payload event.
      int coefficients_of[kPlantBlockWidth];
      std::fill(std::begin(coefficients_of), std::end(coefficients_of), -1);
      int n = 0, substeps = 0;
      for (std::size_t i = b0; i < b1; ++i) {
        if (!start(i, lanes_[i])) continue;
        running[n] = true;
        active[n++] = i;
        substeps = std::max(substeps, lanes_[i].config_.substeps);
      }
      for (int j = 0; j < substeps; ++j) {
        block.lanes = 0;
        for (int a = 0; a < n; ++a) {
          slot[a] = -1;
          Sim& sim = lanes_[active[a]];
          if (!running[a] || j >= sim.config_.substeps) {
            running[a] = false;
            continue;
          }
          Vec6 tau_s;
          const parts::Substep<Scalar> sub = sim.begin_substep(j, tau_s);
          if (sub.in_flow || !sim.vehicle_.diagonal()) {
            const Status st =
                sub.in_flow ? rk4_step_in_flow(sim.vehicle_, sim.eta_, sim.nu_, tau_s, sim.h_,
                                               sub.start, sub.mid, sub.end)
                            : rk4_step(sim.vehicle_, sim.eta_, sim.nu_, tau_s, sim.h_, sub.current);
            running[a] = sim.end_substep(j, st);
            continue;
          }
          const int b = slot[a] = block.lanes++;
          if (coefficients_of[b] != a || sub.vehicle_changed) {
            const Scalar* c = sim.vehicle_.plant_coefficients();
            for (int f = 0; f < pc::count; ++f) block.coefficients[f][b] = c[f];
            coefficients_of[b] = a;
          }
          for (int d = 0; d < 6; ++d) {
            block.eta[d][b] = sim.eta_(d);
            block.nu[d][b] = sim.nu_(d);
            block.tau[d][b] = tau_s(d);
          }
          for (int d = 0; d < 3; ++d) block.current[d][b] = sub.current(d);
          block.h[b] = sim.h_;
        }
        plant_rk4_block(block);
        // The block's padding lanes took lane 0's coefficients.
        for (int b = block.lanes; b < kPlantBlockWidth; ++b) coefficients_of[b] = -1;
        for (int a = 0; a < n; ++a) {
          if (slot[a] < 0) continue;
          Sim& sim = lanes_[active[a]];
          for (int d = 0; d < 6; ++d) {
            sim.eta_(d) = block.eta[d][slot[a]];
            sim.nu_(d) = block.nu[d][slot[a]];
          }
          running[a] = sim.end_substep(j, static_cast<Status>(block.status[slot[a]]));
        }
      }
      for (int a = 0; a < n; ++a) finish(active[a], lanes_[active[a]], lanes_[active[a]].end_period());
      stepped += static_cast<std::size_t>(n);
    }
    return stepped;
  }

  /// Lanes with the same reference (same_reference) follow one
  /// ReferenceTrajectory. The lanes are grouped against at most
  /// kReferenceGroups distinct references (a lane of a further one keeps
  /// its own), and a reference only one lane has is not shared.
  void share_references() {
    constexpr std::size_t kReferenceGroups = 64;
    std::vector<std::size_t> first;  // each group's first lane
    std::vector<std::size_t> group(lanes_.size(), kReferenceGroups), count;
    for (std::size_t i = 0; i < lanes_.size(); ++i) {
      const Sim& lane = lanes_[i];
      std::size_t g = 0;
      while (g < first.size() &&
             !same_reference(lanes_[first[g]].config_, lanes_[first[g]].rows_, lane.config_, lane.rows_))
        ++g;
      if (g == first.size()) {
        if (first.size() == kReferenceGroups) continue;
        first.push_back(i);
        count.push_back(0);
      }
      group[i] = g;
      ++count[g];
    }
    for (std::size_t g = 0; g < first.size(); ++g) {
      if (count[g] < 2) continue;
      const Sim& lane = lanes_[first[g]];
      const auto shared = ReferenceTrajectory<Scalar>::build(lane.config_, lane.rows_);
      if (!shared) continue;
      for (std::size_t i = 0; i < lanes_.size(); ++i)
        if (group[i] == g) lanes_[i].follow_reference(shared);
    }
  }

  std::vector<Sim> lanes_;
  int logged_parameters_ = 0;
  Eigen::Index log_rows_ = 0;
};

/// Lanes a stepping thread gets at least. Handing a share to another thread
/// and waiting for it costs about what a hundred lanes' control period
/// costs: on the 2-core machine 64 vector envs on two threads took 1.33 x
/// the time of one, 128 1.03 x, 256 0.71 x (bench/README.md).
inline constexpr std::size_t kMinLanesPerThread = 128;

/// Where K runs' state is stacked, row i from lane i: rows of 6 (the
/// measured eta and nu and the desired state of the observation, the true
/// eta and nu of the plant), or one value (t, faults, the flags, the steps).
/// A null pointer is left out. What the bindings hand numpy's storage to
/// (BatchSimulator.observation and state, TrackingTask.step_batch's info).
template <typename Scalar>
struct LaneReadout {
  Scalar *t = nullptr, *eta = nullptr, *nu = nullptr, *eta_d = nullptr, *eta_d_dot = nullptr,
         *eta_d_ddot = nullptr, *eta_true = nullptr, *nu_true = nullptr;
  std::uint8_t* faults = nullptr;
  bool *diverged = nullptr, *done = nullptr;
  std::int64_t *steps = nullptr, *planned_steps = nullptr, *steps_left = nullptr;

  /// Row i from a run.
  void read(std::size_t i, const Simulator<Scalar>& s) const noexcept {
    const Observation<Scalar>& o = s.observation();
    const auto put = [i](Scalar* rows, const Vector6<Scalar>& v) noexcept {
      if (rows) Eigen::Map<Vector6<Scalar>>{rows + 6 * i} = v;
    };
    put(eta, o.eta);
    put(nu, o.nu);
    put(eta_d, o.desired.eta_d);
    put(eta_d_dot, o.desired.eta_d_dot);
    put(eta_d_ddot, o.desired.eta_d_ddot);
    put(eta_true, s.eta());
    put(nu_true, s.nu());
    if (t) t[i] = o.t;
    if (faults) faults[i] = s.faults();
    if (diverged) diverged[i] = s.diverged();
    if (done) done[i] = s.done();
    if (steps) steps[i] = static_cast<std::int64_t>(s.steps());
    if (planned_steps) planned_steps[i] = static_cast<std::int64_t>(s.planned_steps());
    if (steps_left) steps_left[i] = static_cast<std::int64_t>(s.planned_steps() - s.steps());
  }

  /// Every lane of a batch.
  void read(const BatchSimulator<Scalar>& batch) const noexcept {
    for (std::size_t i = 0; i < batch.size(); ++i) read(i, batch.lane(i));
  }
};

/// share(begin, end) on contiguous shares of the k lanes [0, k) over
/// `threads` threads (0: one per hardware thread), never fewer than
/// `min_lanes` lanes a thread (one thread below that; a period of a lane is
/// microseconds, a whole run milliseconds); `share` must not throw. With a
/// `pool` that is free and large enough the shares run on its threads;
/// otherwise threads are started for the call, so it allocates
/// (and may throw std::bad_alloc before any share has run): a host's batch
/// call, not a control loop's step. A thread the system refuses leaves its
/// share to the calling thread.
template <typename Share>
void split_lanes(std::size_t k, unsigned threads, WorkerPool* pool, Share&& share,
                 std::size_t min_lanes = kMinLanesPerThread) {
  const std::size_t most = k / std::max<std::size_t>(1, min_lanes);
  // One share: no thread, and no hardware_concurrency() either (it reads
  // /sys at every call, 2.6 us of a one-env vector step of 13 us).
  if (most <= 1) return share(0, k);
  std::size_t n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  n = std::max<std::size_t>(1, std::min(n, most));
  auto part = [&](std::size_t t) noexcept { share(k * t / n, k * (t + 1) / n); };
  if (n == 1) return part(0);
  auto pooled = [&](unsigned t) noexcept { part(t); };
  if (pool && pool->run(static_cast<unsigned>(n), pooled)) return;
  std::vector<std::thread> workers;
  workers.reserve(n - 1);
  std::size_t started = 1;
  try {
    for (; started < n; ++started) workers.emplace_back(part, started);
  } catch (const std::system_error&) {
  }
  for (std::size_t t = started; t < n; ++t) part(t);
  part(0);
  for (std::thread& w : workers) w.join();
}

/// BatchSimulator::step with its lanes split over threads by split_lanes:
/// the same results as step().
template <typename Scalar>
void step_threaded(BatchSimulator<Scalar>& batch, unsigned threads, const Scalar* tau, const bool* mask,
                   std::uint8_t* statuses,
                   const std::common_type_t<Scalar>* parameters = nullptr,  // not deduced: nullptr
                   WorkerPool* pool = nullptr) {
  split_lanes(batch.size(), threads, pool, [&](std::size_t begin, std::size_t end) noexcept {
    batch.step_lanes(begin, end, tau, mask, statuses, parameters);
  });
}

namespace detail {

template <typename List>
struct VariantOf;
template <typename... Ts>
struct VariantOf<TypeList<Ts...>> {
  using type = std::variant<Ts...>;
};

}  // namespace detail

/// Any built-in controller in Scalar (the list of built_in_controllers.hpp).
template <typename Scalar>
using AnyBuiltInController = typename detail::VariantOf<BuiltInControllers<Scalar>>::type;

/// How run_batch runs: its threads (0: one per hardware thread, never more
/// than the lanes) and, with metrics_only, per lane the start of the metrics
/// window (RunSums::after) instead of the rows.
struct BatchOptions {
  unsigned threads = 0;
  bool metrics_only = false;
  std::vector<double> after;  ///< one per lane, with metrics_only
};

/// Rows a metrics-only lane holds between two accumulations.
inline constexpr Eigen::Index kMetricsWindowRows = 64;

/// The lanes of a batch with their controllers, run to the end.
template <typename Scalar, typename Controller>
class BatchRun {
 public:
  BatchRun(BatchSimulator<Scalar>& batch, std::vector<Controller>& controllers,
           const BatchOptions& options)
      : batch_(batch), controllers_(controllers), options_(options) {
    parameters_.resize(batch.size());
    tau_.resize(batch.size());
    if (options.metrics_only) sums_.resize(batch.size());
    for (std::size_t i = 0; i < sums_.size(); ++i) sums_[i].after = options.after[i];
  }

  /// Runs the lanes in [begin, end) to their ends, kPlantBlockWidth lanes
  /// in lockstep (their plants in SIMD lanes) before the next block: a
  /// block's controllers and plants stay in cache.
  void run(std::size_t begin, std::size_t end) noexcept {
    for (std::size_t g0 = begin; g0 < end; g0 += kPlantBlockWidth) {
      const std::size_t g1 = std::min(end, g0 + kPlantBlockWidth);
      const auto start = [this](std::size_t i, Simulator<Scalar>& sim) noexcept {
        if (sim.done()) return false;
        return std::visit(
            [&](auto& c) noexcept {
              const Observation<Scalar>& o = sim.observation();
              const Status cs = c.step(o.eta, o.nu, o.desired, tau_[i]);
              return sim.begin_period(tau_[i], controller_report<Scalar>(c, cs, parameters_[i])) ==
                     Status::ok;
            },
            controllers_[i]);
      };
      const auto finish = [this](std::size_t i, Simulator<Scalar>& sim, Status) noexcept {
        if (options_.metrics_only && (sim.log_full() || sim.done())) {
          sums_[i].add(sim.log(), sim.steps() - sim.logged_from());
          sim.discard();
        }
      };
      while (batch_.step_blocks(g0, g1, start, finish) > 0) {
      }
    }
  }

  std::vector<RunSums>& sums() noexcept { return sums_; }

  /// Moves each lane's rows into results[i] (the lanes are empty afterwards).
  void release(std::vector<SimulationResult<Scalar>>& results) {
    results.resize(batch_.size());
    for (std::size_t i = 0; i < batch_.size(); ++i) batch_.lane_mut(i).release_result(results[i]);
  }

 private:
  BatchSimulator<Scalar>& batch_;
  std::vector<Controller>& controllers_;
  const BatchOptions& options_;
  std::vector<Eigen::Matrix<Scalar, 1, kMaxLoggedParameters>> parameters_;
  std::vector<Vector6<Scalar>> tau_;  ///< each lane's force of this period
  std::vector<RunSums> sums_;
};

/// Runs K closed loops, lane i the vehicle, controller and configuration i
/// (each controller as given, left in its final state), over
/// options.threads threads. The full rows come back in `results` (or, with
/// metrics_only, the metric sums in `sums`, no rows kept). A bad
/// configuration comes back as the ValidationError before any step, with
/// `failed_lane` set; the outputs are then untouched. `Controller` is a
/// std::variant of controller types (AnyBuiltInController).
template <typename Scalar, typename Controller>
ValidationError run_batch(const std::vector<Vehicle<Scalar>>& vehicles,
                          std::vector<Controller>& controllers,
                          const std::vector<SimulationConfig<Scalar>>& configs,
                          const BatchOptions& options, std::vector<SimulationResult<Scalar>>* results,
                          std::vector<RunSums>* sums, std::size_t* failed_lane = nullptr) {
  const std::size_t k = vehicles.size();
  if (controllers.size() != k)
    return detail::invalid("controllers", -1, static_cast<double>(controllers.size()),
                           "one controller per vehicle");
  if (options.metrics_only && options.after.size() != k)
    return detail::invalid("after", -1, static_cast<double>(options.after.size()),
                           "one window start per lane with metrics_only");
  for (std::size_t i = 0; i < options.after.size(); ++i)
    if (!std::isfinite(options.after[i]))
      return detail::invalid("after", static_cast<int>(i), options.after[i], "a finite time [s]");
  std::vector<int> logged(k);
  for (std::size_t i = 0; i < k; ++i)
    logged[i] = std::visit(
        [](const auto& c) { return std::decay_t<decltype(c)>::kLoggedParameters; }, controllers[i]);
  BatchSimulator<Scalar> batch;
  if (auto e = BatchSimulator<Scalar>::create_lanes(
          vehicles, configs, batch, logged, options.metrics_only ? kMetricsWindowRows : 0,
          failed_lane))
    return e;
  BatchRun<Scalar, Controller> run(batch, controllers, options);
  // Contiguous shares: the lanes of a share sit together in memory. A whole
  // run is worth a thread of its own.
  split_lanes(
      k, options.threads, nullptr,
      [&run](std::size_t begin, std::size_t end) noexcept { run.run(begin, end); }, 1);
  if (options.metrics_only) {
    if (sums) *sums = std::move(run.sums());
  } else if (results) {
    run.release(*results);
  }
  return {};
}

}  // namespace neurov
