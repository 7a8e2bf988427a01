/* The processor-in-the-loop task: the firmware's side of `neurov pil`. The
 * host sends the controller's parameters once (PIL_CONFIG) and then, every
 * control period, the measured state and the desired trajectory
 * (PIL_MEASUREMENT); the board runs the NN controller and, with thrusters,
 * the thrust allocation of neurov_c and answers with the command
 * (PIL_COMMAND). Whatever the link delivers, the board answers with a safe
 * command (zero force, zero thrust) and says why: a refused frame, a
 * measurement out of range, or none within the watchdog period. The frame
 * layouts are those of python/neurov/pil/framing.py. Every object is static;
 * nothing allocates. */
#include <math.h>
#include <string.h>

#include "board.h"
#include "neurov/c_api.h"
#include "pil_frame.h"

#define N NEUROV_C_CENTRES
#define IN NEUROV_C_INPUTS

/* A deliberate change of the firmware's gains (K_d times this), to show that
 * the comparison with the host would notice one: tests build an image with
 * -DPIL_KD_SCALE=1.01f. */
#ifndef PIL_KD_SCALE
#define PIL_KD_SCALE 1.0f
#endif

static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char nn_storage[NEUROV_NN_STORAGE_BYTES(N)];
static _Alignas(NEUROV_STORAGE_ALIGN) unsigned char alloc_storage[NEUROV_ALLOCATOR_STORAGE_BYTES(0)];
static pil_parser parser;
static neurov_nn* nn;
static neurov_allocator* alloc;
static uint32_t thrusters, watchdog_ticks;
static float limits[4]; /* |x|,|y|,|z| [m]; |roll|,|pitch| [rad]; |u|,|v|,|w| [m/s]; |p|,|q|,|r| [rad/s] */
static uint32_t measurements, bad_frames, timeouts, out_of_range, max_step_ticks;

typedef struct reader {
  const uint8_t* at;
  const uint8_t* end;
} reader;

static uint32_t get_u32(reader* r) {
  uint32_t v = 0;
  if (r->at + 4 <= r->end) memcpy(&v, r->at, 4);
  r->at += 4;
  return v;
}

static float get_f32(reader* r) {
  float v = 0.0f;
  if (r->at + 4 <= r->end) memcpy(&v, r->at, 4);
  r->at += 4;
  return v;
}

static void get_floats(reader* r, float* out, uint32_t n) {
  for (uint32_t i = 0; i < n; ++i) out[i] = get_f32(r);
}

static void put(uint8_t** at, const void* v, uint32_t bytes) {
  memcpy(*at, v, bytes);
  *at += bytes;
}

static void ack(uint32_t status, const neurov_validation_error* e) {
  uint8_t out[32] = {0};
  uint8_t* at = out;
  const int32_t index = e != 0 && e->field != 0 ? e->index : -1;
  put(&at, &status, 4);
  put(&at, &index, 4);
  if (e != 0 && e->field != 0) strncpy((char*)at, e->field, 23);
  pil_send(PIL_ACK, out, sizeof out);
}

/* PIL_CONFIG: u32 N, thrusters, watchdog [ms], modification, saturation;
 * f32 dt, gamma, sigma_m, kappa, w_max, dead_zone, lambda[6], kd[6],
 * limits[4]; widths[N], input_offset[24], input_scale[24], centres[N x 24];
 * with thrusters n: B[6 x n] row-major, min_thrust[n], max_thrust[n]. */
