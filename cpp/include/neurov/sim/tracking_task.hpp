// The tracking task of the Gymnasium environments (python/neurov/gym/, the
// formulas in docs/gymnasium.md), step by step over K rows at once: the
// normalised action's body force, the 26-number observation, the reward and
// the episode's end. The single environment (K = 1) and the vector one (K
// lanes of a BatchSimulator) both compute them here, so lane i of the vector
// env is the single env to the bit, and a step pays no per-row Python.
//
// Free functions over caller storage, row-major (K, width) blocks: no
// allocation, noexcept. The constants are a TrackingTaskConfig, validated
// once by TrackingTask::create, which also derives what every step reads
// (the observation's bounds, the box's centre and half-widths).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <utility>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/model/kinematics.hpp"

namespace neurov {

/// Entries of one observation: the pose error (position in the body frame,
/// angles wrapped) 6, the measured nu 6, the desired velocity and
/// acceleration in the body frame 6 + 6, the measured roll and pitch 2.
inline constexpr int kTrackingObservationSize = 26;

/// The task's constants (docs/gymnasium.md, "Reward" and "Observation").
template <typename Scalar>
struct TrackingTaskConfig {
  using VectorX = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  using Allocation = Eigen::Matrix<Scalar, 6, Eigen::Dynamic>;

  Scalar position_weight = Scalar(1);   ///< reward weight of |p - p_d|^2 [1/m^2]
  Scalar attitude_weight = Scalar(1);   ///< of |wrap(Theta - Theta_d)|^2 [1/rad^2]
  Scalar effort_weight = Scalar(0.01);  ///< of |a|^2, a the clipped action
  /// The true position must stay in [box_low, box_high] (NED, m).
  Vector3<Scalar> box_low = Vector3<Scalar>::Constant(Scalar(-5));
  Vector3<Scalar> box_high = Vector3<Scalar>::Constant(Scalar(5));
  /// Bound of the observation's velocity entries [m/s, rad/s].
  Scalar velocity_bound = Scalar(5);
  /// What action +1 and -1 stand for, per component (> 0 each: N and N m,
  /// or N of thrust per thruster); equal vectors scale both ways alike.
  VectorX action_positive = VectorX::Ones(6);
  VectorX action_negative = VectorX::Ones(6);
  /// tau = thrusters u for thruster commands u (6 x n); no columns: the
  /// action's components are tau's own (n = 6).
  Allocation thrusters;
  /// A non-finite measurement (a sensor dropout's NaN) reads 0.
  bool dropouts_read_zero = false;
};

/// The task's fields; validate() below checks them.
template <typename Scalar>
auto config_fields(const TrackingTaskConfig<Scalar>*) noexcept {
  using C = TrackingTaskConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("position_weight", &C::position_weight, "1/m^2", Check::non_negative,
                    "Reward weight of |p - p_d|^2"),
      field_spec<C>("attitude_weight", &C::attitude_weight, "1/rad^2", Check::non_negative,
                    "Reward weight of |wrap(Theta - Theta_d)|^2"),
      field_spec<C>("effort_weight", &C::effort_weight, "", Check::non_negative,
                    "Reward weight of |a|^2 (a the clipped action)"),
      field_spec<C>("box_low", &C::box_low, "m", Check::finite,
                    "The bounding box's low corner (NED)"),
      field_spec<C>("box_high", &C::box_high, "m", Check::none, "Its high corner (> box_low)"),
      field_spec<C>("velocity_bound", &C::velocity_bound, "m/s, rad/s", Check::positive,
                    "Bound of the observation's velocity entries"),
      field_spec<C>("action_positive", &C::action_positive, "", Check::positive,
                    "What action +1 stands for per component (n,): N and N m, or N of thrust"),
      field_spec<C>("action_negative", &C::action_negative, "", Check::positive,
                    "The magnitude action -1 stands for per component (n,)"),
      field_spec<C>("thrusters", &C::thrusters, "", Check::finite,
                    "tau = thrusters u for thruster commands u, (6, n); (6, 0): the action is "
                    "tau (n = 6)"),
      field_spec<C>("dropouts_read_zero", &C::dropouts_read_zero,
                    "A non-finite measurement (a sensor dropout's NaN) reads 0 in the "
                    "observation"));
}

