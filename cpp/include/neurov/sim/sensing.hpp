// What stands between the true state and the controller when a run has
// sensors: the four sensor models of sensors.hpp (each optional), sampled at
// every plant substep, and either the EKF of estimation/ekf.hpp fed by their
// readings as they arrive (`ekf`) or the latest reading of each sensor handed
// on as it is (`none`). All of it is held inline: sensing allocates nothing.
//
// `none`: eta = [usbl x, y; depth z (else usbl z); imu attitude], nu = [dvl
// velocity; imu rates (with the gyro bias)], each the last reading delivered
// (the initial state before the first); a component no configured sensor
// measures is the true one. `ekf` needs the IMU and the USBL (attitude,
// rates and position; the DVL and the depth sensor are optional) and hands on
// the filter's eta and nu. Angles are handed on continuous: each is the
// branch of the wrapped reading or estimate nearest the angle given before,
// so a heading past pi does not jump by 2 pi in the controller's error.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include <Eigen/Core>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/estimation/ekf.hpp"
#include "neurov/sim/sensors.hpp"

namespace neurov {

/// The sensors of a run; none configured: ideal sensing.
template <typename Scalar>
struct SensorsConfig {
  std::optional<UsblConfig<Scalar>> usbl;
  std::optional<DvlConfig<Scalar>> dvl;
  std::optional<DepthConfig<Scalar>> depth;
  std::optional<ImuConfig<Scalar>> imu;

  bool any() const noexcept { return usbl || dvl || depth || imu; }
};

template <typename Scalar>
auto config_fields(const SensorsConfig<Scalar>*) noexcept {
  using C = SensorsConfig<Scalar>;
  return std::make_tuple(field_spec<C>("usbl", &C::usbl, "A UsblConfig, or None."),
                         field_spec<C>("dvl", &C::dvl, "A DvlConfig, or None."),
                         field_spec<C>("depth", &C::depth, "A DepthConfig, or None."),
                         field_spec<C>("imu", &C::imu, "An ImuConfig, or None."));
}

/// What the controller is given from the sensors: the raw readings or the EKF's estimate.
enum class EstimatorType : std::uint8_t { none = 0, ekf = 1 };

/// The estimator of a run. The EKF's measurement noises are the sensors'
/// own (a noise below kFilterNoiseFloor is taken as that floor, so that an
/// ideal sensor does not make the innovation covariance singular); its
/// process noise and initial uncertainty are set here.
template <typename Scalar>
struct EstimatorConfig {
  using StateVector = Eigen::Matrix<Scalar, kEkfStates, 1>;
  EstimatorType type = EstimatorType::none;
  /// sqrt of the PSD of the velocities' random walk [m/s^2/sqrt(Hz)], >= 0.
  Scalar linear_acceleration_noise = Scalar(0.05);
  /// sqrt of the PSD of the angular rates' random walk [rad/s^2/sqrt(Hz)], >= 0.
  Scalar angular_acceleration_noise = Scalar(0.02);
  /// Standard deviations of the initial estimate, > 0: position [m], angles
  /// [rad], body velocity [m/s], rates [rad/s], gyro bias [rad/s].
  StateVector initial_std = default_initial_std();

  static StateVector default_initial_std() noexcept {
    StateVector s;
    s << Scalar(1), Scalar(1), Scalar(1), Scalar(0.05), Scalar(0.05), Scalar(0.05), Scalar(0.1),
        Scalar(0.1), Scalar(0.1), Scalar(0.05), Scalar(0.05), Scalar(0.05), Scalar(0.01),
        Scalar(0.01), Scalar(0.01);
    return s;
  }
};

template <typename Scalar>
auto config_fields(const EstimatorConfig<Scalar>*) noexcept {
  using C = EstimatorConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("type", &C::type, "An EstimatorType."),
      field_spec<C>("linear_acceleration_noise", &C::linear_acceleration_noise, "m/s^2/sqrt(Hz)",
                    Check::non_negative, "sqrt of the PSD of the velocities' random walk"),
      field_spec<C>("angular_acceleration_noise", &C::angular_acceleration_noise,
                    "rad/s^2/sqrt(Hz)", Check::non_negative,
                    "sqrt of the PSD of the rates' random walk"),
      field_spec<C>("initial_std", &C::initial_std, "", Check::positive,
                    "Standard deviations of the initial estimate (15,): position, angles, body "
                    "velocity, rates, gyro bias"));
}

