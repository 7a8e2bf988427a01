/* A caller built with another N than the library (NEUROV_C_CENTRES here is
 * not NEUROV_TEST_LIBRARY_CENTRES, the library's N; tests/firmware/CMakeLists.txt
 * builds this file for half and twice the library's N and links the library
 * without the definition neurov::neurov_c carries, as a build without CMake
 * does). neurov_nn_create() must refuse it naming centres_count, both with
 * storage sized for the caller's N and with storage large enough for the
 * library's, and must not read its arrays: they are followed by NaN, so a
 * read past them would show as a refusal of `centres` or `widths` (or, were
 * the NaN not checked, as a controller built from memory that is not the
 * caller's). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "c_check.h"
#include "neurov/c_api.h"

#define N NEUROV_C_CENTRES
#define LIBRARY_N NEUROV_TEST_LIBRARY_CENTRES
/* Floats past the caller's arrays that a library of LIBRARY_N would read. */
#define BEYOND (LIBRARY_N > N ? LIBRARY_N - N : 1)

/* One object, so that what follows each array is known memory. */
static struct {
  float centres[N * NEUROV_C_INPUTS];
  float after_centres[BEYOND * NEUROV_C_INPUTS];
  float widths[N];
  float after_widths[BEYOND];
} caller;

/* Storage for the caller's own N, and storage the library's object fits in. */
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char own_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char large_storage[NEUROV_NN_STORAGE_BYTES(
    LIBRARY_N > N ? LIBRARY_N : N)];

static int field_is(const neurov_validation_error* e, const char* field) {
  return e->field != NULL && strcmp(e->field, field) == 0;
}

static void fill_arrays(void) {
  for (int j = 0; j < N; ++j) {
    caller.widths[j] = 2.0f;
    for (int i = 0; i < NEUROV_C_INPUTS; ++i)
      caller.centres[j * NEUROV_C_INPUTS + i] = (float)((j * 7 + i * 3) % 11 - 5) / 5.0f;
  }
  for (int k = 0; k < BEYOND * NEUROV_C_INPUTS; ++k) caller.after_centres[k] = NAN;
  for (int k = 0; k < BEYOND; ++k) caller.after_widths[k] = NAN;
}

static void refused(unsigned char* storage, size_t size, const char* which) {
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  CHECK(p.centres_count == (uint32_t)N); /* the caller's N, not the library's */
  p.centres = caller.centres;
  p.widths = caller.widths;
  neurov_nn* nn = (neurov_nn*)(void*)storage; /* must become NULL */
  neurov_validation_error e;
  const neurov_status s = neurov_nn_create(storage, size, &p, &nn, &e);
  printf("N = %d against a library of %u, %s storage (%zu bytes): %s, field %s = %g, expected %s\n",
         N, (unsigned)neurov_nn_centres(), which, size, neurov_status_name(s),
         e.field != NULL ? e.field : "(none)", e.value, e.expected != NULL ? e.expected : "(none)");
  CHECK(s == NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(nn == NULL);
  CHECK(field_is(&e, "centres_count") && e.value == (double)N && e.expected != NULL);
  /* Whatever create did, the buffer holds no object a call would use. */
  float tau[6] = {1, 1, 1, 1, 1, 1};
  const float zero[6] = {0};
  neurov_desired d;
  memset(&d, 0, sizeof d);
  CHECK(neurov_nn_step((neurov_nn*)(void*)storage, zero, zero, &d, tau) ==
        NEUROV_STATUS_INVALID_ARGUMENT);
  CHECK(tau[0] == 0.0f);
}

int main(void) {
  CHECK(N != LIBRARY_N); /* else this program tests nothing */
  CHECK(neurov_nn_centres() == (uint32_t)LIBRARY_N);
  /* No object of the caller's N exists in this library: no size for it. */
  CHECK(neurov_nn_storage_size() == 0);
  fill_arrays();
  refused(own_storage, sizeof own_storage, "its own N's");
  refused(large_storage, sizeof large_storage, "the library's N's");
  printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
