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
#include "nerov_task.h"

#ifndef LOOP
#define LOOP 2
#endif
#ifndef STEPS
#define STEPS 20
#endif

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
  const neurov_nn_params p = nerov_nn_params(centres, widths);
  neurov_nn* nn;
  neurov_reference* ref;
  if (neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, 0) != NEUROV_STATUS_OK) return 2;
  float eta[6] = {0}, nu[6] = {0}, tau[6] = {0};
  if (neurov_reference_create(ref_storage, sizeof ref_storage, kLambdaD, kOmega, eta, &ref, 0) !=
      NEUROV_STATUS_OK)
    return 3;

  const neurov_allocator_params ap = nerov_allocator_params();
  neurov_allocator* alloc;
  if (neurov_allocator_create(alloc_storage, sizeof alloc_storage, &ap, &alloc, 0) != NEUROV_STATUS_OK)
    return 5;
  const neurov_ekf_params ep = onboard_ekf_params(0.5f);
  neurov_ekf* ekf;
  if (neurov_ekf_create(ekf_storage, sizeof ekf_storage, &ep, eta, nu, &ekf, 0) != NEUROV_STATUS_OK)
    return 6;
  float commands[6];

  /* A command with every DOF moving, so no branch takes a shortcut. */
  const float command[6] = {2.0f, 1.0f, 0.5f, 0.05f, -0.05f, 0.5f};
  neurov_desired desired = {{0}, {0}, {0}};
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
    plant_step(tau, p.dt, eta, nu);
  }
  return bad == 0 ? 0 : 4;
}

void _start(void) { sys_exit(run()); }
