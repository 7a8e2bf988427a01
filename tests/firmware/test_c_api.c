/* The C interface from C: static storage sized by the header's constants,
 * validation errors as statuses, a closed loop, refusal of bad input, warm
 * start and reset. Exits non-zero on the first failed check. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "c_check.h"
#include "neurov/c_api.h"

#define N NEUROV_C_CENTRES

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char nn_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char ref_storage[NEUROV_REFERENCE_STORAGE_BYTES];
static float centres[N * NEUROV_C_INPUTS];
static float widths[N];
static float weights_before[6 * N], weights_after[6 * N];

static int field_is(const neurov_validation_error* e, const char* field) {
  return e->field != NULL && strcmp(e->field, field) == 0;
}

static void fill_centres(void) {
  uint32_t state = 2024u;
  for (int j = 0; j < N; ++j) {
    widths[j] = 30.0f;
    for (int i = 0; i < NEUROV_C_INPUTS; ++i) {
      state = state * 1664525u + 1013904223u;
      const float u = (float)(state >> 8) / 16777216.0f;
      centres[j * NEUROV_C_INPUTS + i] = (2.0f * u - 1.0f) * (i < 18 ? 1.0f : 3.0f);
    }
  }
}

/* The controller's default parameters on the centres of fill_centres(). */
static neurov_nn_params params_on_centres(void) {
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  p.centres = centres;
  p.widths = widths;
  return p;
}

static void sizes(void) {
  CHECK(neurov_nn_centres() == N);
  CHECK(neurov_nn_storage_size() > 0 && neurov_nn_storage_size() <= sizeof nn_storage);
  CHECK(neurov_nn_storage_size_n(N + 1) == 0); /* the library builds no other N */
  CHECK(neurov_reference_storage_size() <= sizeof ref_storage);
  CHECK(neurov_storage_align() <= NEUROV_STORAGE_ALIGN);
  CHECK(strcmp(neurov_status_name(NEUROV_STATUS_NON_FINITE_INPUT), "non_finite_input") == 0);
  printf("N = %d: controller %zu bytes (bound %u), reference model %zu bytes, align %zu\n", N,
         neurov_nn_storage_size(), (unsigned)NEUROV_NN_STORAGE_BYTES(N),
         neurov_reference_storage_size(), neurov_storage_align());
}

static void create_refuses_bad_arguments(void) {
  neurov_nn_params p = params_on_centres();
  neurov_nn* nn = (neurov_nn*)&p; /* must be overwritten with NULL */
  neurov_validation_error e;

  CHECK(neurov_nn_create(NULL, sizeof nn_storage, &p, &nn, &e) == NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(nn == NULL && field_is(&e, "storage"));
  CHECK(neurov_nn_create(nn_storage + 4, sizeof nn_storage - 4, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "storage"));
  CHECK(neurov_nn_create(nn_storage, neurov_nn_storage_size() - 1, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "size"));

  p.centres_count = N + 1;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "centres_count") && e.value == N + 1);
  /* Ahead of the size, which a caller of another N sizes for its N. */
  CHECK(neurov_nn_create(nn_storage, neurov_nn_storage_size() - 1, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "centres_count"));
  p.centres_count = N;

  p.dt = -0.2f;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "dt") && e.value == -0.2f);
  p.dt = 0.2f;

  p.modification = (neurov_modification)300;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "modification"));
  p.modification = NEUROV_MODIFICATION_PROJECTION; /* needs w_max > 0 */
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "w_max"));
  p.modification = NEUROV_MODIFICATION_NONE;

  widths[5] = NAN;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "widths") && e.index == 5 && e.expected != NULL);
  widths[5] = 30.0f;

  /* A bad entry of the row-major centre table is named by its index in it. */
  const float kept = centres[3 * NEUROV_C_INPUTS + 7];
  centres[3 * NEUROV_C_INPUTS + 7] = NAN;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(field_is(&e, "centres") && e.index == 3 * NEUROV_C_INPUTS + 7);
  centres[3 * NEUROV_C_INPUTS + 7] = kept;

  float tau[6] = {1, 1, 1, 1, 1, 1};
  const float zero[6] = {0};
  neurov_desired d;
  memset(&d, 0, sizeof d);
  CHECK(neurov_nn_step(NULL, zero, zero, &d, tau) == NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(tau[0] == 0.0f && tau[5] == 0.0f);

  neurov_reference* ref = NULL;
  const float ones[6] = {1, 1, 1, 1, 1, 1};
  CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, ones, zero, zero, &ref, &e) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(ref == NULL && field_is(&e, "omega") && e.index == 0);
}

/* Per DOF m x_ddot = tau - d x_dot: a stand-in plant, valid for the small
 * angles this run keeps (eta_dot = nu). */
static void plant_step(float eta[6], float nu[6], const float tau[6], float dt) {
  static const float m[6] = {215, 265, 265, 40, 80, 80};
  static const float damp[6] = {70, 100, 100, 30, 50, 50};
  for (int i = 0; i < 6; ++i) {
    nu[i] += dt * (tau[i] - damp[i] * nu[i]) / m[i];
    eta[i] += dt * nu[i];
  }
}

