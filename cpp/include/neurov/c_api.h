/* neurov's C interface, for firmware written in C.
 *
 * The RBF neural-network adaptive controller (float, a number of centres N
 * fixed when the library neurov_c was built: NEUROV_C_CENTRES) and the
 * reference model, each living in a buffer the caller provides. Nothing here
 * allocates, throws or blocks: create() builds the object inside the buffer,
 * step() runs in bounded time, and there is no destroy (the buffer is plain
 * memory; call create() on it again to start over).
 *
 * Arrays are float[6] in the paper's order: eta = [x, y, z, phi, theta, psi]
 * (NED position, ZYX Euler angles), nu = [u, v, w, p, q, r] (body velocity),
 * tau = body forces and moments.
 *
 * Every call on an object treats a pointer that create() did not hand out
 * (a buffer never passed to create, one whose create was refused, the other
 * kind of object) as it treats NULL: INVALID_ARGUMENT and zero outputs, or
 * nothing done. create() writes a canary into the object last and every call
 * checks it. A refused create() leaves no object in a usable buffer (not
 * NULL, aligned, large enough), whatever it held before.
 *
 * Link neurov::neurov_c with CMake; it carries the NEUROV_C_CENTRES the
 * library was built with. docs/firmware.md has the details.
 */
#ifndef NEUROV_C_API_H
#define NEUROV_C_API_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* N the library was built with. The CMake target defines it for its users;
 * a build without CMake must pass the same -DNEUROV_C_CENTRES=N, and
 * neurov_nn_create() refuses a mismatch (params.centres_count). */
#ifndef NEUROV_C_CENTRES
#define NEUROV_C_CENTRES 64
#endif

/* Network inputs: x = [nu_r_dot; nu_r; nu; eta] (eq. 35 of the paper). */
#define NEUROV_C_INPUTS 24

/* Storage an object needs, in bytes, as compile-time constants so the
 * buffers can be static. An upper bound: float storage of
 *   N (n_in + 16) + 2 n_in + 108 values (n_in = 24 inputs), plus alignment slack;
 * the library checks at compile time that its objects fit. The exact sizes are
 * neurov_nn_storage_size() and neurov_reference_storage_size(). */
#define NEUROV_NN_STORAGE_BYTES(n)                                                   \
  (4u * ((unsigned)(n) * (NEUROV_C_INPUTS + 16u) + 2u * NEUROV_C_INPUTS + 108u) + 128u)
#define NEUROV_REFERENCE_STORAGE_BYTES 256u
/* Alignment every storage buffer must have (Eigen's fixed-size matrices). */
#ifndef NEUROV_STORAGE_ALIGN
#define NEUROV_STORAGE_ALIGN 16u
#endif

/* The same codes and values as neurov::Status in C++. */
typedef enum neurov_status {
  NEUROV_STATUS_OK = 0,
  /* |cos(theta)| near 0: pitch at +-90 deg, where the Euler transform is singular. */
  NEUROV_STATUS_NEAR_SINGULARITY = 1,
  /* An input held NaN or +-Inf. */
  NEUROV_STATUS_NON_FINITE_INPUT = 2,
  /* An argument was wrong: NULL pointer, bad size, invalid configuration. */
  NEUROV_STATUS_INVALID_ARGUMENT = 3,
  /* Finite inputs overflowed; the outputs were replaced by safe values. */
  NEUROV_STATUS_NON_FINITE_OUTPUT = 4
} neurov_status;

/* Robust modification of the adaptive law (none: the paper's pure gradient). */
typedef enum neurov_modification {
  NEUROV_MODIFICATION_NONE = 0,
  NEUROV_MODIFICATION_SIGMA = 1,
  NEUROV_MODIFICATION_E_MODIFICATION = 2,
  NEUROV_MODIFICATION_PROJECTION = 3
} neurov_modification;

/* Why a create() refused its arguments. The strings are static. */
typedef struct neurov_validation_error {
  const char* field;    /* offending field, NULL when valid */
  int index;            /* element index within the field, or -1 */
  double value;         /* offending value (NaN for a whole matrix) */
  const char* expected; /* what the field must satisfy */
} neurov_validation_error;

/* The desired trajectory at one instant (earth frame). */
typedef struct neurov_desired {
  float eta_d[6];
  float eta_d_dot[6];
  float eta_d_ddot[6];
} neurov_desired;

