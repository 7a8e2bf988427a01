/* A C firmware's control task on a Cortex-M7, linked against neurov_c: the
 * NN controller and the reference model in static storage, stepped at a fixed
 * rate. There is no vehicle here, so a first-order stand-in plant closes the
 * loop; on a vehicle, read_sensors() and write_thrusters() talk to hardware
 * and a timer interrupt paces the loop. The image exists to be linked, sized
 * and checked for heap and exception symbols (examples/firmware/cortex-m7). */
#include <stdint.h>

#include "neurov/c_api.h"

#define N NEUROV_C_CENTRES

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char nn_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ref_storage[NEUROV_REFERENCE_STORAGE_BYTES];

static float eta[6], nu[6];
static volatile float thrust_out[6];
static volatile neurov_status last_status;

static void read_sensors(float eta_out[6], float nu_out[6]) {
  for (int i = 0; i < 6; ++i) {
    eta_out[i] = eta[i];
    nu_out[i] = nu[i];
  }
}

static void write_thrusters(const float tau[6]) {
  static const float m[6] = {215, 265, 265, 40, 80, 80};
  static const float d[6] = {70, 100, 100, 30, 50, 50};
  for (int i = 0; i < 6; ++i) {
    thrust_out[i] = tau[i];
    nu[i] += 0.2f * (tau[i] - d[i] * nu[i]) / m[i];
    eta[i] += 0.2f * nu[i];
  }
}

/* Centres on a deterministic pseudo-random pattern; a vehicle would keep a
 * table in flash. Filled on the stack and copied by neurov_nn_create(). */
static int configure(neurov_nn** nn, neurov_reference** ref) {
  float centres[N * NEUROV_C_INPUTS];
  float widths[N];
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
  neurov_validation_error error;
  if (neurov_nn_create(nn_storage, sizeof nn_storage, &p, nn, &error) != NEUROV_STATUS_OK)
    return 0;
  const float lambda_d[6] = {0.4f, 0.4f, 0.4f, 0.4f, 0.4f, 0.4f};
  const float omega[6] = {0.04f, 0.04f, 0.04f, 0.04f, 0.04f, 0.04f};
  const float eta0[6] = {0};
  return neurov_reference_create(ref_storage, sizeof ref_storage, lambda_d, omega, eta0, ref,
                                 &error) == NEUROV_STATUS_OK;
}

int main(void) {
  neurov_nn* nn;
  neurov_reference* ref;
  if (!configure(&nn, &ref)) {
    for (;;) {
    } /* a safe mode */
  }
  const float command[6] = {2.0f, 1.0f, 0.5f, 0.0f, 0.0f, 0.5f};
  neurov_desired desired;
  float eta_meas[6], nu_meas[6], tau[6];
  for (;;) { /* one pass per control period (5 Hz) */
    read_sensors(eta_meas, nu_meas);
    neurov_status s = neurov_reference_step(ref, command, 0.2f, &desired);
    if (s == NEUROV_STATUS_OK) s = neurov_nn_step(nn, eta_meas, nu_meas, &desired, tau);
    if (s != NEUROV_STATUS_OK) neurov_nn_reset(nn); /* tau is already 0 */
    last_status = s;
    write_thrusters(tau);
  }
}
