/* The on-board chain of the C interface from C: thrust allocation with an
 * inverse thrust curve and the estimator, in static storage sized by the
 * header's constants; the allocation reproduces tau inside the attainable
 * set, refusals leave neutral commands and an unchanged estimate, buffers
 * create() never saw are refused. Exits non-zero on the first failed check
 * (all are counted). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "c_check.h"
#include "neurov/c_api.h"
#include "onboard_params.h"

#define THRUSTERS 8

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char alloc_storage[NEUROV_ALLOCATOR_STORAGE_BYTES(1)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ekf_storage[NEUROV_EKF_STORAGE_BYTES];

/* An eight-thruster vectored layout (the BlueROV2 Heavy's topology). */
#define H 0.70710678f
static const float positions[3 * THRUSTERS] = {
    0.156f, 0.111f, 0.085f, 0.156f, -0.111f, 0.085f, -0.156f, 0.111f, 0.085f, -0.156f, -0.111f, 0.085f,
    0.120f, 0.218f, 0.0f,   0.120f, -0.218f, 0.0f,   -0.120f, 0.218f, 0.0f,   -0.120f, -0.218f, 0.0f};
static const float directions[3 * THRUSTERS] = {H, -H, 0, H, H, 0, H, H, 0, H, -H, 0,
                                                0, 0,  1, 0, 0, 1, 0, 0, 1, 0, 0,  1};
static const float min_thrust[THRUSTERS] = {-40, -40, -40, -40, -40, -40, -40, -40};
static const float max_thrust[THRUSTERS] = {50, 50, 50, 50, 50, 50, 50, 50};
/* A command table in PWM microseconds (shape only, not a manufacturer's data). */
static const float table_command[] = {1100, 1300, 1475, 1525, 1700, 1900};
static const float table_thrust[] = {-40, -15, 0, 0, 19, 51};

/* The wrench of thrusts u: sum over i of [d_i; r_i x d_i] u_i. */
static void wrench(const float* u, double w[6]) {
  for (int k = 0; k < 6; ++k) w[k] = 0.0;
  for (int i = 0; i < THRUSTERS; ++i) {
    const float* r = positions + 3 * i;
    const float* d = directions + 3 * i;
    const double m[3] = {r[1] * d[2] - r[2] * d[1], r[2] * d[0] - r[0] * d[2], r[0] * d[1] - r[1] * d[0]};
    for (int k = 0; k < 3; ++k) {
      w[k] += d[k] * u[i];
      w[3 + k] += m[k] * u[i];
    }
  }
}

static neurov_allocator* make_allocator(const neurov_thruster_curve* curve) {
  const neurov_allocator_params p =
      onboard_allocator_params(THRUSTERS, positions, directions, min_thrust, max_thrust, curve);
  neurov_allocator* a = NULL;
  neurov_validation_error e;
  CHECK(neurov_allocator_create(alloc_storage, sizeof alloc_storage, &p, &a, &e) == NEUROV_STATUS_OK);
  return a;
}

