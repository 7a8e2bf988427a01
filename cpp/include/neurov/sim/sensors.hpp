// Sensor models between the true state and an estimator: an AHRS/IMU
// (attitude and gyro, gyro bias random walk), a DVL (body velocity over the
// seabed, dropouts), a pressure depth sensor and an acoustic position fix
// (USBL-like). Each samples the truth at its own rate, adds its bias and
// white noise from its own random stream, and delivers the sample `latency`
// seconds later through a fixed-capacity delay line.
//
//   sample n is taken at the first call with time >= n / rate,
//   z_n = h(x(t_n)) + bias + noise_n,  noise_n ~ N(0, noise^2 I),
//   delivered by read() once time >= t_n + latency.
//
// Times are double whatever the Scalar: a float clock loses milliseconds
// within hours.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "neurov/core/field_spec.hpp"
#include "neurov/core/random.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"
#include "neurov/sim/random_streams.hpp"

namespace neurov {

/// The sensors' random streams (RandomStream's numbers, which never change).
namespace sensor_stream {
inline constexpr RandomStream imu = RandomStream::imu;
inline constexpr RandomStream dvl = RandomStream::dvl;
inline constexpr RandomStream depth = RandomStream::depth;
inline constexpr RandomStream usbl = RandomStream::usbl;
}  // namespace sensor_stream

/// Samples a delay line holds: a latency of up to (capacity - 1) periods.
inline constexpr int kSensorDelayCapacity = 64;

template <typename Scalar, int Dim>
struct Measurement {
  double time = 0.0;  ///< when the truth was sampled [s]
  Eigen::Matrix<Scalar, Dim, 1> value = Eigen::Matrix<Scalar, Dim, 1>::Zero();
  bool valid = false;  ///< false for a dropout: the sensor reported no fix
};

/// A first-in first-out ring of measurements with a fixed capacity.
template <typename Scalar, int Dim>
class DelayLine {
 public:
  bool push(const Measurement<Scalar, Dim>& m) noexcept {
    if (size_ == kSensorDelayCapacity) return false;
    items_[(head_ + size_) % kSensorDelayCapacity] = m;
    ++size_;
    return true;
  }
  /// The oldest measurement taken at or before `release_time`, if any.
  bool pop_until(double release_time, Measurement<Scalar, Dim>& out) noexcept {
    if (size_ == 0 || items_[head_].time > release_time) return false;
    out = items_[head_];
    head_ = (head_ + 1) % kSensorDelayCapacity;
    --size_;
    return true;
  }
  int size() const noexcept { return size_; }
  void clear() noexcept { head_ = size_ = 0; }

 private:
  Measurement<Scalar, Dim> items_[kSensorDelayCapacity];
  int head_ = 0, size_ = 0;
};

namespace detail {

/// Rate, latency, clock, delay line and noise source of one sensor.
template <typename Scalar, int Dim>
class SensorChannel {
 public:
  using Vec = Eigen::Matrix<Scalar, Dim, 1>;

  /// Names the fields with the sensor's prefix, e.g. "sensors.dvl.rate".
  static ValidationError check(const char* rate_field, double rate, const char* latency_field,
                               double latency) noexcept {
    if (auto e = check_positive_scalar(rate_field, rate)) return e;
    if (auto e = check_non_negative_scalar(latency_field, latency)) return e;
    if (!(latency * rate <= kSensorDelayCapacity - 2))
      return invalid(latency_field, -1, latency,
                     "<= 62 sample periods (the delay line holds 64 samples)");
    return {};
  }

  void start(double rate, double latency, std::uint64_t seed, RandomStream stream) noexcept {
    rate_ = rate;
    latency_ = latency;
    seed_ = stream_seed(seed, stream);
    reset();
  }

  void reset() noexcept {
    next_ = 0;
    line_.clear();
    rng_.reseed(seed_);
  }

  /// True (and the clock advanced) when a sample is due at `time`; the
  /// tolerance lets a caller stepping at exact multiples of the period hit
  /// every sample despite rounding.
  bool due(double time) noexcept {
    if (!(time * rate_ >= static_cast<double>(next_) - 1e-6)) return false;
    next_ = static_cast<std::int64_t>(std::floor(time * rate_ + 1e-6)) + 1;
    return true;
  }

  void emit(double time, const Vec& value, bool valid) noexcept {
    Measurement<Scalar, Dim> m;
    m.time = time;
    m.value = value;
    m.valid = valid;
    // The capacity check at create() keeps a reading caller from overflowing;
    // a caller that never reads loses the newest samples, not memory.
    (void)line_.push(m);
  }

