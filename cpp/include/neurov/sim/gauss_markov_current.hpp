// A three-dimensional ocean current whose speed and direction wander as
// first-order Gauss-Markov processes (Fossen 2011, Handbook of Marine Craft
// Hydrodynamics and Motion Control, section 8.3):
//   V_c = V_mean + x_V,      x_V' = -x_V / T + w,
//   psi_c = psi_mean + x_psi, gamma_c = gamma_mean + x_gamma (likewise),
// discretised exactly, x_{k+1} = a x_k + sqrt(1 - a^2) sigma w_k with
// a = exp(-h / T) and w_k standard normal, so the process has the stationary
// standard deviation sigma and the autocorrelation exp(-|tau| / T) whatever
// the step h. The speed given out is clipped to [speed_min, speed_max]; the
// process state is not, so it keeps its statistics. The process is not
// differentiable: the force of the current's acceleration is neglected.
#pragma once

#include <cmath>
#include <cstdint>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/random.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/sim/random_streams.hpp"

namespace neurov {

/// The fields and units of the scenario file's [current] table with
/// model = "gauss_markov" (angles in degrees, as the file has them).
template <typename Scalar>
struct GaussMarkovCurrentConfig {
  Scalar speed = Scalar(0.5);           ///< mean speed [m/s]
  Scalar speed_std = Scalar(0.1);       ///< stationary standard deviation [m/s]
  Scalar time_constant = Scalar(30);    ///< T of all three processes [s]
  Scalar speed_min = Scalar(0);         ///< lower bound of the speed given out [m/s]
  Scalar speed_max = Scalar(2);         ///< upper bound of the speed given out [m/s]
  Scalar direction = Scalar(0);         ///< mean direction the current flows toward [deg from north]
  Scalar direction_std = Scalar(0);     ///< [deg]
  /// Mean angle of the flow below the horizontal plane [deg], positive when
  /// it flows downward (NED z is down).
  Scalar vertical_angle = Scalar(0);
  Scalar vertical_angle_std = Scalar(0);  ///< [deg]
};

template <typename Scalar>
auto config_fields(const GaussMarkovCurrentConfig<Scalar>*) noexcept {
  using C = GaussMarkovCurrentConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("speed", &C::speed, "m/s", Check::none, "Mean speed, within [speed_min, speed_max]"),
      field_spec<C>("speed_std", &C::speed_std, "m/s", Check::non_negative, "Stationary standard deviation"),
      field_spec<C>("time_constant", &C::time_constant, "s", Check::positive, "Of all three processes"),
      field_spec<C>("speed_min", &C::speed_min, "m/s", Check::non_negative,
                    "Lower bound of the speed given out"),
      field_spec<C>("speed_max", &C::speed_max, "m/s", Check::none,
                    "Upper bound of the speed given out, >= speed_min"),
      field_spec<C>("direction", &C::direction, "deg from north", Check::finite,
                    "Mean direction the current flows toward"),
      field_spec<C>("direction_std", &C::direction_std, "deg", Check::non_negative,
                    "Standard deviation of the direction"),
      field_spec<C>("vertical_angle", &C::vertical_angle, "deg", Check::none,
                    "Mean angle below the horizontal plane, positive flowing down, within "
                    "[-90, 90]"),
      field_spec<C>("vertical_angle_std", &C::vertical_angle_std, "deg", Check::non_negative,
                    "Standard deviation of the vertical angle"));
}

/// Checks a configuration; the error names the field. Speeds are magnitudes,
/// so the bounds are >= 0, and the mean lies within them.
template <typename Scalar>
inline ValidationError validate(const GaussMarkovCurrentConfig<Scalar>& c) noexcept {
  using detail::invalid;
  const auto d = [](Scalar v) { return static_cast<double>(v); };
  if (auto e = detail::check_positive_scalar("time_constant", d(c.time_constant))) return e;
  if (auto e = detail::check_non_negative_scalar("speed_std", d(c.speed_std))) return e;
  if (auto e = detail::check_non_negative_scalar("direction_std", d(c.direction_std))) return e;
  if (auto e = detail::check_non_negative_scalar("vertical_angle_std", d(c.vertical_angle_std)))
    return e;
  if (auto e = detail::check_non_negative_scalar("speed_min", d(c.speed_min))) return e;
  if (!(std::isfinite(d(c.speed_max)) && c.speed_max >= c.speed_min))
    return invalid("speed_max", -1, d(c.speed_max), ">= speed_min and finite");
  if (!(std::isfinite(d(c.speed)) && c.speed >= c.speed_min && c.speed <= c.speed_max))
    return invalid("speed", -1, d(c.speed), "within [speed_min, speed_max]");
  if (!std::isfinite(d(c.direction))) return invalid("direction", -1, d(c.direction), "finite");
  if (!(std::isfinite(d(c.vertical_angle)) && std::abs(d(c.vertical_angle)) <= 90.0))
    return invalid("vertical_angle", -1, d(c.vertical_angle), "within [-90, 90] deg");
  return {};
}

