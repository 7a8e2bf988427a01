// The C interface (neurov/c_api.h) over the C++ templates: float, N fixed at
// build time, objects placement-new'd into caller storage. Built with
// -fno-exceptions -fno-rtti, so nothing can unwind through a C caller.
#include "neurov/c_api.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <type_traits>

#include <Eigen/Core>

#include "neurov/control/nn_controller.hpp"
#include "neurov/control/reference_model.hpp"
#include "neurov/core/status.hpp"
#include "neurov/core/validation.hpp"
#include "c_api_internal.hpp"

namespace {

constexpr int kCentres = NEUROV_C_CENTRES;
static_assert(kCentres >= 1, "NEUROV_C_CENTRES must be at least 1");
static_assert(NEUROV_C_INPUTS == neurov::kNNInputs, "c_api.h and nn_controller.hpp disagree");

#define NEUROV_C_STRING_(x) #x
#define NEUROV_C_STRING(x) NEUROV_C_STRING_(x)
// What a refused centres_count is told (the strings of errors are static).
constexpr const char* kCentresExpected =
    "the library's N, neurov_nn_centres() = " NEUROV_C_STRING(NEUROV_C_CENTRES)
    ": compile the caller with -DNEUROV_C_CENTRES=" NEUROV_C_STRING(NEUROV_C_CENTRES)
    " (linking neurov::neurov_c passes it), so that its arrays and storage are for that N";

using Controller = neurov::NNAdaptiveController<float, kCentres>;
using Network = Controller::Network;
// The C side hands over row-major arrays (one centre, one output row after the
// other); Eigen's matrices are column-major, so these maps do the transposition.
using CentresIn = Eigen::Map<const Eigen::Matrix<float, kCentres, neurov::kNNInputs, Eigen::RowMajor>>;
using WeightsRowMajor = Eigen::Matrix<float, 6, kCentres, Eigen::RowMajor>;

using namespace neurov::c_api;

static_assert(static_cast<int>(NEUROV_STATUS_OK) == static_cast<int>(neurov::Status::ok) &&
                  static_cast<int>(NEUROV_STATUS_NEAR_SINGULARITY) ==
                      static_cast<int>(neurov::Status::near_singularity) &&
                  static_cast<int>(NEUROV_STATUS_NON_FINITE_INPUT) ==
                      static_cast<int>(neurov::Status::non_finite_input) &&
                  static_cast<int>(NEUROV_STATUS_INVALID_ARGUMENT) ==
                      static_cast<int>(neurov::Status::invalid_argument) &&
                  static_cast<int>(NEUROV_STATUS_NON_FINITE_OUTPUT) ==
                      static_cast<int>(neurov::Status::non_finite_output),
              "neurov_status must mirror neurov::Status");
static_assert(static_cast<int>(NEUROV_MODIFICATION_NONE) ==
                      static_cast<int>(neurov::RobustModification::none) &&
                  static_cast<int>(NEUROV_MODIFICATION_SIGMA) ==
                      static_cast<int>(neurov::RobustModification::sigma) &&
                  static_cast<int>(NEUROV_MODIFICATION_E_MODIFICATION) ==
                      static_cast<int>(neurov::RobustModification::e_modification) &&
                  static_cast<int>(NEUROV_MODIFICATION_PROJECTION) ==
                      static_cast<int>(neurov::RobustModification::projection),
              "neurov_modification must mirror neurov::RobustModification");

// Every object starts with a canary that create() writes last, once the object
// is valid, and every other call checks: a buffer create() never saw (or
// refused, or that holds the other kind of object) is refused as NULL is,
// instead of being stepped as garbage. The values are neither a debugger's
// fill patterns (0xCD.., 0xDEADBEEF, 0xA5..) nor zero.
constexpr std::uint32_t kNNCanary = 0x4e4e6331u;         // "NNc1"
constexpr std::uint32_t kReferenceCanary = 0x52456331u;  // "REc1"

}  // namespace

struct neurov_nn {
  std::uint32_t canary;
  Controller controller;
};

struct neurov_reference {
  std::uint32_t canary;
  neurov::ReferenceModel<float> model;
};

namespace {

bool valid(const neurov_nn* nn) { return created(nn, kNNCanary); }
bool valid(const neurov_reference* ref) { return created(ref, kReferenceCanary); }

}  // namespace

// The compile-time sizes in c_api.h are what C firmware sizes its static
// buffers with; an object outgrowing them must fail the build, not memory.
static_assert(sizeof(neurov_nn) <= NEUROV_NN_STORAGE_BYTES(NEUROV_C_CENTRES),
              "neurov_nn outgrew NEUROV_NN_STORAGE_BYTES in c_api.h: update the formula");
static_assert(sizeof(neurov_reference) <= NEUROV_REFERENCE_STORAGE_BYTES,
              "neurov_reference outgrew NEUROV_REFERENCE_STORAGE_BYTES in c_api.h");