template <typename Scalar>
inline ValidationError validate(const TrackingTaskConfig<Scalar>& c) noexcept {
  using detail::invalid;
  if (auto e = detail::check_non_negative_scalar("position_weight", c.position_weight)) return e;
  if (auto e = detail::check_non_negative_scalar("attitude_weight", c.attitude_weight)) return e;
  if (auto e = detail::check_non_negative_scalar("effort_weight", c.effort_weight)) return e;
  if (auto e = detail::check_finite("box_low", c.box_low)) return e;
  for (int i = 0; i < 3; ++i)
    if (!(std::isfinite(c.box_high(i)) && c.box_high(i) > c.box_low(i)))
      return invalid("box_high", i, static_cast<double>(c.box_high(i)), "> box_low and finite");
  if (auto e = detail::check_positive_scalar("velocity_bound", c.velocity_bound)) return e;
  const auto n = c.action_positive.size();
  if (n < 1) return invalid("action_positive", -1, 0.0, "at least one component");
  if (auto e = detail::check_positive("action_positive", c.action_positive)) return e;
  if (c.action_negative.size() != n)
    return invalid("action_negative", -1, static_cast<double>(c.action_negative.size()),
                   "as many components as action_positive");
  if (auto e = detail::check_positive("action_negative", c.action_negative)) return e;
  if (c.thrusters.cols() == 0 && n != 6)
    return invalid("action_positive", -1, static_cast<double>(n),
                   "6 components (tau) without a thruster matrix");
  if (c.thrusters.cols() != 0 && c.thrusters.cols() != n)
    return invalid("thrusters", -1, static_cast<double>(c.thrusters.cols()),
                   "one column per action component");
  return detail::check_finite("thrusters", c.thrusters);
}

/// A validated configuration with what every step reads of it.
template <typename Scalar>
class TrackingTask {
 public:
  using Config = TrackingTaskConfig<Scalar>;

  /// `out` made from `config`; on failure `out` is untouched.
  static ValidationError create(const Config& config, TrackingTask& out) {
    if (auto e = validate(config)) return e;
    TrackingTask t;
    t.config_ = config;
    t.symmetric_ = config.action_positive == config.action_negative;
    // The box as centre and half-widths: |p - centre| <= half is the test
    // (NaN fails it, so a non-finite position is outside).
    t.centre_ = (config.box_low + config.box_high) / Scalar(2);
    t.half_ = (config.box_high - config.box_low) / Scalar(2);
    const Vector3<Scalar> d = config.box_high - config.box_low;
    t.reach_ = std::sqrt(d(0) * d(0) + d(1) * d(1) + d(2) * d(2));
    t.termination_cost_ = config.position_weight * t.reach_ * t.reach_;
    const Scalar pi = Scalar(3.14159265358979323846);
    for (int i = 0; i < kTrackingObservationSize; ++i) {
      const Scalar high = i < 3 ? t.reach_ : i < 6 || i >= 24 ? pi : config.velocity_bound;
      t.high_[static_cast<std::size_t>(i)] = static_cast<float>(high);
    }
    out = std::move(t);
    return {};
  }

  const Config& config() const noexcept { return config_; }
  /// n, the components of one action.
  Eigen::Index action_size() const noexcept { return config_.action_positive.size(); }
  /// The box's diagonal |box_high - box_low| [m]: the bound of the
  /// observation's position entries.
  Scalar reach() const noexcept { return reach_; }
  /// What ending early costs per step not simulated: position_weight reach^2.
  Scalar termination_cost() const noexcept { return termination_cost_; }
  /// The observation's bounds: entry i lies in [-high[i], high[i]].
  const std::array<float, kTrackingObservationSize>& observation_high() const noexcept { return high_; }
  bool symmetric() const noexcept { return symmetric_; }
  const Vector3<Scalar>& box_centre() const noexcept { return centre_; }
  const Vector3<Scalar>& box_half() const noexcept { return half_; }

 private:
  Config config_;
  bool symmetric_ = true;
  Vector3<Scalar> centre_ = Vector3<Scalar>::Zero(), half_ = Vector3<Scalar>::Zero();
  Scalar reach_ = Scalar(0), termination_cost_ = Scalar(0);
  std::array<float, kTrackingObservationSize> high_{};
};

/// The angle in [-pi, pi]: the nearest multiple of 2 pi taken off (a tie
/// rounds to the even multiple, as numpy's rint).
template <typename Scalar>
inline Scalar wrap_angle(Scalar angle) noexcept {
  const Scalar two_pi = Scalar(6.28318530717958647692);
  return angle - std::nearbyint(angle / two_pi) * two_pi;
}