template <typename ScalarT>
class GaussMarkovCurrent {
 public:
  using Scalar = ScalarT;
  using Vec3 = Vector3<Scalar>;

  /// Empty: valid() is false and advance() returns invalid_argument.
  GaussMarkovCurrent() = default;

  /// Validates c and builds `out` from it; `out` is untouched on error. The
  /// numbers come from stream_seed(seed, RandomStream::current), so pass the
  /// scenario's seed. The three processes start from their stationary
  /// distribution, so the statistics hold from t = 0 on.
  static ValidationError create(const GaussMarkovCurrentConfig<Scalar>& c, std::uint64_t seed,
                                GaussMarkovCurrent& out) noexcept {
    if (auto e = validate(c)) return e;
    constexpr double deg = 3.14159265358979323846 / 180.0;
    GaussMarkovCurrent g;
    g.config_ = c;
    g.rng_.reseed(stream_seed(seed, RandomStream::current));
    g.sigma_[0] = static_cast<double>(c.speed_std);
    g.sigma_[1] = static_cast<double>(c.direction_std) * deg;
    g.sigma_[2] = static_cast<double>(c.vertical_angle_std) * deg;
    g.mean_[0] = static_cast<double>(c.speed);
    g.mean_[1] = static_cast<double>(c.direction) * deg;
    g.mean_[2] = static_cast<double>(c.vertical_angle) * deg;
    // A process with sigma = 0 draws no numbers: a current with a fixed
    // direction costs one normal per step.
    for (int i = 0; i < 3; ++i) g.state_[i] = g.sigma_[i] > 0.0 ? g.sigma_[i] * g.rng_.normal() : 0.0;
    g.valid_ = true;
    g.update_velocity();
    out = g;
    return {};
  }

  bool valid() const noexcept { return valid_; }
  const GaussMarkovCurrentConfig<Scalar>& config() const noexcept { return config_; }

  /// Moves the processes on by h seconds (any h > 0: the discretisation is
  /// exact). invalid_argument for h <= 0 or an empty current,
  /// non_finite_input for a NaN or infinite h; the state is unchanged then.
  Status advance(Scalar h) noexcept {
    if (!valid_) return Status::invalid_argument;
    const double hd = static_cast<double>(h);
    if (!std::isfinite(hd)) return Status::non_finite_input;
    if (!(hd > 0.0)) return Status::invalid_argument;
    if (hd != last_h_) {
      const double r = hd / static_cast<double>(config_.time_constant);
      a_ = std::exp(-r);
      b_ = std::sqrt(-std::expm1(-2.0 * r));  // sqrt(1 - a^2) without cancellation
      last_h_ = hd;
    }
    for (int i = 0; i < 3; ++i)
      if (sigma_[i] > 0.0) state_[i] = a_ * state_[i] + b_ * sigma_[i] * rng_.normal();
    update_velocity();
    return Status::ok;
  }

  /// The current's velocity in NED [m/s].
  const Vec3& velocity() const noexcept { return velocity_; }
  /// Speed given out, after the clip to [speed_min, speed_max] [m/s].
  Scalar speed() const noexcept { return speed_; }
  /// Direction the current flows toward [rad from north].
  Scalar direction() const noexcept { return static_cast<Scalar>(mean_[1] + state_[1]); }
  /// Angle of the flow below the horizontal plane [rad].
  Scalar vertical_angle() const noexcept { return static_cast<Scalar>(mean_[2] + state_[2]); }
  /// The unclipped speed process V_mean + x_V [m/s].
  Scalar speed_process() const noexcept { return static_cast<Scalar>(mean_[0] + state_[0]); }

 private:
  void update_velocity() noexcept {
    const double v = std::fmin(std::fmax(mean_[0] + state_[0], static_cast<double>(config_.speed_min)),
                               static_cast<double>(config_.speed_max));
    const double psi = mean_[1] + state_[1], gamma = mean_[2] + state_[2];
    const double horizontal = v * std::cos(gamma);
    speed_ = static_cast<Scalar>(v);
    velocity_ = Vec3(static_cast<Scalar>(horizontal * std::cos(psi)),
                     static_cast<Scalar>(horizontal * std::sin(psi)),
                     static_cast<Scalar>(v * std::sin(gamma)));
  }

  GaussMarkovCurrentConfig<Scalar> config_{};
  NormalRandom rng_{};
  // The processes run in double, so a float build keeps their statistics.
  double mean_[3] = {0, 0, 0};   ///< speed [m/s], direction and vertical angle [rad]
  double sigma_[3] = {0, 0, 0};
  double state_[3] = {0, 0, 0};  ///< x_V, x_psi, x_gamma
  double last_h_ = -1.0, a_ = 0.0, b_ = 0.0;
  Vec3 velocity_ = Vec3::Zero();
  Scalar speed_ = Scalar(0);
  bool valid_ = false;
};

}  // namespace neurov