static_assert(alignof(neurov_nn) <= NEUROV_STORAGE_ALIGN &&
                  alignof(neurov_reference) <= NEUROV_STORAGE_ALIGN,
              "Eigen aligns more than NEUROV_STORAGE_ALIGN (a wider SIMD target?): "
              "define NEUROV_STORAGE_ALIGN to the larger alignment for the library and its users");
// No destroy(): reusing the buffer must not skip a destructor that matters.
static_assert(std::is_trivially_destructible<neurov_nn>::value &&
                  std::is_trivially_destructible<neurov_reference>::value,
              "C objects must be trivially destructible");

extern "C" {

const char* neurov_status_name(neurov_status status) {
  return neurov::to_string(static_cast<neurov::Status>(status));
}

uint32_t neurov_nn_centres(void) { return static_cast<uint32_t>(kCentres); }
size_t neurov_nn_storage_size_n(uint32_t centres) {
  return centres == static_cast<uint32_t>(kCentres) ? sizeof(neurov_nn) : 0;
}
size_t neurov_storage_align(void) {
  std::size_t a = alignof(neurov_nn) > alignof(neurov_reference) ? alignof(neurov_nn)
                                                                 : alignof(neurov_reference);
  if (allocator_align() > a) a = allocator_align();
  if (ekf_align() > a) a = ekf_align();
  return a;
}

void neurov_nn_params_init_n(neurov_nn_params* params, uint32_t centres) {
  if (params == nullptr) return;
  const neurov::NNAdaptiveConfig<float> d{};
  // The caller's N, which create() compares with the library's: the
  // library's own N here would make that check pass for every caller.
  params->centres_count = centres;
  params->centres = nullptr;
  params->widths = nullptr;
  params->input_offset = nullptr;
  params->input_scale = nullptr;
  copy6(d.lambda, params->lambda);
  copy6(d.kd, params->kd);
  params->gamma = d.gamma;
  params->dt = d.dt;
  params->modification = static_cast<neurov_modification>(d.modification);
  params->sigma_m = d.sigma_m;
  params->kappa = d.kappa;
  params->w_max = d.w_max;
  params->dead_zone = d.dead_zone;
}

neurov_status neurov_nn_create(void* storage, size_t size, const neurov_nn_params* params,
                               neurov_nn** out, neurov_validation_error* error) {
  // A caller compiled with another N has arrays and storage of that N: its
  // N is refused before its storage size, which it explains, and before a
  // single value of its arrays is read.
  if (params != nullptr && params->centres_count != static_cast<uint32_t>(kCentres))
    return refuse_before_size(storage, size, out, error,
                              neurov::detail::invalid("centres_count", -1,
                                                      static_cast<double>(params->centres_count),
                                                      kCentresExpected));
  const neurov_status begun =
      begin_create(storage, size, out, error, "a pointer to receive the controller");
  if (begun != NEUROV_STATUS_OK) return begun;
  if (params == nullptr) return fail(error, "params", 0.0, "parameters, not NULL");
  if (params->centres == nullptr) return fail(error, "centres", 0.0, "N x 24 floats, not NULL");
  if (params->widths == nullptr) return fail(error, "widths", 0.0, "N floats, not NULL");
  // A C caller may store any value the field holds; in C++ loading an enum
  // outside its values' range is undefined, so the field's bytes are read as
  // its underlying integer (whatever size the ABI gives it, short enums on
  // bare-metal ARM included), checked, then converted.
  std::underlying_type_t<neurov_modification> raw{};
  std::memcpy(&raw, &params->modification, sizeof raw);
  const long long modification = static_cast<long long>(raw);
  if (modification < NEUROV_MODIFICATION_NONE || modification > NEUROV_MODIFICATION_PROJECTION)
    return fail(error, "modification", static_cast<double>(modification),
                "none, sigma, e_modification or projection");

  neurov::NNAdaptiveConfig<float> config;
  config.lambda = CVec6(params->lambda);
  config.kd = CVec6(params->kd);
  config.gamma = params->gamma;
  config.dt = params->dt;
  config.modification = static_cast<neurov::RobustModification>(modification);
  config.sigma_m = params->sigma_m;
  config.kappa = params->kappa;
  config.w_max = params->w_max;
  config.dead_zone = params->dead_zone;

  using Input = Network::InputVector;
  const Input offset = params->input_offset != nullptr
                           ? Input(Eigen::Map<const Input>(params->input_offset))
                           : Input(Input::Zero());
  const Input scale = params->input_scale != nullptr
                          ? Input(Eigen::Map<const Input>(params->input_scale))
                          : Input(Input::Ones());
  // The one large temporary of create(): the centres in Eigen's column-major
  // order. The network itself is built in place in the caller's storage.
  const Network::CentreMatrix centres = CentresIn(params->centres);

  // Value-initialised: the canary is 0 until the controller is valid.
  neurov_nn* nn = new (storage) neurov_nn{};
  const neurov::ValidationError e =
      Controller::create(centres, Eigen::Map<const Network::BasisVector>(params->widths), offset,
                         scale, config, nn->controller);
  if (e) return fail(error, e);
  nn->canary = kNNCanary;
  *out = nn;
  return NEUROV_STATUS_OK;
}

neurov_status neurov_nn_step(neurov_nn* nn, const float eta[6], const float nu[6],
                             const neurov_desired* desired, float tau[6]) {
  if (!valid(nn) || eta == nullptr || nu == nullptr || desired == nullptr || tau == nullptr) {
    zero6(tau);
    return NEUROV_STATUS_INVALID_ARGUMENT;
  }
  Vec6 t;
  const neurov::Status s =
      nn->controller.step(CVec6(eta), CVec6(nu), CVec6(desired->eta_d),
                          CVec6(desired->eta_d_dot), CVec6(desired->eta_d_ddot), t);
  copy6(t, tau);
  return to_c(s);
}

neurov_status neurov_nn_status(const neurov_nn* nn) {
  return valid(nn) ? to_c(nn->controller.last_status()) : NEUROV_STATUS_INVALID_ARGUMENT;
}

void neurov_nn_reset(neurov_nn* nn) {
  if (valid(nn)) nn->controller.reset();
}

void neurov_nn_tracking_error(const neurov_nn* nn, float eta_tilde[6], float s[6]) {
  if (!valid(nn)) {
    zero6(eta_tilde);
    zero6(s);
    return;
  }
  if (eta_tilde != nullptr) copy6(nn->controller.tracking().eta_tilde, eta_tilde);
  if (s != nullptr) copy6(nn->controller.tracking().s, s);
}

float neurov_nn_weight_norm(const neurov_nn* nn) {
  return valid(nn) ? nn->controller.weight_norm() : 0.0f;
}

void neurov_nn_get_weights(const neurov_nn* nn, float* weights) {
  if (!valid(nn) || weights == nullptr) return;
  Eigen::Map<WeightsRowMajor> out(weights);
  out = nn->controller.weights();
}

neurov_status neurov_nn_set_initial_weights(neurov_nn* nn, const float* weights) {
  if (!valid(nn) || weights == nullptr)
    return NEUROV_STATUS_INVALID_ARGUMENT;
  const Controller::WeightMatrix w = Eigen::Map<const WeightsRowMajor>(weights);
  if (!w.allFinite()) return NEUROV_STATUS_NON_FINITE_INPUT;
  Controller& c = nn->controller;
  if (!c.set_weights(w)) return NEUROV_STATUS_INVALID_ARGUMENT;
  // create() takes the network's current weights as the initial ones; handing
  // it the controller's own network and configuration cannot fail.
  const neurov::ValidationError e = Controller::create(c.network(), c.config(), c);
  return e ? NEUROV_STATUS_INVALID_ARGUMENT : NEUROV_STATUS_OK;
}

size_t neurov_reference_storage_size(void) { return sizeof(neurov_reference); }

neurov_status neurov_reference_create(void* storage, size_t size, const float lambda_d[6],
                                      const float omega[6], const float eta0[6],
                                      neurov_reference** out, neurov_validation_error* error) {
  const neurov_status begun =
      begin_create(storage, size, out, error, "a pointer to receive the model");
  if (begun != NEUROV_STATUS_OK) return begun;
  if (lambda_d == nullptr) return fail(error, "lambda_d", 0.0, "6 floats, not NULL");
  if (omega == nullptr) return fail(error, "omega", 0.0, "6 floats, not NULL");
  if (eta0 == nullptr) return fail(error, "eta0", 0.0, "6 floats, not NULL");
  neurov_reference* ref = new (storage) neurov_reference{};
  const neurov::ValidationError e = neurov::ReferenceModel<float>::create(
      CVec6(lambda_d), CVec6(omega), CVec6(eta0), ref->model);
  if (e) return fail(error, e);
  ref->canary = kReferenceCanary;
  *out = ref;
  return NEUROV_STATUS_OK;
}

neurov_status neurov_reference_step(neurov_reference* ref, const float r[6], float dt,
                                    neurov_desired* out) {
  if (!valid(ref) || r == nullptr || out == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  neurov::DesiredState<float> d;
  const neurov::Status s = ref->model.step(CVec6(r), dt, d);
  copy6(d.eta_d, out->eta_d);
  copy6(d.eta_d_dot, out->eta_d_dot);
  copy6(d.eta_d_ddot, out->eta_d_ddot);
  return to_c(s);
}

neurov_status neurov_reference_reset(neurov_reference* ref, const float eta0[6]) {
  if (!valid(ref) || eta0 == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  return ref->model.reset(CVec6(eta0)) ? NEUROV_STATUS_OK : NEUROV_STATUS_NON_FINITE_INPUT;
}

}  // extern "C"
