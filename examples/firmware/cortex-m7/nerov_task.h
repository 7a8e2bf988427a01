/* The control task's vehicle and gains, shared by the firmware image
 * (main.c) and the instruction counter (instruction_count.c) so that the
 * counted step is the image's step. In flash: NEROV's six thrusters as
 * neurov's vehicle file assumes them (positions in m, body axes), 250 N each
 * way, one normalised command curve (-1..1) with a dead band and weaker
 * reverse thrust, and the stand-in plant's per-DOF inertia and damping. */
#ifndef NEUROV_EXAMPLE_NEROV_TASK_H
#define NEUROV_EXAMPLE_NEROV_TASK_H

#include <stdint.h>

#include "neurov/c_api.h"
#include "onboard_params.h"

#define N NEUROV_C_CENTRES
#define THRUSTERS 6

static const float kPositions[3 * THRUSTERS] = {-0.5f, 0.3f, 0, -0.5f, -0.3f, 0, 0.4f, 0, 0,
                                                0.4f,  0,    0, -0.4f, 0.3f,  0, -0.4f, -0.3f, 0};
static const float kDirections[3 * THRUSTERS] = {1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
static const float kMinThrust[THRUSTERS] = {-250, -250, -250, -250, -250, -250};
static const float kMaxThrust[THRUSTERS] = {250, 250, 250, 250, 250, 250};
static const float kCurveCommand[] = {-1.0f, -0.5f, -0.05f, 0.05f, 0.5f, 1.0f};
static const float kCurveThrust[] = {-200.0f, -70.0f, 0.0f, 0.0f, 90.0f, 250.0f};
static const neurov_thruster_curve kCurve = {6, kCurveCommand, kCurveThrust, 0.0f, 0.05f, 16.0f, 2.0f};

/* The stand-in plant: M nu_dot = tau - D nu per DOF, no coupling. */
static const float kPlantInertia[6] = {215, 265, 265, 40, 80, 80};
static const float kPlantDamping[6] = {70, 100, 100, 30, 50, 50};

/* The reference model's gains. */
static const float kLambdaD[6] = {0.4f, 0.4f, 0.4f, 0.4f, 0.4f, 0.4f};
static const float kOmega[6] = {0.04f, 0.04f, 0.04f, 0.04f, 0.04f, 0.04f};

/* The NN controller with centres on a deterministic pseudo-random pattern
 * (a vehicle would keep a table in flash) written into the caller's arrays,
 * which neurov_nn_create() copies. */
static inline neurov_nn_params nerov_nn_params(float centres[N * NEUROV_C_INPUTS], float widths[N]) {
  uint32_t state = 1u;
  for (int k = 0; k < N * NEUROV_C_INPUTS; ++k) {
    state = state * 1664525u + 1013904223u;
    centres[k] = (float)(state >> 8) * (2.0f / 16777216.0f) - 1.0f;
  }
  for (int j = 0; j < N; ++j) widths[j] = 30.0f;
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  p.centres = centres;
  p.widths = widths;
  for (int i = 0; i < 6; ++i) p.kd[i] = i < 3 ? 200.0f : 50.0f;
  return p;
}

/* Every thruster on kCurve. */
static inline neurov_allocator_params nerov_allocator_params(void) {
  return onboard_allocator_params(THRUSTERS, kPositions, kDirections, kMinThrust, kMaxThrust, &kCurve);
}

/* One period dt of the stand-in plant under tau. */
static inline void plant_step(const float tau[6], float dt, float eta[6], float nu[6]) {
  for (int i = 0; i < 6; ++i) {
    nu[i] += dt * (tau[i] - kPlantDamping[i] * nu[i]) / kPlantInertia[i];
    eta[i] += dt * nu[i];
  }
}

#endif
