/* A C firmware's control task on a Cortex-M7, linked against neurov_c: one
 * control cycle per period, sensors -> estimator -> reference model -> NN
 * controller -> thrust allocation with the inverse thrust curve -> thruster
 * commands, every object in static storage. There is no vehicle here, so a
 * first-order stand-in plant closes the loop; on a vehicle, the sensor reads
 * and write_thrusters() talk to hardware and a timer interrupt paces the
 * loop. The image exists to be linked, sized and checked for heap and
 * exception symbols (examples/firmware/cortex-m7). */
#include <stdint.h>

#include "neurov/c_api.h"
#include "nerov_task.h"

#define DT 0.2f

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char nn_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ref_storage[NEUROV_REFERENCE_STORAGE_BYTES];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ekf_storage[NEUROV_EKF_STORAGE_BYTES];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char alloc_storage[NEUROV_ALLOCATOR_STORAGE_BYTES(1)];

/* The stand-in vehicle: its true state, and what the thrusters receive. */
static float eta[6], nu[6];
static volatile float command_out[THRUSTERS];
static volatile neurov_status last_status;

static void write_thrusters(const float commands[THRUSTERS], const float thrusts[THRUSTERS]) {
  float tau[6] = {0};
  for (int j = 0; j < THRUSTERS; ++j) {
    const float* r = kPositions + 3 * j;
    const float* e = kDirections + 3 * j;
    command_out[j] = commands[j];
    tau[0] += e[0] * thrusts[j];
    tau[1] += e[1] * thrusts[j];
    tau[2] += e[2] * thrusts[j];
    tau[3] += (r[1] * e[2] - r[2] * e[1]) * thrusts[j];
    tau[4] += (r[2] * e[0] - r[0] * e[2]) * thrusts[j];
    tau[5] += (r[0] * e[1] - r[1] * e[0]) * thrusts[j];
  }
  plant_step(tau, DT, eta, nu);
}

static int configure_controller(neurov_nn** nn, neurov_reference** ref) {
  float centres[N * NEUROV_C_INPUTS]; /* on the stack: copied by neurov_nn_create() */
  float widths[N];
  const neurov_nn_params p = nerov_nn_params(centres, widths);
  neurov_validation_error error;
  if (neurov_nn_create(nn_storage, sizeof nn_storage, &p, nn, &error) != NEUROV_STATUS_OK)
    return 0;
  const float eta0[6] = {0};
  return neurov_reference_create(ref_storage, sizeof ref_storage, kLambdaD, kOmega, eta0, ref,
                                 &error) == NEUROV_STATUS_OK;
}

static int configure_onboard(neurov_ekf** ekf, neurov_allocator** alloc) {
  const neurov_ekf_params e = onboard_ekf_params(0.5f);
  const float zero[6] = {0};
  if (neurov_ekf_create(ekf_storage, sizeof ekf_storage, &e, zero, zero, ekf, 0) != NEUROV_STATUS_OK)
    return 0;
  const neurov_allocator_params a = nerov_allocator_params();
  return neurov_allocator_create(alloc_storage, sizeof alloc_storage, &a, alloc, 0) == NEUROV_STATUS_OK;
}

int main(void) {
  neurov_nn* nn;
  neurov_reference* ref;
  neurov_ekf* ekf;
  neurov_allocator* alloc;
  if (!configure_controller(&nn, &ref) || !configure_onboard(&ekf, &alloc)) {
    for (;;) {
    } /* a safe mode */
  }
  const float command[6] = {2.0f, 1.0f, 0.5f, 0.0f, 0.0f, 0.5f};
  const float supply_voltage = 15.5f; /* on a vehicle: the battery monitor */
  neurov_desired desired;
  float eta_est[6], nu_est[6], tau[6], commands[THRUSTERS], thrusts[THRUSTERS];
  for (uint32_t k = 0;; ++k) { /* one pass per control period (5 Hz) */
    /* Sensors -> estimator: attitude and gyro, DVL and depth every period,
     * an acoustic fix every fifth (1 Hz), 0.4 s old when it arrives. */
    neurov_ekf_predict(ekf, DT);
    neurov_ekf_update_attitude(ekf, eta + 3);
    neurov_ekf_update_gyro(ekf, nu + 3);
    neurov_ekf_update_dvl(ekf, nu);
    neurov_ekf_update_depth(ekf, eta[2]);
    if (k % 5 == 0) neurov_ekf_update_position(ekf, eta, 0.4f);
    neurov_ekf_estimate(ekf, eta_est, nu_est);
    /* -> reference model -> NN controller -> allocation -> commands. */
    neurov_status s = neurov_reference_step(ref, command, DT, &desired);
    if (s == NEUROV_STATUS_OK) s = neurov_nn_step(nn, eta_est, nu_est, &desired, tau);
    if (s != NEUROV_STATUS_OK) neurov_nn_reset(nn); /* tau is already 0 */
    const neurov_status a = neurov_allocator_step(alloc, tau, supply_voltage, commands, thrusts);
    last_status = s != NEUROV_STATUS_OK ? s : a; /* on refusal: neutral commands */
    write_thrusters(commands, thrusts);
  }
}