/// The first of K rows of n actions holding a non-finite entry, or -1 when
/// all are finite: then `out` (may be `actions`) holds them clipped to
/// [-1, 1] and clipped[i] says whether row i needed it. Nothing is written
/// for a non-finite row.
template <typename Scalar>
inline std::ptrdiff_t clip_actions(std::size_t k, Eigen::Index n, const Scalar* actions, Scalar* out,
                                   bool* clipped) noexcept {
  const std::size_t size = k * static_cast<std::size_t>(n);
  for (std::size_t j = 0; j < size; ++j)
    if (!std::isfinite(actions[j])) return static_cast<std::ptrdiff_t>(j / static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < k; ++i) {
    bool any = false;
    for (Eigen::Index c = 0; c < n; ++c) {
      const std::size_t j = i * static_cast<std::size_t>(n) + static_cast<std::size_t>(c);
      const Scalar a = actions[j];
      any = any || a > Scalar(1) || a < Scalar(-1);
      out[j] = a > Scalar(1) ? Scalar(1) : a < Scalar(-1) ? Scalar(-1) : a;
    }
    clipped[i] = any;
  }
  return -1;
}

/// The body forces tau (K x 6) of K clipped actions (K x n): u = a scaled by
/// action_positive where a >= 0 and action_negative where a < 0, then
/// tau = thrusters u (or u itself).
template <typename Scalar>
inline void tracking_forces(const TrackingTask<Scalar>& task, std::size_t k, const Scalar* actions,
                            Scalar* tau) noexcept {
  const auto& c = task.config();
  const Eigen::Index n = task.action_size();
  // u_j: component j of action a scaled by its limit on that side.
  const auto scaled = [&](const Scalar* a, Eigen::Index j) noexcept {
    return a[j] * (task.symmetric() || a[j] >= Scalar(0) ? c.action_positive(j) : c.action_negative(j));
  };
  for (std::size_t i = 0; i < k; ++i) {
    const Scalar* a = actions + i * static_cast<std::size_t>(n);
    Scalar* f = tau + 6 * i;
    if (c.thrusters.cols() == 0) {
      for (Eigen::Index j = 0; j < 6; ++j) f[j] = scaled(a, j);
      continue;
    }
    for (Eigen::Index r = 0; r < 6; ++r) f[r] = Scalar(0);
    for (Eigen::Index j = 0; j < n; ++j) {
      const Scalar u = scaled(a, j);
      for (Eigen::Index r = 0; r < 6; ++r) f[r] += c.thrusters(r, j) * u;
    }
  }
}

/// What one step of K runs is scored from, each a row-major block: the
/// measured eta and nu and the desired state (K x 6 each), the true pose
/// after the step (K x 6), the clipped actions (K x n), and per row whether
/// the plant diverged, whether its run is done and how many steps of the
/// run were not simulated.
template <typename Scalar>
struct TrackingRows {
  const Scalar* eta = nullptr;
  const Scalar* nu = nullptr;
  const Scalar* eta_d = nullptr;
  const Scalar* eta_d_dot = nullptr;
  const Scalar* eta_d_ddot = nullptr;
  const Scalar* eta_true = nullptr;
  const Scalar* actions = nullptr;
  const bool* diverged = nullptr;
  const bool* done = nullptr;
  const std::int64_t* steps_left = nullptr;

  /// The rows from row `first` on (a thread's share), actions of
  /// `action_size` a row.
  TrackingRows from(std::size_t first, Eigen::Index action_size) const noexcept {
    TrackingRows r = *this;
    for (const Scalar** p : {&r.eta, &r.nu, &r.eta_d, &r.eta_d_dot, &r.eta_d_ddot, &r.eta_true})
      if (*p) *p += 6 * first;
    if (r.actions) r.actions += first * static_cast<std::size_t>(action_size);
    if (r.diverged) r.diverged += first;
    if (r.done) r.done += first;
    if (r.steps_left) r.steps_left += first;
    return r;
  }
};

/// Where the scores go, (K,) each.
template <typename Scalar>
struct TrackingScores {
  Scalar* reward = nullptr;
  bool* terminated = nullptr;  ///< outside the box, or the plant diverged
  bool* truncated = nullptr;   ///< the run is done and not terminated
  bool* outside = nullptr;     ///< the true position left the box (NaN: left)

  /// The scores from row `first` on.
  TrackingScores from(std::size_t first) const noexcept {
    return {reward + first, terminated + first, truncated + first, outside + first};
  }
};

