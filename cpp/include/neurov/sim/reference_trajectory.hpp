// The desired states of a run's reference model at every control step,
// computed once and shared by the lanes of a batch whose reference is the
// same. The reference model (control/reference_model.hpp) is open loop: its
// desired state at row k follows from its gains, its start eta0, the command
// r(t) and dt alone, never from the plant, the controller or the noise. Lanes
// that share those and differ in the rest (a Monte-Carlo over perturbed
// plants, a vector environment's episodes) would each integrate the same
// trajectory; a lane that follows a ReferenceTrajectory reads row k
// instead. The rows are made by the same ReferenceModel calls, with the same
// arguments, as a run alone makes (Simulator's observe() and end_period()),
// so a lane that follows one gets its run alone's desired states to the bit.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "neurov/control/desired_state.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/sim/config.hpp"

namespace neurov {

/// Whether runs with configurations a and b of rows_a and rows_b rows have
/// the same reference: the same gains, start, command, period and length.
template <typename Scalar>
bool same_reference(const SimulationConfig<Scalar>& a, Eigen::Index rows_a,
                    const SimulationConfig<Scalar>& b, Eigen::Index rows_b) noexcept {
  const Command<Scalar>& ca = a.command;
  const Command<Scalar>& cb = b.command;
  return rows_a == rows_b && a.dt == b.dt && a.eta0 == b.eta0 && a.lambda_d == b.lambda_d &&
         a.omega == b.omega && ca.linear == cb.linear && ca.times.size() == cb.times.size() &&
         ca.poses.rows() == cb.poses.rows() && ca.times == cb.times && ca.poses == cb.poses;
}

template <typename Scalar>
class ReferenceTrajectory {
 public:
  /// The longest trajectory built (rows): 65,536 rows of a double reference
  /// are 9.5 MB, 3.6 hours at the paper's 0.2 s. A longer run integrates its
  /// own reference.
  static constexpr Eigen::Index kMaxRows = 65536;

  /// The reference of a validated `config` for a run of `rows` rows, or
  /// nullptr when rows > kMaxRows. Allocates: built when a batch is made.
  static std::shared_ptr<const ReferenceTrajectory> build(const SimulationConfig<Scalar>& config,
                                                          Eigen::Index rows) {
    if (rows < 1 || rows > kMaxRows) return nullptr;
    auto out = std::make_shared<ReferenceTrajectory>();
    out->key_.dt = config.dt;
    out->key_.eta0 = config.eta0;
    out->key_.lambda_d = config.lambda_d;
    out->key_.omega = config.omega;
    out->key_.command = config.command;
    out->rows_ = rows;
    // validate() has checked the gains and eta0, so create() succeeds.
    ReferenceModel<Scalar> model;
    ReferenceModel<Scalar>::create(config.lambda_d, config.omega, config.eta0, model);
    // Row rows too: after a run's last period its observation holds the
    // desired state of the step after it.
    out->desired_.resize(static_cast<std::size_t>(rows) + 1);
    out->pitch_limited_.resize(static_cast<std::size_t>(rows) + 1);
    out->desired_[0] = model.desired();
    out->pitch_limited_[0] = model.pitch_limited();
    for (Eigen::Index k = 1; k <= rows; ++k) {
      const auto i = static_cast<std::size_t>(k);
      out->desired_[i] = out->desired_[i - 1];
      model.step(config.command.at(row_time(k - 1, config.dt)), config.dt, out->desired_[i]);
      out->pitch_limited_[i] = model.pitch_limited();
    }
    return out;
  }

  /// t_k as a run computes it (Simulator::observe).
  static Scalar row_time(Eigen::Index k, Scalar dt) noexcept { return static_cast<Scalar>(k) * dt; }

  /// Whether a run of `config` and `rows` rows has this reference.
  bool matches(const SimulationConfig<Scalar>& config, Eigen::Index rows) const noexcept {
    return same_reference(key_, rows_, config, rows);
  }

  /// The desired state after k reference steps (row k's), k in [0, rows].
  const DesiredState<Scalar>& desired(Eigen::Index k) const noexcept {
    return desired_[static_cast<std::size_t>(k)];
  }
  /// ReferenceModel::pitch_limited() after k steps.
  bool pitch_limited(Eigen::Index k) const noexcept {
    return pitch_limited_[static_cast<std::size_t>(k)] != 0;
  }

 private:
  SimulationConfig<Scalar> key_;  ///< only the reference's fields set
  Eigen::Index rows_ = 0;
  std::vector<DesiredState<Scalar>> desired_;
  std::vector<std::uint8_t> pitch_limited_;
};

}  // namespace neurov
