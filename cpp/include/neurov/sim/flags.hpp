// The kinds the configuration and the disturbance parts share: the bits of
// SimulationResult::faults and the current's model.
#pragma once

#include <cstdint>

namespace neurov {

/// Bits of SimulationResult::faults, one per kind of fault active in a step.
namespace fault_bits {
constexpr std::uint8_t freeze = 1;
constexpr std::uint8_t dropout = 2;
constexpr std::uint8_t noise_burst = 4;
constexpr std::uint8_t thruster = 8;  ///< some thruster below full efficiency
/// The row's desired state came from a reference step that limited the pitch
/// (ReferenceModel::pitch_limited(): the command's pitch clamped, or the
/// reference's own held at the limit).
constexpr std::uint8_t pitch_limited = 16;
/// The vehicle was above the wave model's minimum depth (Waves::minimum_depth,
/// 1.2 Hs) at the start of some substep of the row's interval, where the
/// linear deep-water kinematics do not hold.
constexpr std::uint8_t shallow = 32;
}  // namespace fault_bits

/// The current's model: `constant` is the mean + sinusoid + steps of the
/// fields current, current_amplitude, current_period and current_steps;
/// `gauss_markov` is SimulationConfig::gauss_markov_current alone.
enum class CurrentModel : std::uint8_t { constant = 0, gauss_markov = 1 };

}  // namespace neurov