/// The smallest measurement noise the EKF assumes [the sensor's unit].
inline constexpr double kFilterNoiseFloor = 1e-4;

template <typename Scalar>
class Sensing {
 public:
  using Vec3 = Vector3<Scalar>;
  using Vec6 = Vector6<Scalar>;

  /// The filter a run's EKF uses: the estimator's process noise and initial
  /// uncertainty, the sensors' noises (a sensor not configured: 1, unused).
  static EkfConfig<Scalar> filter_config(const SensorsConfig<Scalar>& s,
                                         const EstimatorConfig<Scalar>& e) noexcept {
    auto noise = [](Scalar v) { return std::fmax(v, static_cast<Scalar>(kFilterNoiseFloor)); };
    EkfConfig<Scalar> c;
    c.linear_acceleration_noise = e.linear_acceleration_noise;
    c.angular_acceleration_noise = e.angular_acceleration_noise;
    c.initial_std = e.initial_std;
    c.attitude_noise = s.imu ? noise(s.imu->attitude_noise) : Scalar(1);
    c.gyro_noise = s.imu ? noise(s.imu->gyro_noise) : Scalar(1);
    c.gyro_bias_walk = s.imu ? s.imu->gyro_bias_walk : Scalar(0);
    c.dvl_noise = s.dvl ? noise(s.dvl->noise) : Scalar(1);
    c.depth_noise = s.depth ? noise(s.depth->noise) : Scalar(1);
    c.position_noise = s.usbl ? noise(s.usbl->noise) : Scalar(1);
    return c;
  }

  /// Checks the sensors, the estimator and that the estimator has the
  /// sensors it needs; the error names the TOML key (sensors.usbl.rate, ...).
  static ValidationError validate(const SensorsConfig<Scalar>& s,
                                  const EstimatorConfig<Scalar>& e) noexcept {
    Sensing probe;
    return probe.build(s, e, 0);
  }

  /// Validates and builds the sensing of a run, seeded by `seed`; `out` is
  /// untouched on error.
  static ValidationError create(const SensorsConfig<Scalar>& s, const EstimatorConfig<Scalar>& e,
                                std::uint64_t seed, Sensing& out) noexcept {
    Sensing next;
    if (auto err = next.build(s, e, seed)) return err;
    out = next;
    return {};
  }

  bool active() const noexcept { return active_; }

  /// Back to the start of a run at time 0 from (eta0, nu0), the sensors'
  /// noise drawn from `seed`'s streams; takes the samples due at time 0.
  void reset(std::uint64_t seed, const Vec6& eta0, const Vec6& nu0) noexcept {
    if (!active_) return;
    (void)build(s_, e_, seed);
    if (e_.type == EstimatorType::ekf)
      (void)Ekf<Scalar>::create(Sensing::filter_config(s_, e_), eta0, nu0, ekf_);
    eta_ = eta0;
    nu_ = nu0;
    given_eta_ = eta0;
    filter_time_ = 0.0;
    sense(0.0, eta0, nu0);
  }

  /// The sensors sample the true state at `time` (seconds from the start,
  /// non-decreasing); the readings delivered by then are taken in (the
  /// filter first predicted to `time`). A sample of a non-finite state is
  /// not taken; a rejected filter step leaves the filter as it was.
  void sense(double time, const Vec6& eta, const Vec6& nu) noexcept {
    if (!active_) return;
    const bool ekf = e_.type == EstimatorType::ekf;
    if (ekf && time > filter_time_) {
      (void)ekf_.predict(static_cast<Scalar>(time - filter_time_));
      filter_time_ = time;
    }
    if (s_.imu) {
      (void)imu_.sample(time, eta, nu);
      typename ImuSensor<Scalar>::Reading m;
      while (imu_.read(time, m)) {
        if (ekf) {
          (void)ekf_.update_attitude(m.value.template head<3>());
          (void)ekf_.update_gyro(m.value.template tail<3>());
        }
        eta_.template tail<3>() = m.value.template head<3>();
        nu_.template tail<3>() = m.value.template tail<3>();
      }
    }
    if (s_.dvl) {
      (void)dvl_.sample(time, eta, nu);
      typename DvlSensor<Scalar>::Reading m;
      while (dvl_.read(time, m)) {
        if (!m.valid) continue;
        if (ekf) (void)ekf_.update_dvl(m.value);
        nu_.template head<3>() = m.value;
      }
    }
    if (s_.depth) {
      (void)depth_.sample(time, eta, nu);
      typename DepthSensor<Scalar>::Reading m;
      while (depth_.read(time, m)) {
        if (ekf) (void)ekf_.update_depth(m.value(0));
        eta_(2) = m.value(0);
      }
    }
    if (s_.usbl) {
      (void)usbl_.sample(time, eta, nu);
      typename UsblSensor<Scalar>::Reading m;
      while (usbl_.read(time, m)) {
        if (ekf) (void)ekf_.update_position(m.value, static_cast<Scalar>(time - m.time));
        eta_.template head<2>() = m.value.template head<2>();
        if (!s_.depth) eta_(2) = m.value(2);
      }
    }
  }