  bool read(double time, Measurement<Scalar, Dim>& out) noexcept {
    return line_.pop_until(time - latency_ + 1e-9, out);
  }

  Scalar normal() noexcept { return static_cast<Scalar>(rng_.normal()); }
  double uniform() noexcept { return rng_.uniform(); }
  double period() const noexcept { return 1.0 / rate_; }

 private:
  double rate_ = 1.0, latency_ = 0.0;
  std::uint64_t seed_ = 0;
  std::int64_t next_ = 0;
  NormalRandom rng_{0};
  DelayLine<Scalar, Dim> line_{};
};

template <typename Scalar>
inline Scalar wrap_angle(Scalar a) noexcept {
  const Scalar pi = Scalar(3.14159265358979323846);
  a = std::remainder(a, Scalar(2) * pi);
  return a <= -pi ? a + Scalar(2) * pi : a;
}

/// What a sensor's truth is made of: it refuses a non-finite one.
enum class SensedTruth { pose, velocity, both };

/// What every sensor shares (CRTP): its configuration (with `rate` and
/// `latency`), its channel, create(), sample(), read(), config() and reset().
/// A sensor Derived supplies kRateField and kLatencyField (its fields' names
/// in errors), `static ValidationError check(const Config&)` for its other
/// fields and `bool measure(eta, nu, z)` (false: a dropout, delivered with
/// valid = false and z = 0); with state of its own, reset() calling
/// reset_channel().
template <typename Derived, typename Config, typename Scalar, int Dim, RandomStream Stream,
          SensedTruth Truth>
class Sensor {
 public:
  using Reading = Measurement<Scalar, Dim>;

  static ValidationError create(const Config& c, std::uint64_t seed, Derived& out) noexcept {
    if (auto e = SensorChannel<Scalar, Dim>::check(Derived::kRateField, c.rate,
                                                   Derived::kLatencyField, c.latency))
      return e;
    if (auto e = Derived::check(c)) return e;
    out.c_ = c;
    out.channel_.start(c.rate, c.latency, seed, Stream);
    out.reset();
    return {};
  }

  /// Takes a sample if one is due; a non-finite time or truth takes none.
  Status sample(double time, const Vector6<Scalar>& eta, const Vector6<Scalar>& nu) noexcept {
    const bool finite = (Truth == SensedTruth::velocity || all_finite(eta)) &&
                        (Truth == SensedTruth::pose || all_finite(nu));
    if (!std::isfinite(time) || !finite) return Status::non_finite_input;
    if (!channel_.due(time)) return Status::ok;
    Eigen::Matrix<Scalar, Dim, 1> z;
    const bool valid = static_cast<Derived&>(*this).measure(eta, nu, z);
    if (!valid) z.setZero();
    channel_.emit(time, z, valid);
    return Status::ok;
  }

  bool read(double time, Reading& out) noexcept { return channel_.read(time, out); }
  const Config& config() const noexcept { return c_; }
  void reset() noexcept { reset_channel(); }

 protected:
  void reset_channel() noexcept { channel_.reset(); }

  Config c_{};
  SensorChannel<Scalar, Dim> channel_{};
};

}  // namespace detail

// ---------------------------------------------------------------- AHRS / IMU

template <typename Scalar>
struct ImuConfig {
  double rate = 50.0;                ///< [Hz], > 0
  double latency = 0.0;              ///< [s], >= 0
  Scalar attitude_noise = Scalar(0);  ///< std of phi, theta, psi [rad]
  Scalar gyro_noise = Scalar(0);      ///< std of p, q, r [rad/s]
  Scalar gyro_bias_walk = Scalar(0);  ///< bias random walk [rad/s/sqrt(s)]
  Vector3<Scalar> gyro_bias = Vector3<Scalar>::Zero();  ///< initial gyro bias [rad/s]
};

template <typename Scalar>
auto config_fields(const ImuConfig<Scalar>*) noexcept {
  using C = ImuConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("rate", &C::rate, "Hz", Check::positive, "Sample rate"),
      field_spec<C>("latency", &C::latency, "s", Check::non_negative, "Latency"),
      field_spec<C>("attitude_noise", &C::attitude_noise, "rad", Check::non_negative, "Standard deviation of the angles"),
      field_spec<C>("gyro_noise", &C::gyro_noise, "rad/s", Check::non_negative, "Standard deviation of the rates"),
      field_spec<C>("gyro_bias_walk", &C::gyro_bias_walk, "rad/s/sqrt(s)", Check::non_negative, "Bias random walk"),
      field_spec<C>("gyro_bias", &C::gyro_bias, "rad/s", Check::finite, "Initial gyro bias (3,)"));
}