static void allocation(void) {
  CHECK(neurov_allocator_storage_size(1) <= sizeof alloc_storage);
  printf("allocator: %zu bytes with one curve (bound %u), %zu without\n",
         neurov_allocator_storage_size(1), (unsigned)NEUROV_ALLOCATOR_STORAGE_BYTES(1),
         neurov_allocator_storage_size(0));
  const neurov_thruster_curve curve = {6, table_command, table_thrust, 1500.0f, 25.0f, 16.0f, 2.0f};
  neurov_allocator* a = make_allocator(&curve);
  if (a == NULL) return;
  const float tau[6] = {20, -10, 15, 1.5f, -2, 3};
  float commands[THRUSTERS], u[THRUSTERS];
  CHECK(neurov_allocator_step(a, tau, 16.0f, commands, u) == NEUROV_STATUS_OK);
  double w[6];
  wrench(u, w);
  for (int k = 0; k < 6; ++k) CHECK(fabs(w[k] - tau[k]) < 1e-4 * 20.0);
  for (int i = 0; i < THRUSTERS; ++i) {
    CHECK(commands[i] >= 1100.0f && commands[i] <= 1900.0f);
    CHECK((u[i] > 0.0f) == (commands[i] > 1500.0f));
  }
  /* Refused: neutral commands, no thrust, then the same answer as before. */
  const float bad[6] = {NAN, 0, 0, 0, 0, 0};
  float c2[THRUSTERS], u2[THRUSTERS];
  CHECK(neurov_allocator_step(a, bad, 16.0f, c2, u2) == NEUROV_STATUS_NON_FINITE_INPUT);
  for (int i = 0; i < THRUSTERS; ++i) CHECK(c2[i] == 1500.0f && u2[i] == 0.0f);
  CHECK(neurov_allocator_step(a, tau, NAN, c2, u2) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(neurov_allocator_step(a, tau, 0.0f, c2, u2) == NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(neurov_allocator_status(a) == NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(neurov_allocator_step(a, tau, 16.0f, c2, u2) == NEUROV_STATUS_OK);
  CHECK(memcmp(c2, commands, sizeof c2) == 0 && memcmp(u2, u, sizeof u2) == 0);
  /* Far outside the attainable set: the wrench keeps its direction. */
  const float big[6] = {2000, -1000, 1500, 150, -200, 300};
  CHECK(neurov_allocator_step(a, big, 16.0f, c2, u2) == NEUROV_STATUS_OK);
  wrench(u2, w);
  double dot = 0, nw = 0, nt = 0;
  for (int k = 0; k < 6; ++k) {
    dot += w[k] * big[k];
    nw += w[k] * w[k];
    nt += (double)big[k] * big[k];
  }
  CHECK(dot / sqrt(nw * nt) > 1.0 - 1e-6);
  /* A bad layout is named. */
  const neurov_allocator_params p = onboard_allocator_params(
      THRUSTERS, positions, positions /* not unit vectors */, min_thrust, max_thrust, NULL);
  neurov_validation_error e;
  CHECK(neurov_allocator_create(alloc_storage, sizeof alloc_storage, &p, &a, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(a == NULL && e.field != NULL && strcmp(e.field, "thrusters.direction") == 0 && e.index == 0);
  CHECK(neurov_allocator_step((neurov_allocator*)(void*)alloc_storage, tau, 16.0f, c2, u2) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
}

static void estimator(void) {
  CHECK(neurov_ekf_storage_size() <= sizeof ekf_storage);
  printf("estimator: %zu bytes (bound %u)\n", neurov_ekf_storage_size(), (unsigned)NEUROV_EKF_STORAGE_BYTES);
  memset(ekf_storage, 0xCD, sizeof ekf_storage);
  CHECK(neurov_ekf_predict((neurov_ekf*)(void*)ekf_storage, 0.1f) == NEUROV_STATUS_INVALID_ARGUMENT);
  neurov_ekf_params p;
  memset(&p, 0, sizeof p);
  neurov_ekf* f = NULL;
  neurov_validation_error e;
  const float zero[6] = {0};
  CHECK(neurov_ekf_create(ekf_storage, sizeof ekf_storage, &p, zero, zero, &f, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(f == NULL && e.field != NULL && strcmp(e.field, "estimator.attitude_noise") == 0);
  p = onboard_ekf_params(1.0f);
  CHECK(neurov_ekf_create(ekf_storage, sizeof ekf_storage, &p, zero, zero, &f, &e) == NEUROV_STATUS_OK);
  if (f == NULL) return;
  /* A vehicle moving at 0.5 m/s in surge, 2 m deep: DVL and depth at 5 Hz. */
  for (int k = 0; k < 100; ++k) {
    const float dvl[3] = {0.5f, 0, 0}, att[3] = {0, 0, 0};
    CHECK(neurov_ekf_predict(f, 0.2f) == NEUROV_STATUS_OK);
    CHECK(neurov_ekf_update_dvl(f, dvl) == NEUROV_STATUS_OK);
    CHECK(neurov_ekf_update_attitude(f, att) == NEUROV_STATUS_OK);
    CHECK(neurov_ekf_update_depth(f, 2.0f) == NEUROV_STATUS_OK);
  }
  float eta[6], nu[6], var[NEUROV_EKF_STATES];
  neurov_ekf_estimate(f, eta, nu);
  CHECK(fabsf(nu[0] - 0.5f) < 1e-3f && fabsf(eta[2] - 2.0f) < 0.01f);
  CHECK(fabsf(eta[0] - 10.0f) < 0.2f); /* dead reckoning over 20 s */
  neurov_ekf_covariance_diagonal(f, var);
  /* A NaN measurement changes nothing. */
  const float nan3[3] = {NAN, 0, 0};
  float eta2[6], nu2[6], var2[NEUROV_EKF_STATES];
  CHECK(neurov_ekf_update_position(f, nan3, 0.5f) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(neurov_ekf_update_depth(f, NAN) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(neurov_ekf_status(f) == NEUROV_STATUS_NON_FINITE_INPUT);
  neurov_ekf_estimate(f, eta2, nu2);
  neurov_ekf_covariance_diagonal(f, var2);
  CHECK(memcmp(eta, eta2, sizeof eta) == 0 && memcmp(nu, nu2, sizeof nu) == 0);
  CHECK(memcmp(var, var2, sizeof var) == 0);
}

int main(void) {
  allocation();
  estimator();
  printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