static void configure(const uint8_t* payload, uint32_t length) {
  /* Kept between configurations, and too large for the stack. */
  static float widths[N], offset[IN], scale[IN], centres[N * IN];
  static float matrix[6 * NEUROV_C_MAX_THRUSTERS], lo[NEUROV_C_MAX_THRUSTERS], hi[NEUROV_C_MAX_THRUSTERS];
  reader r = {payload, payload + length};
  neurov_nn_params p;
  neurov_nn_params_init(&p);
  p.centres_count = get_u32(&r);
  const uint32_t n = get_u32(&r);
  const uint32_t watchdog_ms = get_u32(&r);
  p.modification = (neurov_modification)get_u32(&r);
  const uint32_t saturation = get_u32(&r);
  p.dt = get_f32(&r);
  p.gamma = get_f32(&r);
  p.sigma_m = get_f32(&r);
  p.kappa = get_f32(&r);
  p.w_max = get_f32(&r);
  p.dead_zone = get_f32(&r);
  get_floats(&r, p.lambda, 6);
  get_floats(&r, p.kd, 6);
  for (int i = 0; i < 6; ++i) p.kd[i] *= PIL_KD_SCALE;
  get_floats(&r, limits, 4);
  const uint32_t centres_count = p.centres_count == N ? N : 0u;
  get_floats(&r, widths, centres_count);
  get_floats(&r, offset, IN);
  get_floats(&r, scale, IN);
  get_floats(&r, centres, centres_count * IN);
  const uint32_t used = n <= NEUROV_C_MAX_THRUSTERS ? n : 0u;
  get_floats(&r, matrix, 6 * used);
  get_floats(&r, lo, used);
  get_floats(&r, hi, used);
  nn = 0;
  alloc = 0;
  neurov_validation_error error = {0, -1, 0.0, 0};
  if (r.at != r.end) {
    error.field = "length";
    ack(NEUROV_STATUS_INVALID_ARGUMENT, &error);
    return;
  }
  p.centres = centres;
  p.widths = widths;
  p.input_offset = offset;
  p.input_scale = scale;
  neurov_status s = neurov_nn_create(nn_storage, sizeof nn_storage, &p, &nn, &error);
  if (s == NEUROV_STATUS_OK && n > 0) {
    neurov_allocator_params a;
    neurov_allocator_params_init(&a);
    a.thrusters = n;
    a.matrix = matrix;
    a.min_thrust = lo;
    a.max_thrust = hi;
    a.saturation = (neurov_saturation)saturation;
    s = neurov_allocator_create(alloc_storage, sizeof alloc_storage, &a, &alloc, &error);
    if (s != NEUROV_STATUS_OK) nn = 0;
  }
  thrusters = s == NEUROV_STATUS_OK ? n : 0u;
  watchdog_ticks = watchdog_ms * (board_tick_hz() / 1000u);
  measurements = bad_frames = timeouts = out_of_range = max_step_ticks = 0;
  ack(s, &error);
}

/* The answer: u32 seq; u8 status, fault, thrusters, 0; u32 ticks of the
 * step; f32 tau[6], s[6], thrust[thrusters]. */
static void answer(uint32_t seq, uint32_t status, uint32_t fault, uint32_t ticks, const float tau[6],
                   const float s[6], const float* thrust) {
  static uint8_t out[12 + 48 + 4 * NEUROV_C_MAX_THRUSTERS];
  uint8_t* at = out;
  const uint8_t head[4] = {(uint8_t)status, (uint8_t)fault, (uint8_t)thrusters, 0};
  put(&at, &seq, 4);
  put(&at, head, 4);
  put(&at, &ticks, 4);
  put(&at, tau, 24);
  put(&at, s, 24);
  put(&at, thrust, 4 * thrusters);
  pil_send(PIL_COMMAND, out, (uint32_t)(at - out));
}

static void safe_answer(uint32_t seq, uint32_t fault) {
  static const float zero[6 + NEUROV_C_MAX_THRUSTERS];
  answer(seq, NEUROV_STATUS_OK, fault, 0, zero, zero, zero);
}

static int in_range(const float eta[6], const float nu[6]) {
  for (int i = 0; i < 3; ++i) {
    if (fabsf(eta[i]) > limits[0] || fabsf(nu[i]) > limits[2] || fabsf(nu[3 + i]) > limits[3]) return 0;
  }
  return !(fabsf(eta[3]) > limits[1] || fabsf(eta[4]) > limits[1]);
}