/// Measures [phi, theta, psi (wrapped to (-pi, pi]), p, q, r] + [0; bias] + noise.
template <typename Scalar>
class ImuSensor : public detail::Sensor<ImuSensor<Scalar>, ImuConfig<Scalar>, Scalar, 6,
                                        sensor_stream::imu, detail::SensedTruth::both> {
  using Base = detail::Sensor<ImuSensor<Scalar>, ImuConfig<Scalar>, Scalar, 6, sensor_stream::imu,
                              detail::SensedTruth::both>;
  friend Base;

 public:
  const Vector3<Scalar>& gyro_bias() const noexcept { return bias_; }
  void reset() noexcept {
    this->reset_channel();
    bias_ = this->c_.gyro_bias;
  }

 private:
  static constexpr const char* kRateField = "sensors.imu.rate";
  static constexpr const char* kLatencyField = "sensors.imu.latency";

  static ValidationError check(const ImuConfig<Scalar>& c) noexcept {
    if (auto e = detail::check_non_negative_scalar("sensors.imu.attitude_noise", c.attitude_noise))
      return e;
    if (auto e = detail::check_non_negative_scalar("sensors.imu.gyro_noise", c.gyro_noise)) return e;
    if (auto e = detail::check_non_negative_scalar("sensors.imu.gyro_bias_walk", c.gyro_bias_walk))
      return e;
    return detail::check_finite("sensors.imu.gyro_bias", c.gyro_bias);
  }

  bool measure(const Vector6<Scalar>& eta, const Vector6<Scalar>& nu, Vector6<Scalar>& z) noexcept {
    const auto& c = this->c_;
    auto& channel = this->channel_;
    const Scalar walk = c.gyro_bias_walk * static_cast<Scalar>(std::sqrt(channel.period()));
    for (int i = 0; i < 3; ++i) bias_(i) += walk * channel.normal();
    for (int i = 0; i < 3; ++i) z(i) = eta(3 + i) + c.attitude_noise * channel.normal();
    for (int i = 0; i < 3; ++i) z(3 + i) = nu(3 + i) + bias_(i) + c.gyro_noise * channel.normal();
    for (int i = 0; i < 3; ++i) z(i) = detail::wrap_angle(z(i));
    return true;
  }

  Vector3<Scalar> bias_ = Vector3<Scalar>::Zero();
};

// ---------------------------------------------------------------------- DVL

template <typename Scalar>
struct DvlConfig {
  double rate = 5.0;          ///< [Hz], > 0
  double latency = 0.0;       ///< [s], >= 0
  Scalar noise = Scalar(0);   ///< std per axis [m/s]
  double dropout_rate = 0.0;  ///< probability that a sample has no bottom lock, [0, 1)
  Vector3<Scalar> bias = Vector3<Scalar>::Zero();  ///< [m/s]
};

template <typename Scalar>
auto config_fields(const DvlConfig<Scalar>*) noexcept {
  using C = DvlConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("rate", &C::rate, "Hz", Check::positive, "Sample rate"),
      field_spec<C>("latency", &C::latency, "s", Check::non_negative, "Latency"),
      field_spec<C>("noise", &C::noise, "m/s", Check::non_negative, "Standard deviation per axis"),
      field_spec<C>("dropout_rate", &C::dropout_rate, "", Check::none,
                    "Probability that a sample has no bottom lock, in [0, 1)"),
      field_spec<C>("bias", &C::bias, "m/s", Check::finite, "Bias (3,)"));
}

/// Measures the body velocity over ground [u, v, w] + bias + noise; a
/// dropout delivers a sample with valid = false.
template <typename Scalar>
class DvlSensor : public detail::Sensor<DvlSensor<Scalar>, DvlConfig<Scalar>, Scalar, 3,
                                        sensor_stream::dvl, detail::SensedTruth::velocity> {
  friend detail::Sensor<DvlSensor<Scalar>, DvlConfig<Scalar>, Scalar, 3, sensor_stream::dvl,
                        detail::SensedTruth::velocity>;

  static constexpr const char* kRateField = "sensors.dvl.rate";
  static constexpr const char* kLatencyField = "sensors.dvl.latency";

  static ValidationError check(const DvlConfig<Scalar>& c) noexcept {
    if (auto e = detail::check_non_negative_scalar("sensors.dvl.noise", c.noise)) return e;
    if (!(c.dropout_rate >= 0.0 && c.dropout_rate < 1.0))
      return detail::invalid("sensors.dvl.dropout_rate", -1, c.dropout_rate, ">= 0 and < 1");
    return detail::check_finite("sensors.dvl.bias", c.bias);
  }

  bool measure(const Vector6<Scalar>&, const Vector6<Scalar>& nu, Vector3<Scalar>& z) noexcept {
    // Draw the noise whether or not the sample drops out, so a dropout does
    // not shift the noise of every later sample.
    const bool lost = this->channel_.uniform() <= this->c_.dropout_rate;
    for (int i = 0; i < 3; ++i)
      z(i) = nu(i) + this->c_.bias(i) + this->c_.noise * this->channel_.normal();
    return !lost;
  }
};

