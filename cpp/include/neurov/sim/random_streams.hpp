// One independent random stream per source of randomness (measurement noise,
// current, waves), each derived from the scenario's one seed. Turning a
// source on, or drawing more numbers from it (a smaller step, more
// substeps), then leaves every other source's numbers as they were.
#pragma once

#include <cstdint>

namespace neurov {

/// The random sources of a simulation. The numbers are part of the
/// reproducibility contract: a given (seed, stream) pair gives the same
/// numbers in every release, so never renumber them.
enum class RandomStream : std::uint64_t {
  /// The noise on the measured eta and nu. Its seed is the scenario seed
  /// itself, so runs from before the other streams existed draw the same noise.
  measurement_noise = 0,
  current = 1,
  waves = 2,
  // The sensors' noise (sim/sensors.hpp), one stream each.
  imu = 16,
  dvl = 17,
  depth = 18,
  usbl = 19,
};

namespace detail {
/// splitmix64's output function: a bijection of 64-bit words that spreads
/// every input bit over the whole output.
constexpr std::uint64_t splitmix64_mix(std::uint64_t z) noexcept {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
}  // namespace detail

/// The seed of one stream: the scenario seed itself for measurement_noise,
/// otherwise splitmix64_mix(seed ^ splitmix64_mix(golden * (id + 1))).
/// NormalRandom::reseed expands a seed s by walking s + k * golden, so seeds
/// that differ by a multiple of the golden ratio constant would share
/// state words; the full mix above puts the streams' seeds far apart instead.
constexpr std::uint64_t stream_seed(std::uint64_t seed, RandomStream stream) noexcept {
  if (stream == RandomStream::measurement_noise) return seed;
  const std::uint64_t id = static_cast<std::uint64_t>(stream);
  return detail::splitmix64_mix(seed ^ detail::splitmix64_mix(0x9E3779B97F4A7C15ULL * (id + 1)));
}

}  // namespace neurov