/* PIL_MEASUREMENT: u32 seq; f32 eta[6], nu[6], eta_d[6], eta_d_dot[6], eta_d_ddot[6]. */
static void control(const uint8_t* payload, uint32_t length) {
  reader r = {payload, payload + length};
  const uint32_t seq = get_u32(&r);
  float eta[6], nu[6], tau[6], s[6], thrust[NEUROV_C_MAX_THRUSTERS] = {0};
  neurov_desired d;
  get_floats(&r, eta, 6);
  get_floats(&r, nu, 6);
  get_floats(&r, d.eta_d, 6);
  get_floats(&r, d.eta_d_dot, 6);
  get_floats(&r, d.eta_d_ddot, 6);
  if (r.at != r.end) {
    ++bad_frames;
    safe_answer(seq, PIL_FAULT_BAD_FRAME);
    return;
  }
  if (nn == 0) {
    safe_answer(seq, PIL_FAULT_NOT_CONFIGURED);
    return;
  }
  ++measurements;
  const uint32_t start = board_ticks();
  /* NaN and Inf are the controller's to refuse (NON_FINITE_INPUT, tau = 0);
   * the range check is for finite values a sensor cannot give. */
  int range_ok = in_range(eta, nu);
  neurov_status status = NEUROV_STATUS_OK;
  if (range_ok) {
    status = neurov_nn_step(nn, eta, nu, &d, tau);
    if (thrusters > 0) {
      const neurov_status a = neurov_allocator_step(alloc, tau, 1.0f, thrust, 0);
      if (status == NEUROV_STATUS_OK) status = a;
    }
  }
  const uint32_t ticks = board_ticks() - start;
  if (!range_ok) {
    ++out_of_range;
    safe_answer(seq, PIL_FAULT_OUT_OF_RANGE);
    return;
  }
  if (ticks > max_step_ticks) max_step_ticks = ticks;
  neurov_nn_tracking_error(nn, 0, s);
  answer(seq, status, PIL_FAULT_NONE, ticks, tau, s, thrust);
}

static void report(void) {
  const uint32_t v[7] = {board_stack_used(), board_stack_size(), measurements, bad_frames,
                         timeouts, out_of_range, max_step_ticks};
  pil_send(PIL_REPORT, (const uint8_t*)v, sizeof v);
}

int main(void) {
  board_init();
  const uint32_t hello[6] = {board_cpuid(), board_mvfr0(), board_tick_hz(), N, board_stack_size(),
                             PIL_MAX_PAYLOAD};
  pil_send(PIL_HELLO, (const uint8_t*)hello, sizeof hello);
  pil_parser_reset(&parser);
  uint32_t last = board_ticks();
  for (;;) {
    const int byte = board_read(last, watchdog_ticks);
    if (byte < 0) { /* nothing for a watchdog period (only once configured); a partial frame is dropped */
      if (watchdog_ticks > 0 && nn != 0) {
        ++timeouts;
        safe_answer(0xFFFFFFFFu, PIL_FAULT_TIMEOUT);
      }
      pil_parser_reset(&parser);
      last = board_ticks();
      continue;
    }
    last = board_ticks(); /* the watchdog: silence on the link, within a frame too */
    const pil_parse_result got = pil_parser_feed(&parser, (uint8_t)byte);
    if (got == PIL_MORE) continue;
    if (got == PIL_BAD) {
      ++bad_frames;
      safe_answer(0xFFFFFFFFu, PIL_FAULT_BAD_FRAME);
    } else if (parser.type == PIL_CONFIG) {
      configure(parser.payload, parser.length);
    } else if (parser.type == PIL_MEASUREMENT) {
      control(parser.payload, parser.length);
    } else if (parser.type == PIL_STATS) {
      report();
    } else {
      ++bad_frames;
      safe_answer(0xFFFFFFFFu, PIL_FAULT_BAD_FRAME);
    }
  }
}