// -------------------------------------------------------------------- depth

template <typename Scalar>
struct DepthConfig {
  double rate = 10.0;        ///< [Hz], > 0
  double latency = 0.0;      ///< [s], >= 0
  Scalar noise = Scalar(0);  ///< std [m]
  Scalar bias = Scalar(0);   ///< [m]
};

template <typename Scalar>
auto config_fields(const DepthConfig<Scalar>*) noexcept {
  using C = DepthConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("rate", &C::rate, "Hz", Check::positive, "Sample rate"),
      field_spec<C>("latency", &C::latency, "s", Check::non_negative, "Latency"),
      field_spec<C>("noise", &C::noise, "m", Check::non_negative, "Standard deviation"),
      field_spec<C>("bias", &C::bias, "m", Check::finite, "Bias"));
}

/// Measures the depth z (NED, down positive) + bias + noise.
template <typename Scalar>
class DepthSensor : public detail::Sensor<DepthSensor<Scalar>, DepthConfig<Scalar>, Scalar, 1,
                                          sensor_stream::depth, detail::SensedTruth::pose> {
  friend detail::Sensor<DepthSensor<Scalar>, DepthConfig<Scalar>, Scalar, 1, sensor_stream::depth,
                        detail::SensedTruth::pose>;

  static constexpr const char* kRateField = "sensors.depth.rate";
  static constexpr const char* kLatencyField = "sensors.depth.latency";

  static ValidationError check(const DepthConfig<Scalar>& c) noexcept {
    if (auto e = detail::check_non_negative_scalar("sensors.depth.noise", c.noise)) return e;
    if (!std::isfinite(static_cast<double>(c.bias)))
      return detail::invalid("sensors.depth.bias", -1, c.bias, "finite");
    return {};
  }

  bool measure(const Vector6<Scalar>& eta, const Vector6<Scalar>&,
               Eigen::Matrix<Scalar, 1, 1>& z) noexcept {
    z(0) = eta(2) + this->c_.bias + this->c_.noise * this->channel_.normal();
    return true;
  }
};

// --------------------------------------------------------------------- USBL

template <typename Scalar>
struct UsblConfig {
  double rate = 1.0;         ///< [Hz], > 0
  double latency = 0.0;      ///< [s], >= 0 (acoustic travel and processing)
  Scalar noise = Scalar(0);  ///< std per axis [m]
  Vector3<Scalar> bias = Vector3<Scalar>::Zero();  ///< [m], NED
};

template <typename Scalar>
auto config_fields(const UsblConfig<Scalar>*) noexcept {
  using C = UsblConfig<Scalar>;
  return std::make_tuple(
      field_spec<C>("rate", &C::rate, "Hz", Check::positive, "Sample rate"),
      field_spec<C>("latency", &C::latency, "s", Check::non_negative, "Latency (acoustic travel and processing)"),
      field_spec<C>("noise", &C::noise, "m", Check::non_negative, "Standard deviation per axis"),
      field_spec<C>("bias", &C::bias, "m", Check::finite, "Bias, NED (3,)"));
}

/// Measures the position [x, y, z] (NED) + bias + noise, at the sample time.
template <typename Scalar>
class UsblSensor : public detail::Sensor<UsblSensor<Scalar>, UsblConfig<Scalar>, Scalar, 3,
                                         sensor_stream::usbl, detail::SensedTruth::pose> {
  friend detail::Sensor<UsblSensor<Scalar>, UsblConfig<Scalar>, Scalar, 3, sensor_stream::usbl,
                        detail::SensedTruth::pose>;

  static constexpr const char* kRateField = "sensors.usbl.rate";
  static constexpr const char* kLatencyField = "sensors.usbl.latency";

  static ValidationError check(const UsblConfig<Scalar>& c) noexcept {
    if (auto e = detail::check_non_negative_scalar("sensors.usbl.noise", c.noise)) return e;
    return detail::check_finite("sensors.usbl.bias", c.bias);
  }

  bool measure(const Vector6<Scalar>& eta, const Vector6<Scalar>&, Vector3<Scalar>& z) noexcept {
    for (int i = 0; i < 3; ++i)
      z(i) = eta(i) + this->c_.bias(i) + this->c_.noise * this->channel_.normal();
    return true;
  }
};

}  // namespace neurov
