/* Counts the instructions one control step executes on Cortex-M7 code: the
 * same -Os Thumb-2/FPv5 object as the firmware image, run under qemu-arm in
 * user mode, one instruction per translation block, each one logged. Five
 * variants of this program differ only in what the loop does
 * (LOOP = 0: the stand-in plant, 1: + reference model, 2: + NN controller,
 * 3: + thrust allocation with the inverse curve, 4: + the estimator's
 * predict and all five updates), so the differences of their counts over
 * STEPS passes are the instructions per step of each. instruction_count.sh
 * builds and runs them and does the arithmetic.
 *
 * There is no C library start-up: _start runs the loop and leaves through the
 * Linux exit system call, so qemu-arm can run the program as it is. */
#include <stdint.h>

#include "neurov/c_api.h"

#ifndef LOOP
#define LOOP 2
#endif
#ifndef STEPS
#define STEPS 20
#endif
#define N NEUROV_C_CENTRES

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char nn_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ref_storage[NEUROV_REFERENCE_STORAGE_BYTES];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char alloc_storage[NEUROV_ALLOCATOR_STORAGE_BYTES(1)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ekf_storage[NEUROV_EKF_STORAGE_BYTES];
static float centres[N * NEUROV_C_INPUTS];
static float widths[N];

static void sys_exit(int code) {
  register int r0 __asm__("r0") = code;
  register int r7 __asm__("r7") = 1; /* exit */
  __asm__ volatile("svc 0" : : "r"(r0), "r"(r7) : "memory");
  for (;;) {
  }
}

static int run(void) {
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
  neurov_nn* nn;
  neurov_reference* ref;
  if (neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, 0) != NEUROV_STATUS_OK) return 2;
  const float lambda_d[6] = {0.4f, 0.4f, 0.4f, 0.4f, 0.4f, 0.4f};
  const float omega[6] = {0.04f, 0.04f, 0.04f, 0.04f, 0.04f, 0.04f};
  float eta[6] = {0}, nu[6] = {0}, tau[6] = {0};
  if (neurov_reference_create(ref_storage, sizeof ref_storage, lambda_d, omega, eta, &ref, 0) !=
      NEUROV_STATUS_OK)
    return 3;

  /* NEROV's six thrusters (as in main.c) with one command curve. */
  static const float pos[18] = {-0.5f, 0.3f, 0, -0.5f, -0.3f, 0, 0.4f, 0, 0, 0.4f, 0, 0, -0.4f, 0.3f, 0, -0.4f, -0.3f, 0};
  static const float dir[18] = {1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  static const float lo[6] = {-250, -250, -250, -250, -250, -250}, hi[6] = {250, 250, 250, 250, 250, 250};
  static const float cc[6] = {-1.0f, -0.5f, -0.05f, 0.05f, 0.5f, 1.0f}, ct[6] = {-200, -70, 0, 0, 90, 250};
  const neurov_thruster_curve curve = {6, cc, ct, 0.0f, 0.05f, 16.0f, 2.0f};
  neurov_allocator_params ap;
  neurov_allocator_params_init(&ap);
  ap.thrusters = 6;
  ap.positions = pos;
  ap.directions = dir;
  ap.min_thrust = lo;
  ap.max_thrust = hi;
  ap.curve_count = 1;
  ap.curves = &curve;
  neurov_allocator* alloc;
  if (neurov_allocator_create(alloc_storage, sizeof alloc_storage, &ap, &alloc, 0) != NEUROV_STATUS_OK)
    return 5;
  neurov_ekf_params ep = {0.05f, 0.01f, 1e-4f, 0.005f, 0.001f, 0.01f, 0.02f, 0.5f, {0}};
  for (int i = 0; i < NEUROV_EKF_STATES; ++i) ep.initial_std[i] = 0.5f;
  neurov_ekf* ekf;
  if (neurov_ekf_create(ekf_storage, sizeof ekf_storage, &ep, eta, nu, &ekf, 0) != NEUROV_STATUS_OK)
    return 6;
  float commands[6];

  /* A command with every DOF moving, so no branch takes a shortcut. */
  const float command[6] = {2.0f, 1.0f, 0.5f, 0.05f, -0.05f, 0.5f};
  neurov_desired desired = {{0}, {0}, {0}};
  static const float m[6] = {215, 265, 265, 40, 80, 80};
  static const float d[6] = {70, 100, 100, 30, 50, 50};
  int bad = 0;
  for (int k = 0; k < STEPS; ++k) {
#if LOOP >= 1
    bad += neurov_reference_step(ref, command, p.dt, &desired) != NEUROV_STATUS_OK;
#endif
#if LOOP >= 2
    bad += neurov_nn_step(nn, eta, nu, &desired, tau) != NEUROV_STATUS_OK;
#endif
#if LOOP >= 3
    bad += neurov_allocator_step(alloc, tau, 15.5f, commands, 0) != NEUROV_STATUS_OK;
#endif
#if LOOP >= 4
    bad += neurov_ekf_predict(ekf, p.dt) != NEUROV_STATUS_OK;
    bad += neurov_ekf_update_attitude(ekf, eta + 3) != NEUROV_STATUS_OK;
    bad += neurov_ekf_update_gyro(ekf, nu + 3) != NEUROV_STATUS_OK;
    bad += neurov_ekf_update_dvl(ekf, nu) != NEUROV_STATUS_OK;
    bad += neurov_ekf_update_depth(ekf, eta[2]) != NEUROV_STATUS_OK;
    bad += neurov_ekf_update_position(ekf, eta, 0.4f) != NEUROV_STATUS_OK;
#endif
    for (int i = 0; i < 6; ++i) {
      nu[i] += p.dt * (tau[i] - d[i] * nu[i]) / m[i];
      eta[i] += p.dt * nu[i];
    }
  }
  return bad == 0 ? 0 : 4;
}

void _start(void) { sys_exit(run()); }
