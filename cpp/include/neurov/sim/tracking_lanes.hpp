// The tracking task (tracking_task.hpp) over runs: one Simulator (the single
// Gymnasium env) or every lane of a BatchSimulator (the vector env) stepped
// under clipped actions, read into a LaneReadout's storage and scored, so
// that the bindings only convert the arrays. Lane i of a batch step is the
// step of the same run alone, to the bit, whatever the threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "neurov/core/status.hpp"
#include "neurov/sim/batch.hpp"
#include "neurov/sim/simulator.hpp"
#include "neurov/sim/tracking_task.hpp"
#include "neurov/sim/worker_pool.hpp"

namespace neurov {

/// The rows the task observes and scores, viewing what `lanes` writes the
/// runs into (its eta, nu, eta_d, eta_d_dot, eta_d_ddot, eta_true, diverged,
/// done and steps_left), with the clipped actions (nullptr to observe only).
template <typename Scalar>
TrackingRows<Scalar> tracking_rows(const LaneReadout<Scalar>& lanes, const Scalar* actions) noexcept {
  TrackingRows<Scalar> r;
  r.eta = lanes.eta;
  r.nu = lanes.nu;
  r.eta_d = lanes.eta_d;
  r.eta_d_dot = lanes.eta_d_dot;
  r.eta_d_ddot = lanes.eta_d_ddot;
  r.eta_true = lanes.eta_true;
  r.actions = actions;
  r.diverged = lanes.diverged;
  r.done = lanes.done;
  r.steps_left = lanes.steps_left;
  return r;
}

/// The observations (k x 26) of k runs as they stand, run(i) the i-th, each
/// read into row i of `lanes` first.
template <typename Scalar, typename Run>
void tracking_observe(const TrackingTask<Scalar>& task, std::size_t k, Run&& run, const LaneReadout<Scalar>& lanes,
                      float* observations) noexcept {
  for (std::size_t i = 0; i < k; ++i) lanes.read(i, run(i));
  tracking_observation(task, k, tracking_rows<Scalar>(lanes, nullptr), observations);
}

/// One control period of `sim` under one clipped action (action_size()
/// numbers): its force applied, the run read into row 0 of `lane`, observed
/// and scored. Returns the plant's status. The run must be able to step (not
/// done, its log window not full, no logged parameters): the caller checks.
template <typename Scalar>
Status tracking_step(const TrackingTask<Scalar>& task, Simulator<Scalar>& sim, const Scalar* action,
                     const LaneReadout<Scalar>& lane, float* observation,
                     const TrackingScores<Scalar>& score) noexcept {
  Vector6<Scalar> tau;
  tracking_forces(task, 1, action, tau.data());
  const Status plant = sim.step(tau, ControllerReport<Scalar>{});
  lane.read(0, sim);
  tracking_outcome(task, 1, tracking_rows(lane, action), observation, score);
  return plant;
}

/// tracking_step for every lane i of `batch` with mask[i] (mask nullptr:
/// every lane) that is not done, under row i of the K clipped actions
/// (row-major, K x action_size()), the lanes split over `threads` as
/// step_threaded splits them (the same results). statuses[i] is
/// BatchSimulator::step's; every lane is read into row i of `lanes` and
/// observed, and a lane not stepped scores reward 0 and no flag. A batch made
/// with a log window (a vector env's) is read from its observations, never
/// its log: a lane's full window is emptied so that it steps on.
template <typename Scalar>
void tracking_step_batch(const TrackingTask<Scalar>& task, BatchSimulator<Scalar>& batch, const Scalar* actions,
                         const bool* mask, std::uint8_t* statuses, const LaneReadout<Scalar>& lanes,
                         float* observations, const TrackingScores<Scalar>& scores, unsigned threads = 1,
                         WorkerPool* pool = nullptr) {
  const std::size_t k = batch.size();
  const auto n = static_cast<std::size_t>(task.action_size());
  std::vector<Scalar> tau(6 * k);
  const TrackingRows<Scalar> rows = tracking_rows(lanes, actions);
  // Each thread's share of the lanes through the whole step: the rows are
  // independent, so the split changes nothing.
  split_lanes(k, threads, pool, [&](std::size_t b, std::size_t e) noexcept {
    tracking_forces(task, e - b, actions + n * b, tau.data() + 6 * b);
    if (batch.log_rows() > 0)
      for (std::size_t i = b; i < e; ++i)
        if (batch.lane(i).log_full() && !batch.lane(i).done()) batch.discard(i);
    batch.step_lanes(b, e, tau.data(), mask, statuses);
    for (std::size_t i = b; i < e; ++i) lanes.read(i, batch.lane(i));
    tracking_outcome(task, e - b, rows.from(b, task.action_size()),
                     observations + static_cast<std::size_t>(kTrackingObservationSize) * b, scores.from(b));
    for (std::size_t i = b; i < e; ++i)
      if (statuses[i] == kLaneNotStepped) {
        scores.reward[i] = Scalar(0);
        scores.terminated[i] = scores.truncated[i] = scores.outside[i] = false;
      }
  });
}

}  // namespace neurov
