/* neurov's C interface, for firmware written in C.
 *
 * The RBF neural-network adaptive controller (float, a number of centres N
 * fixed when the library neurov_c was built: NEUROV_C_CENTRES), the
 * reference model, the thrust allocation with the inverse thrust curves and
 * the state estimator, each living in a buffer the caller provides. Nothing here
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

/* The caller's N, which must be the one the library was built with. The
 * CMake target defines it for its users; a build without CMake must pass the
 * same -DNEUROV_C_CENTRES=N. neurov_nn_params_init() (a macro) hands this
 * value to the library, which refuses any other in neurov_nn_create()
 * (params.centres_count), so a caller compiled with another N is stopped
 * before the library reads its N-sized arrays. */
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
  uint32_t centres_count;    /* the caller's N (set by _init); must be neurov_nn_centres() */
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

/* The storage query and the initialiser depend on the caller's N, so they
 * are macros over functions that take it: each macro passes the
 * NEUROV_C_CENTRES this header was compiled with. (Through a foreign-function
 * interface, which sees no macros, call the _n functions with the N the
 * arrays are sized for.) */
uint32_t neurov_nn_centres(void);  /* N built into the library */
size_t neurov_storage_align(void); /* required alignment, <= NEUROV_STORAGE_ALIGN */

/* Exact bytes of a controller of `centres` centres, <= NEUROV_NN_STORAGE_BYTES(centres);
 * 0 when `centres` is not the library's N (it builds no other). */
size_t neurov_nn_storage_size_n(uint32_t centres);
#define neurov_nn_storage_size() neurov_nn_storage_size_n(NEUROV_C_CENTRES)

/* The C++ defaults (lambda 0.5, K_d 0, gamma 0.3, dt 0.2, no modification),
 * NULL arrays and centres_count = `centres`, the caller's N. */
void neurov_nn_params_init_n(neurov_nn_params* params, uint32_t centres);
#define neurov_nn_params_init(params) neurov_nn_params_init_n((params), NEUROV_C_CENTRES)

/* Builds a controller inside `storage` (size bytes, aligned to
 * neurov_storage_align()) with zero initial weights and sets *out. On failure
 * returns NEUROV_STATUS_INVALID_ARGUMENT, sets *out = NULL and, if `error` is
 * not NULL, says which field is wrong. A centres_count other than the
 * library's N is refused (field "centres_count") after the pointer checks,
 * before the size check and without reading the arrays. Copies the arrays;
 * they need not outlive the call. Uses about 24 N floats of stack for the copy of the centres. */
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

/* ---- thrust allocation with the inverse thrust curve ------------------- */

/* Most thrusters an allocator takes (the BlueROV2 Heavy has 8). */
#define NEUROV_C_MAX_THRUSTERS 8
/* Most rows of a thrust-curve table (neurov::kThrusterCurveCapacity). */
#define NEUROV_C_CURVE_POINTS 256
/* Storage of an allocator with `curves` distinct curves, an upper bound as a
 * compile-time constant (the exact size: neurov_allocator_storage_size()):
 * 1 KiB for the layout and pseudo-inverse, 2.1 KiB per curve table. */
#define NEUROV_ALLOCATOR_STORAGE_BYTES(curves) (1024u + 2112u * (unsigned)(curves))

/* How a wrench beyond the thrusters' reach is cut down. */
typedef enum neurov_saturation {
  /* One factor for all thrusters: the wrench keeps its direction. */
  NEUROV_SATURATION_SCALE = 0,
  /* Each thruster clipped to its limits: the wrench may turn. */
  NEUROV_SATURATION_CLIP = 1
} neurov_saturation;

/* A thruster's static curve, command -> thrust at reference_voltage: a table
 * (linearly interpolated; commands strictly increasing, in any unit, e.g.
 * PWM us), a dead band around the neutral command, and thrust scaling as
 * (voltage / reference_voltage)^voltage_exponent. Outside the dead band the
 * thrust must rise strictly with the command (reverse thrusts below neutral,
 * forward above), so that it can be inverted. */
