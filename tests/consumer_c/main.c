/* One control period from C: the estimator, the NN controller and the thrust
 * allocation, with a buffer created and one never created; exits non-zero if
 * anything is off, so CI sees a package a C project cannot use. */
#include <stdio.h>

#include <neurov/c_api.h>

#include "onboard_params.h"

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char storage[NEUROV_NN_STORAGE_BYTES(NEUROV_C_CENTRES)];
static float centres[NEUROV_C_CENTRES * NEUROV_C_INPUTS];
static float widths[NEUROV_C_CENTRES];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ekf_storage[NEUROV_EKF_STORAGE_BYTES];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char alloc_storage[NEUROV_ALLOCATOR_STORAGE_BYTES(0)];

/* Six thrusters, one per DOF: B = I (a layout given as its matrix). */
static int allocate(const float tau[6]) {
  float b[36] = {0}, lo[6], hi[6], commands[6];
  for (int i = 0; i < 6; ++i) {
    b[7 * i] = 1.0f;
    lo[i] = -100.0f;
    hi[i] = 100.0f;
  }
  neurov_allocator_params p = onboard_allocator_params(6, NULL, NULL, lo, hi, NULL);
  p.matrix = b;
  neurov_allocator* a = NULL;
  if (neurov_allocator_create(alloc_storage, sizeof alloc_storage, &p, &a, NULL) != NEUROV_STATUS_OK) return 5;
  if (neurov_allocator_step(a, tau, 0.0f, commands, NULL) != NEUROV_STATUS_OK) return 6;
  return commands[0] == (tau[0] > 100.0f ? 100.0f : tau[0]) ? 0 : 7;
}

static int estimate(float eta[6], float nu[6]) {
  const neurov_ekf_params p = onboard_ekf_params(1.0f);
  neurov_ekf* f = NULL;
  const float zero[6] = {0}, dvl[3] = {0.1f, 0, 0};
  if (neurov_ekf_create(ekf_storage, sizeof ekf_storage, &p, zero, zero, &f, NULL) != NEUROV_STATUS_OK) return 8;
  if (neurov_ekf_predict(f, 0.2f) != NEUROV_STATUS_OK) return 9;
  if (neurov_ekf_update_dvl(f, dvl) != NEUROV_STATUS_OK) return 10;
  neurov_ekf_estimate(f, eta, nu);
  return nu[0] > 0.0f ? 0 : 11;
}

int main(void) {
  for (int j = 0; j < NEUROV_C_CENTRES; ++j) {
    widths[j] = 2.0f;
    for (int i = 0; i < NEUROV_C_INPUTS; ++i)
      centres[j * NEUROV_C_INPUTS + i] = (float)((j * 7 + i * 3) % 11 - 5) / 5.0f;
  }
  neurov_desired d = {{1.0f, 0, 0, 0, 0, 0}, {0}, {0}};
  float eta[6], nu[6];
  float tau[6];
  const int e = estimate(eta, nu);
  if (e != 0) return e;
  if (neurov_nn_step((neurov_nn*)(void*)storage, eta, nu, &d, tau) !=
      NEUROV_STATUS_INVALID_ARGUMENT)
    return 1; /* a buffer create() never saw */
  /* The caller's N, through the header's macros, is the installed library's. */
  if (neurov_nn_storage_size() == 0 || neurov_nn_storage_size() > sizeof storage) return 12;
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  if (p.centres_count != neurov_nn_centres()) return 13;
  p.centres = centres;
  p.widths = widths;
  p.kd[0] = 100.0f;
  neurov_nn* nn = NULL;
  if (neurov_nn_create(storage, sizeof storage, &p, &nn, NULL) != NEUROV_STATUS_OK) return 2;
  if (neurov_nn_step(nn, eta, nu, &d, tau) != NEUROV_STATUS_OK) return 3;
  if (!(tau[0] > 0.0f)) return 4;
  printf("neurov_c from C: N = %u, tau_x = %.3f N after one step\n", (unsigned)neurov_nn_centres(),
         (double)tau[0]);
  return allocate(tau);
}
