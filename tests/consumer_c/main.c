/* One control period of the NN controller from C, with a buffer created and
 * one never created; exits non-zero if anything is off, so CI sees a package
 * a C project cannot use. */
#include <stdio.h>

#include <neurov/c_api.h>

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char storage[NEUROV_NN_STORAGE_BYTES(NEUROV_C_CENTRES)];
static float centres[NEUROV_C_CENTRES * NEUROV_C_INPUTS];
static float widths[NEUROV_C_CENTRES];

int main(void) {
  for (int j = 0; j < NEUROV_C_CENTRES; ++j) {
    widths[j] = 2.0f;
    for (int i = 0; i < NEUROV_C_INPUTS; ++i)
      centres[j * NEUROV_C_INPUTS + i] = (float)((j * 7 + i * 3) % 11 - 5) / 5.0f;
  }
  neurov_desired d = {{1.0f, 0, 0, 0, 0, 0}, {0}, {0}};
  const float eta[6] = {0}, nu[6] = {0};
  float tau[6];
  if (neurov_nn_step((neurov_nn*)(void*)storage, eta, nu, &d, tau) !=
      NEUROV_STATUS_INVALID_ARGUMENT)
    return 1; /* a buffer create() never saw */
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  p.centres = centres;
  p.widths = widths;
  p.kd[0] = 100.0f;
  neurov_nn* nn = NULL;
  if (neurov_nn_create(storage, sizeof storage, &p, &nn, NULL) != NEUROV_STATUS_OK) return 2;
  if (neurov_nn_step(nn, eta, nu, &d, tau) != NEUROV_STATUS_OK) return 3;
  printf("neurov_c from C: N = %u, tau_x = %.3f N after one step\n", (unsigned)neurov_nn_centres(),
         (double)tau[0]);
  return tau[0] > 0.0f ? 0 : 4;
}