typedef struct neurov_thruster_curve {
  uint32_t points;       /* rows, 2..NEUROV_C_CURVE_POINTS */
  const float* command;  /* `points` commands */
  const float* thrust;   /* `points` thrusts [N] */
  float neutral;         /* command of zero thrust, inside the table */
  float dead_band;       /* half-width around neutral (>= 0) */
  float reference_voltage; /* [V] of the table (> 0) */
  float voltage_exponent;  /* (>= 0; 2: thrust ~ speed^2 ~ voltage^2) */
} neurov_thruster_curve;

/* The thruster layout; fill with neurov_allocator_params_init() first. */
typedef struct neurov_allocator_params {
  uint32_t thrusters;       /* n, 6..NEUROV_C_MAX_THRUSTERS */
  /* Either B (6 x n, row-major: row k = DOF k, tau = B u) ... */
  const float* matrix;
  /* ... or, with matrix NULL, each thruster's position r (n x 3, body axes,
   * m) and unit thrust direction d (n x 3): column i of B = [d; r x d]. */
  const float* positions;
  const float* directions;
  const float* min_thrust;  /* n limits [N], <= 0 */
  const float* max_thrust;  /* n limits [N], >= 0, > min */
  const float* weights;     /* n allocation weights (> 0), or NULL for 1 */
  neurov_saturation saturation;
  /* 0: the commands are the thrusts [N]. Otherwise `curves` holds
   * curve_count tables and thruster i uses curves[curve_of[i]]; curve_of may
   * be NULL when curve_count is 1 (one curve for all) or n (curve i). */
  uint32_t curve_count;
  const neurov_thruster_curve* curves;
  const uint8_t* curve_of;
} neurov_allocator_params;

typedef struct neurov_allocator neurov_allocator; /* lives in the caller's buffer */

/* Zero arrays, scale saturation, no curves. */
void neurov_allocator_params_init(neurov_allocator_params* params);

/* Exact bytes for an allocator with `curve_count` curves
 * (<= NEUROV_ALLOCATOR_STORAGE_BYTES(curve_count)); 0 for more than
 * NEUROV_C_MAX_THRUSTERS curves. */
size_t neurov_allocator_storage_size(uint32_t curve_count);

/* Builds an allocator in `storage`: checks the layout (B of rank 6, the
 * limits, each curve) and computes the weighted pseudo-inverse
 * u = W^-1 B^T (B W^-1 B^T)^-1 tau. Copies the arrays. Errors as for
 * neurov_nn_create(). */
neurov_status neurov_allocator_create(void* storage, size_t size,
                                      const neurov_allocator_params* params,
                                      neurov_allocator** out, neurov_validation_error* error);

/* tau (6) -> thrusts u (n, may be NULL) -> commands (n): the pseudo-inverse,
 * each thrust limited to [min, max] and to what its curve yields at
 * `voltage` [V], the saturation law, then the inverse curve (a thrust inside
 * the dead band's jump gives the band's edge; 0 gives neutral). `voltage` is
 * read only when there are curves. On any status but OK the thrusts are 0
 * and every command is its neutral one (0 without a curve):
 * NON_FINITE_INPUT for NaN/Inf in tau or the voltage, INVALID_ARGUMENT for a
 * voltage <= 0 or a bad pointer. */
neurov_status neurov_allocator_step(neurov_allocator* alloc, const float tau[6], float voltage,
                                    float* commands, float* thrusts);

/* n of the allocator (0 for a bad pointer). */
uint32_t neurov_allocator_thrusters(const neurov_allocator* alloc);

/* Status of the last step (OK before the first). */
neurov_status neurov_allocator_status(const neurov_allocator* alloc);

/* ---- state estimator: extended Kalman filter (15 states) -------------- */