static void closed_loop(void) {
  neurov_nn_params p = params_on_centres();
  const float kd[6] = {200, 200, 200, 50, 50, 50};
  memcpy(p.kd, kd, sizeof kd);
  neurov_nn* nn = NULL;
  neurov_validation_error e;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &e) == NEUROV_STATUS_OK);
  CHECK(nn != NULL && e.field == NULL);
  if (nn == NULL) return;

  neurov_reference* ref = NULL;
  const float lambda_d[6] = {1, 1, 1, 1, 1, 1};
  const float omega[6] = {0.25f, 0.25f, 0.25f, 0.25f, 0.25f, 0.25f};
  float eta[6] = {0}, nu[6] = {0}, tau[6];
  CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, lambda_d, omega, eta, &ref, &e) ==
        NEUROV_STATUS_OK);
  if (ref == NULL) return;

  const float r[6] = {1.0f, -0.5f, 0.3f, 0.0f, 0.0f, 0.0f};
  neurov_desired d;
  int bad = 0;
  for (int k = 0; k < 300; ++k) { /* 60 s at 5 Hz, plant at 50 Hz */
    if (neurov_reference_step(ref, r, p.dt, &d) != NEUROV_STATUS_OK) ++bad;
    if (neurov_nn_step(nn, eta, nu, &d, tau) != NEUROV_STATUS_OK) ++bad;
    for (int i = 0; i < 10; ++i) plant_step(eta, nu, tau, p.dt / 10.0f);
  }
  CHECK(bad == 0);
  float err = 0.0f;
  for (int i = 0; i < 3; ++i) err += (eta[i] - r[i]) * (eta[i] - r[i]);
  err = sqrtf(err);
  CHECK(err < 0.05f);
  float eta_tilde[6], s[6];
  neurov_nn_tracking_error(nn, eta_tilde, s);
  CHECK(fabsf(eta_tilde[0] - (eta[0] - d.eta_d[0])) < 0.05f); /* eta has moved one period on */
  const float w_norm = neurov_nn_weight_norm(nn);
  CHECK(w_norm > 0.0f);
  printf("closed loop: |position error| after 60 s = %.2e m, ||W|| = %.3g\n", err, w_norm);

  /* A NaN measurement: refused, tau = 0, nothing changes. */
  neurov_nn_get_weights(nn, weights_before);
  float bad_nu[6];
  memcpy(bad_nu, nu, sizeof nu);
  bad_nu[2] = NAN;
  CHECK(neurov_nn_step(nn, eta, bad_nu, &d, tau) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(neurov_nn_status(nn) == NEUROV_STATUS_NON_FINITE_INPUT);
  for (int i = 0; i < 6; ++i) CHECK(tau[i] == 0.0f);
  neurov_nn_get_weights(nn, weights_after);
  CHECK(memcmp(weights_before, weights_after, sizeof weights_before) == 0);
  const float nan_r[6] = {NAN, 0, 0, 0, 0, 0};
  neurov_desired d2 = d;
  CHECK(neurov_reference_step(ref, nan_r, p.dt, &d2) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(memcmp(&d2, &d, sizeof d) == 0);

  /* Reset goes back to zero weights; a warm start makes the learnt ones initial. */
  neurov_nn_reset(nn);
  CHECK(neurov_nn_weight_norm(nn) == 0.0f && neurov_nn_status(nn) == NEUROV_STATUS_OK);
  CHECK(neurov_nn_set_initial_weights(nn, weights_before) == NEUROV_STATUS_OK);
  CHECK(fabsf(neurov_nn_weight_norm(nn) - w_norm) <= 1e-5f * w_norm);
  CHECK(neurov_nn_step(nn, eta, nu, &d, tau) == NEUROV_STATUS_OK);
  neurov_nn_reset(nn);
  CHECK(fabsf(neurov_nn_weight_norm(nn) - w_norm) <= 1e-5f * w_norm);
  weights_before[7] = INFINITY;
  CHECK(neurov_nn_set_initial_weights(nn, weights_before) == NEUROV_STATUS_NON_FINITE_INPUT);
  CHECK(fabsf(neurov_nn_weight_norm(nn) - w_norm) <= 1e-5f * w_norm);
}

/* Storage filled with a debugger's pattern, as a buffer create() never saw. */
static void fill_pattern(unsigned char* buf, size_t size, int deadbeef) {
  static const unsigned char beef[4] = {0xDE, 0xAD, 0xBE, 0xEF};
  for (size_t i = 0; i < size; ++i) buf[i] = deadbeef ? beef[i % 4] : 0xCD;
}

/* Every call on an object refuses a buffer that create() never saw, one
 * whose create() was refused, and the other kind of object. */
static void uncreated_objects_are_refused(void) {
  const float zero[6] = {0}, ones[6] = {1, 1, 1, 1, 1, 1};
  for (int pattern = 0; pattern < 4; ++pattern) {
    if (pattern < 2) {
      fill_pattern(nn_storage, sizeof nn_storage, pattern);
      fill_pattern(ref_storage, sizeof ref_storage, pattern);
    } else { /* a create refused for its parameters, on a buffer that held an object */
      neurov_nn_params p = params_on_centres();
      neurov_nn* made = NULL;
      neurov_reference* made_ref = NULL;
      CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &made, NULL) == NEUROV_STATUS_OK);
      CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, ones, ones, zero, &made_ref,
                                    NULL) == NEUROV_STATUS_OK);
      if (pattern == 2)
        p.gamma = -1.0f;
      else
        p.centres_count = N + 1; /* refused before the other checks */
      CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &made, NULL) ==
            NEUROV_STATUS_INVALID_ARGUMENT);
      CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, ones, zero, zero, &made_ref,
                                    NULL) == NEUROV_STATUS_INVALID_ARGUMENT);
    }
    neurov_nn* nn = (neurov_nn*)nn_storage;
    neurov_reference* ref = (neurov_reference*)ref_storage;
    neurov_desired d;
    memset(&d, 0, sizeof d);
    float tau[6] = {1, 1, 1, 1, 1, 1}, et[6] = {1, 1, 1, 1, 1, 1}, s[6] = {1, 1, 1, 1, 1, 1};
    CHECK(neurov_nn_step(nn, zero, zero, &d, tau) == NEUROV_STATUS_INVALID_ARGUMENT);
    for (int i = 0; i < 6; ++i) CHECK(tau[i] == 0.0f);
    CHECK(neurov_nn_status(nn) == NEUROV_STATUS_INVALID_ARGUMENT);
    CHECK(neurov_nn_weight_norm(nn) == 0.0f);
    neurov_nn_tracking_error(nn, et, s);
    for (int i = 0; i < 6; ++i) CHECK(et[i] == 0.0f && s[i] == 0.0f);
    weights_after[0] = 42.0f;
    neurov_nn_get_weights(nn, weights_after);
    CHECK(weights_after[0] == 42.0f);
    memset(weights_before, 0, sizeof weights_before);
    CHECK(neurov_nn_set_initial_weights(nn, weights_before) == NEUROV_STATUS_INVALID_ARGUMENT);
    unsigned char kept[sizeof nn_storage];
    memcpy(kept, nn_storage, sizeof kept);
    neurov_nn_reset(nn);
    CHECK(memcmp(kept, nn_storage, sizeof kept) == 0);
    CHECK(neurov_reference_step(ref, zero, 0.2f, &d) == NEUROV_STATUS_INVALID_ARGUMENT);
    CHECK(neurov_reference_reset(ref, zero) == NEUROV_STATUS_INVALID_ARGUMENT);
    /* The other kind of object, however it got there. */
    CHECK(neurov_nn_step((neurov_nn*)(void*)ref, zero, zero, &d, tau) ==
          NEUROV_STATUS_INVALID_ARGUMENT);
    CHECK(neurov_reference_step((neurov_reference*)(void*)nn, zero, 0.2f, &d) ==
          NEUROV_STATUS_INVALID_ARGUMENT);
  }
  /* A real object of each kind is still refused in the other's calls. */
  neurov_nn_params p = params_on_centres();
  neurov_nn* nn = NULL;
  neurov_reference* ref = NULL;
  CHECK(neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, NULL) == NEUROV_STATUS_OK);
  CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, ones, ones, zero, &ref, NULL) ==
        NEUROV_STATUS_OK);
  neurov_desired d;
  float tau[6];
  CHECK(neurov_reference_step((neurov_reference*)(void*)nn, zero, 0.2f, &d) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  memset(&d, 0, sizeof d);
  CHECK(neurov_nn_step((neurov_nn*)(void*)ref, zero, zero, &d, tau) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
}

/* A step longer than the documented maximum (10 s) is an invalid argument,
 * not a non-finite input, and changes nothing. */
static void absurd_step_is_refused(void) {
  const float zero[6] = {0}, ones[6] = {1, 1, 1, 1, 1, 1}, r[6] = {1, 0, 0, 0, 0, 0};
  neurov_reference* ref = NULL;
  CHECK(neurov_reference_create(ref_storage, sizeof ref_storage, ones, ones, zero, &ref, NULL) ==
        NEUROV_STATUS_OK);
  if (ref == NULL) return;
  neurov_desired d, before;
  CHECK(neurov_reference_step(ref, r, 0.2f, &d) == NEUROV_STATUS_OK);
  before = d;
  const float steps[3] = {1e30f, 1e6f, 10.5f};
  for (int i = 0; i < 3; ++i) {
    CHECK(neurov_reference_step(ref, r, steps[i], &d) == NEUROV_STATUS_INVALID_ARGUMENT);
    CHECK(memcmp(&d, &before, sizeof d) == 0);
  }
  CHECK(neurov_reference_step(ref, r, 10.0f, &d) == NEUROV_STATUS_OK);
}

int main(void) {
  fill_centres();
  sizes();
  create_refuses_bad_arguments();
  uncreated_objects_are_refused();
  absurd_step_is_refused();
  closed_loop();
  printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