/// The observations (K x 26, float, clipped to +-observation_high) of the
/// measured eta, nu and the desired state of `rows` (the other fields are
/// not read): J(eta)^-1 from the measured pose turns the position error and
/// the desired rates into the body frame.
template <typename Scalar>
inline void tracking_observation(const TrackingTask<Scalar>& task, std::size_t k, const TrackingRows<Scalar>& rows,
                                 float* observation) noexcept {
  using Vec6 = Vector6<Scalar>;
  const bool zero_dropouts = task.config().dropouts_read_zero;
  const auto& high = task.observation_high();
  for (std::size_t i = 0; i < k; ++i) {
    Vec6 eta = Eigen::Map<const Vec6>(rows.eta + 6 * i);
    Vec6 nu = Eigen::Map<const Vec6>(rows.nu + 6 * i);
    if (zero_dropouts)
      for (int j = 0; j < 6; ++j) {
        if (!std::isfinite(eta(j))) eta(j) = Scalar(0);
        if (!std::isfinite(nu(j))) nu(j) = Scalar(0);
      }
    const Eigen::Map<const Vec6> eta_d(rows.eta_d + 6 * i);
    const auto kin = EulerKinematics<Scalar>::from_pose(eta);
    const Vec6 error = eta - eta_d;
    const Vec6 rate = kin.apply_inverse(Eigen::Map<const Vec6>(rows.eta_d_dot + 6 * i));
    const Vec6 accel = kin.apply_inverse(Eigen::Map<const Vec6>(rows.eta_d_ddot + 6 * i));
    std::array<Scalar, kTrackingObservationSize> o;
    const Vector3<Scalar> position = kin.R.transpose() * error.template head<3>();
    for (int j = 0; j < 3; ++j) {
      o[static_cast<std::size_t>(j)] = position(j);
      o[static_cast<std::size_t>(3 + j)] = wrap_angle(error(3 + j));
    }
    for (int j = 0; j < 6; ++j) {
      o[static_cast<std::size_t>(6 + j)] = nu(j);
      o[static_cast<std::size_t>(12 + j)] = rate(j);
      o[static_cast<std::size_t>(18 + j)] = accel(j);
    }
    o[24] = eta(3);
    o[25] = eta(4);
    float* out = observation + static_cast<std::size_t>(kTrackingObservationSize) * i;
    for (std::size_t j = 0; j < o.size(); ++j) {
      // Clipped before the cast to float (the same as after it: rounding is
      // monotonic and the bound a float), so no out-of-range cast; NaN stays.
      const Scalar h = static_cast<Scalar>(high[j]);
      const Scalar v = o[j] > h ? h : o[j] < -h ? -h : o[j];
      out[j] = static_cast<float>(v);
    }
  }
}

/// The reward, termination and truncation of K rows after a step:
/// reward = -(position_weight |p - p_d|^2 + attitude_weight
/// |wrap(Theta - Theta_d)|^2 + effort_weight |a|^2) of the true pose and the
/// clipped action; a terminated row also pays termination_cost for each
/// step not simulated, so that ending early never pays.
template <typename Scalar>
inline void tracking_score(const TrackingTask<Scalar>& task, std::size_t k, const TrackingRows<Scalar>& rows,
                           const TrackingScores<Scalar>& out) noexcept {
  const auto& c = task.config();
  const Eigen::Index n = task.action_size();
  const auto& centre = task.box_centre();
  const auto& half = task.box_half();
  for (std::size_t i = 0; i < k; ++i) {
    const Scalar* eta = rows.eta_true + 6 * i;
    const Scalar* eta_d = rows.eta_d + 6 * i;
    const Scalar* a = rows.actions + i * static_cast<std::size_t>(n);
    Scalar position = Scalar(0), attitude = Scalar(0), effort = Scalar(0);
    bool outside = false;
    for (int j = 0; j < 3; ++j) {
      const Scalar dp = eta[j] - eta_d[j];
      const Scalar da = wrap_angle(eta[3 + j] - eta_d[3 + j]);
      position += dp * dp;
      attitude += da * da;
      outside = outside || !(std::abs(eta[j] - centre(j)) <= half(j));
    }
    for (Eigen::Index j = 0; j < n; ++j) effort += a[j] * a[j];
    Scalar reward = -(c.position_weight * position + c.attitude_weight * attitude + c.effort_weight * effort);
    const bool terminated = outside || rows.diverged[i];
    if (terminated) reward -= task.termination_cost() * static_cast<Scalar>(rows.steps_left[i]);
    out.reward[i] = reward;
    out.terminated[i] = terminated;
    out.truncated[i] = rows.done[i] && !terminated;
    out.outside[i] = outside;
  }
}

/// tracking_observation and tracking_score of the same K rows.
template <typename Scalar>
inline void tracking_outcome(const TrackingTask<Scalar>& task, std::size_t k, const TrackingRows<Scalar>& rows,
                             float* observation, const TrackingScores<Scalar>& scores) noexcept {
  tracking_observation(task, k, rows, observation);
  tracking_score(task, k, rows, scores);
}

}  // namespace neurov