/* State x = [position (NED, 3), attitude (phi, theta, psi), body velocity
 * (u, v, w), body rates (p, q, r), gyro bias (3)]. The prediction is
 * kinematic (velocities as random walks), so it needs neither tau nor the
 * vehicle's coefficients. */
#define NEUROV_EKF_STATES 15
#define NEUROV_EKF_STORAGE_BYTES 2048u

/* Every field must be set (no defaults: they belong to the sensors). */
typedef struct neurov_ekf_params {
  float linear_acceleration_noise;  /* [m/s^2/sqrt(Hz)], >= 0 */
  float angular_acceleration_noise; /* [rad/s^2/sqrt(Hz)], >= 0 */
  float gyro_bias_walk;             /* [rad/s/sqrt(s)], >= 0 */
  float attitude_noise;             /* std of the AHRS attitude [rad], > 0 */
  float gyro_noise;                 /* std of the gyro [rad/s], > 0 */
  float dvl_noise;                  /* std of the DVL per axis [m/s], > 0 */
  float depth_noise;                /* std of the depth [m], > 0 */
  float position_noise;             /* std of an acoustic fix per axis [m], > 0 */
  float initial_std[NEUROV_EKF_STATES]; /* std of the initial estimate, > 0 */
} neurov_ekf_params;

typedef struct neurov_ekf neurov_ekf; /* lives in the caller's buffer */

size_t neurov_ekf_storage_size(void); /* <= NEUROV_EKF_STORAGE_BYTES */

/* Starts at (eta0, nu0), zero gyro bias, covariance diag(initial_std^2). */
neurov_status neurov_ekf_create(void* storage, size_t size, const neurov_ekf_params* params,
                                const float eta0[6], const float nu0[6], neurov_ekf** out,
                                neurov_validation_error* error);

/* Back to (eta0, nu0) as create() started; NON_FINITE_INPUT (unchanged) for NaN/Inf. */
neurov_status neurov_ekf_reset(neurov_ekf* ekf, const float eta0[6], const float nu0[6]);

/* Propagates by dt in (0, 10] s. Each update fuses one measurement when the
 * sensor delivers it. On any status but OK (and NEAR_SINGULARITY, which
 * predict() reports for a pitch near +-90 deg and still applies) the
 * estimate and covariance are exactly as before: NON_FINITE_INPUT for
 * NaN/Inf, INVALID_ARGUMENT for a bad pointer or dt, NON_FINITE_OUTPUT when
 * the update would overflow. */
neurov_status neurov_ekf_predict(neurov_ekf* ekf, float dt);
neurov_status neurov_ekf_update_attitude(neurov_ekf* ekf, const float attitude[3]); /* AHRS */
neurov_status neurov_ekf_update_gyro(neurov_ekf* ekf, const float rates[3]);       /* p, q, r */
neurov_status neurov_ekf_update_dvl(neurov_ekf* ekf, const float velocity[3]);     /* u, v, w */
neurov_status neurov_ekf_update_depth(neurov_ekf* ekf, float depth);               /* z, down */
/* An acoustic (USBL) fix [x, y, z] taken `age` seconds ago (0..10). */
neurov_status neurov_ekf_update_position(neurov_ekf* ekf, const float position[3], float age);

/* The estimate (either pointer may be NULL); zeros for a bad pointer. */
void neurov_ekf_estimate(const neurov_ekf* ekf, float eta[6], float nu[6]);
/* The 15 variances of the covariance diagonal (order of the state). */
void neurov_ekf_covariance_diagonal(const neurov_ekf* ekf, float variance[NEUROV_EKF_STATES]);
/* The estimated gyro bias [rad/s]. */
void neurov_ekf_gyro_bias(const neurov_ekf* ekf, float bias[3]);
/* Status of the last call that changed or refused to change the estimate. */
neurov_status neurov_ekf_status(const neurov_ekf* ekf);

#ifdef __cplusplus
}
#endif

#endif /* NEUROV_C_API_H */
