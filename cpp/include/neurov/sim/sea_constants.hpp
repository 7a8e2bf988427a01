// Physical constants of the sea models, one place for each.
#pragma once

namespace neurov {

/// g [m/s^2]: the weight of a payload (W = m g) and the deep-water
/// dispersion relation of the waves (k = omega^2 / g).
inline constexpr double standard_gravity = 9.81;

}  // namespace neurov