  /// What the controller is given, the true state (eta, nu) filling what no
  /// sensor measures with `none`.
  void measurement(const Vec6& eta, const Vec6& nu, Vec6& eta_out, Vec6& nu_out) noexcept {
    if (e_.type == EstimatorType::ekf) {
      eta_out = ekf_.eta();
      nu_out = ekf_.nu();
    } else {
      eta_out = eta;
      nu_out = nu;
      if (s_.usbl) eta_out.template head<2>() = eta_.template head<2>();
      if (s_.usbl || s_.depth) eta_out(2) = eta_(2);
      if (s_.imu) {
        eta_out.template tail<3>() = eta_.template tail<3>();
        nu_out.template tail<3>() = nu_.template tail<3>();
      }
      if (s_.dvl) nu_out.template head<3>() = nu_.template head<3>();
    }
    // Moved by whole turns only when it jumped more than half of one, so a
    // continuous angle is handed on bit for bit.
    const Scalar turn = Scalar(6.283185307179586);
    for (int i = 3; i < 6; ++i) {
      const Scalar jump = eta_out(i) - given_eta_(i);
      if (std::abs(jump) > turn / Scalar(2)) eta_out(i) -= turn * std::round(jump / turn);
    }
    if (eta_out.allFinite()) given_eta_ = eta_out;
  }

  const Ekf<Scalar>& filter() const noexcept { return ekf_; }

 private:
  ValidationError build(const SensorsConfig<Scalar>& s, const EstimatorConfig<Scalar>& e,
                        std::uint64_t seed) noexcept {
    if (s.usbl)
      if (auto err = UsblSensor<Scalar>::create(*s.usbl, seed, usbl_)) return err;
    if (s.dvl)
      if (auto err = DvlSensor<Scalar>::create(*s.dvl, seed, dvl_)) return err;
    if (s.depth)
      if (auto err = DepthSensor<Scalar>::create(*s.depth, seed, depth_)) return err;
    if (s.imu)
      if (auto err = ImuSensor<Scalar>::create(*s.imu, seed, imu_)) return err;
    if (e.type != EstimatorType::none && e.type != EstimatorType::ekf)
      return detail::invalid("estimator.type", -1, static_cast<double>(e.type), "none or ekf");
    if (e.type == EstimatorType::ekf) {
      // The filter needs an absolute attitude and position; velocity and
      // depth it can do without.
      if (!s.imu)
        return detail::invalid("sensors.imu", -1, std::nan(""), "an IMU for the ekf estimator");
      if (!s.usbl)
        return detail::invalid("sensors.usbl", -1, std::nan(""),
                               "an acoustic position fix (usbl) for the ekf estimator");
    }
    if (auto err = neurov::validate(Sensing::filter_config(s, e))) return err;
    s_ = s;
    e_ = e;
    active_ = s.any();
    return {};
  }

  SensorsConfig<Scalar> s_{};
  EstimatorConfig<Scalar> e_{};
  bool active_ = false;
  UsblSensor<Scalar> usbl_{};
  DvlSensor<Scalar> dvl_{};
  DepthSensor<Scalar> depth_{};
  ImuSensor<Scalar> imu_{};
  Ekf<Scalar> ekf_{};
  double filter_time_ = 0.0;
  /// The last reading of each component (the initial state before the first).
  Vec6 eta_ = Vec6::Zero(), nu_ = Vec6::Zero();
  /// The pose given last: the branch the next angles are brought to.
  Vec6 given_eta_ = Vec6::Zero();
};

}  // namespace neurov