/* Configuration of the NN controller; fill with neurov_nn_params_init() first. */
typedef struct neurov_nn_params {
  uint32_t centres_count;    /* must be NEUROV_C_CENTRES (set by _init) */
  const float* centres;      /* N x 24, row-major: centre j is centres[24 j .. 24 j + 23] */
  const float* widths;       /* N widths sigma_j (> 0) */
  const float* input_offset; /* 24 values, or NULL for 0 */
  const float* input_scale;  /* 24 values (> 0), or NULL for 1 */
  float lambda[6];           /* Lambda of s = eta_tilde_dot + Lambda eta_tilde (> 0) */
  float kd[6];               /* K_d (>= 0) */
  float gamma;               /* learning rate (the paper: 0.3) */
  float dt;                  /* control period [s] (the paper: 0.2) */
  neurov_modification modification;
  float sigma_m;   /* sigma-modification leakage (> 0 when used) */
  float kappa;     /* e-modification gain (> 0 when used) */
  float w_max;     /* projection bound on ||W||_F (> 0 when used) */
  float dead_zone; /* no adaptation while ||s|| < dead_zone (0: off) */
} neurov_nn_params;

typedef struct neurov_nn neurov_nn;               /* lives in the caller's buffer */
typedef struct neurov_reference neurov_reference; /* likewise */

/* "ok", "near_singularity", ...: stable names for logs. */
const char* neurov_status_name(neurov_status status);

/* ---- NN adaptive controller ------------------------------------------- */

uint32_t neurov_nn_centres(void);     /* N built into the library */
size_t neurov_nn_storage_size(void);  /* exact bytes, <= NEUROV_NN_STORAGE_BYTES(N) */
size_t neurov_storage_align(void);    /* required alignment, <= NEUROV_STORAGE_ALIGN */

/* The C++ defaults (lambda 0.5, K_d 0, gamma 0.3, dt 0.2, no modification),
 * centres_count = N and NULL arrays. */
void neurov_nn_params_init(neurov_nn_params* params);

/* Builds a controller inside `storage` (size bytes, aligned to
 * neurov_storage_align()) with zero initial weights and sets *out. On failure
 * returns NEUROV_STATUS_INVALID_ARGUMENT, sets *out = NULL and, if `error` is
 * not NULL, says which field is wrong. Copies the arrays; they need not
 * outlive the call. Uses about 24 N floats of stack for the copy of the centres. */
neurov_status neurov_nn_create(void* storage, size_t size, const neurov_nn_params* params,
                               neurov_nn** out, neurov_validation_error* error);

/* tau = W g(x) - J^T K_d s and one step of the adaptive law. On any status
 * but OK, tau = 0 and the controller is exactly as before the call. */
neurov_status neurov_nn_step(neurov_nn* nn, const float eta[6], const float nu[6],
                             const neurov_desired* desired, float tau[6]);

/* Status of the last step (OK before the first). */
neurov_status neurov_nn_status(const neurov_nn* nn);

/* Back to the initial weights (zero, or the last neurov_nn_set_initial_weights)
 * and a zero history. */
void neurov_nn_reset(neurov_nn* nn);

/* eta_tilde = eta - eta_d and s of the last accepted step (either may be NULL). */
void neurov_nn_tracking_error(const neurov_nn* nn, float eta_tilde[6], float s[6]);

/* ||W||_F, to watch the weights for drift. */
float neurov_nn_weight_norm(const neurov_nn* nn);

/* The 6 x N weights, row-major (to save what was learnt). */
void neurov_nn_get_weights(const neurov_nn* nn, float* weights);

/* Warm start: replaces the weights (6 x N, row-major), makes them the ones
 * reset() returns to, and resets the history as reset() does.
 * INVALID_ARGUMENT / NON_FINITE_INPUT leave the controller unchanged. */
neurov_status neurov_nn_set_initial_weights(neurov_nn* nn, const float* weights);

/* ---- reference model (eq. 12-13) ------------------------------------- */

size_t neurov_reference_storage_size(void); /* <= NEUROV_REFERENCE_STORAGE_BYTES */

/* Damping lambda_d (> 0) and stiffness omega (> 0) per DOF, at rest at eta0. */
neurov_status neurov_reference_create(void* storage, size_t size, const float lambda_d[6],
                                      const float omega[6], const float eta0[6],
                                      neurov_reference** out, neurov_validation_error* error);

/* Advances by dt towards the commanded pose r and writes the desired state.
 * On any status but OK the model keeps its state and `out` gets the last good
 * desired state. */
neurov_status neurov_reference_step(neurov_reference* ref, const float r[6], float dt,
                                    neurov_desired* out);

/* Back to rest at eta0; NON_FINITE_INPUT (unchanged) for NaN/Inf. */
neurov_status neurov_reference_reset(neurov_reference* ref, const float eta0[6]);

#ifdef __cplusplus
}
#endif

#endif /* NEUROV_C_API_H */
