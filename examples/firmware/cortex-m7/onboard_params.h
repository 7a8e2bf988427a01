/* Parameter sets of the C interface's on-board chain written once for the
 * programs that run it: the Cortex-M7 image and its instruction counter, and
 * the C interface's own tests (tests/firmware, tests/consumer_c, tests/cpp),
 * which include this file from here so that they run the example's numbers. */
#ifndef NEUROV_EXAMPLE_ONBOARD_PARAMS_H
#define NEUROV_EXAMPLE_ONBOARD_PARAMS_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "neurov/c_api.h"

/* The estimator's noise figures for an AHRS, a DVL, a depth sensor and an
 * acoustic fix, with every state's initial standard deviation initial_std. */
static inline neurov_ekf_params onboard_ekf_params(float initial_std) {
  neurov_ekf_params p;
  memset(&p, 0, sizeof p);
  p.linear_acceleration_noise = 0.05f;
  p.angular_acceleration_noise = 0.01f;
  p.gyro_bias_walk = 1e-4f;
  p.attitude_noise = 0.005f;
  p.gyro_noise = 0.001f;
  p.dvl_noise = 0.01f;
  p.depth_noise = 0.02f;
  p.position_noise = 0.5f;
  for (int i = 0; i < NEUROV_EKF_STATES; ++i) p.initial_std[i] = initial_std;
  return p;
}

/* Allocation over `thrusters` thrusters given by their positions and
 * directions (3 floats each, body axes) and thrust bounds, every thruster on
 * `curve` (NULL: thrust is the command). The parameters point at the arrays
 * until neurov_allocator_create copies them. */
static inline neurov_allocator_params onboard_allocator_params(uint32_t thrusters,
                                                               const float* positions,
                                                               const float* directions,
                                                               const float* min_thrust,
                                                               const float* max_thrust,
                                                               const neurov_thruster_curve* curve) {
  neurov_allocator_params p;
  neurov_allocator_params_init(&p);
  p.thrusters = thrusters;
  p.positions = positions;
  p.directions = directions;
  p.min_thrust = min_thrust;
  p.max_thrust = max_thrust;
  p.curve_count = curve != NULL ? 1u : 0u;
  p.curves = curve;
  return p;
}

#endif
