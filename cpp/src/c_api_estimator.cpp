// The C interface's state estimator (neurov/c_api.h): Ekf<float> in the
// caller's storage, with the configuration kept for reset().
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <type_traits>

#include <Eigen/Core>

#include "c_api_internal.hpp"
#include "neurov/c_api.h"
#include "neurov/estimation/ekf.hpp"

namespace {

using namespace neurov::c_api;
using Filter = neurov::Ekf<float>;
using Vec3 = neurov::Vector3<float>;
using CVec3 = Eigen::Map<const Vec3>;

static_assert(NEUROV_EKF_STATES == neurov::kEkfStates, "c_api.h and ekf.hpp disagree");

constexpr std::uint32_t kEkfCanary = 0x454b6331u;  // "EKc1"

}  // namespace

struct neurov_ekf {
  std::uint32_t canary;
  neurov_status last;
  neurov::EkfConfig<float> config;  // for reset(): create() again from it
  Filter filter;
};

static_assert(sizeof(neurov_ekf) <= NEUROV_EKF_STORAGE_BYTES,
              "neurov_ekf outgrew NEUROV_EKF_STORAGE_BYTES in c_api.h");
static_assert(alignof(neurov_ekf) <= NEUROV_STORAGE_ALIGN, "neurov_ekf needs more than NEUROV_STORAGE_ALIGN");
static_assert(std::is_trivially_destructible<neurov_ekf>::value, "C objects must be trivially destructible");

namespace {

bool valid(const neurov_ekf* f) { return created(f, kEkfCanary); }

/// Records and returns the status of a call on a valid filter.
neurov_status record(neurov_ekf* f, neurov::Status s) {
  f->last = to_c(s);
  return f->last;
}

}  // namespace

namespace neurov::c_api {
std::size_t ekf_align() { return alignof(neurov_ekf); }
}  // namespace neurov::c_api

extern "C" {

size_t neurov_ekf_storage_size(void) { return sizeof(neurov_ekf); }

neurov_status neurov_ekf_create(void* storage, size_t size, const neurov_ekf_params* params,
                                const float eta0[6], const float nu0[6], neurov_ekf** out,
                                neurov_validation_error* error) {
  const neurov_status begun =
      begin_create(storage, size, out, error, "a pointer to receive the estimator");
  if (begun != NEUROV_STATUS_OK) return begun;
  if (params == nullptr) return fail(error, "params", 0.0, "parameters, not NULL");
  if (eta0 == nullptr) return fail(error, "eta0", 0.0, "6 floats, not NULL");
  if (nu0 == nullptr) return fail(error, "nu0", 0.0, "6 floats, not NULL");
  neurov::EkfConfig<float> c;
  c.linear_acceleration_noise = params->linear_acceleration_noise;
  c.angular_acceleration_noise = params->angular_acceleration_noise;
  c.gyro_bias_walk = params->gyro_bias_walk;
  c.attitude_noise = params->attitude_noise;
  c.gyro_noise = params->gyro_noise;
  c.dvl_noise = params->dvl_noise;
  c.depth_noise = params->depth_noise;
  c.position_noise = params->position_noise;
  c.initial_std = Eigen::Map<const Filter::StateVector>(params->initial_std);
  neurov_ekf* f = new (storage) neurov_ekf{};
  if (auto e = Filter::create(c, CVec6(eta0), CVec6(nu0), f->filter)) return fail(error, e);
  f->config = c;
  f->last = NEUROV_STATUS_OK;
  f->canary = kEkfCanary;
  *out = f;
  return NEUROV_STATUS_OK;
}

neurov_status neurov_ekf_reset(neurov_ekf* ekf, const float eta0[6], const float nu0[6]) {
  if (!valid(ekf) || eta0 == nullptr || nu0 == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  // create() validated this configuration already, so only a NaN/Inf start fails.
  if (Filter::create(ekf->config, CVec6(eta0), CVec6(nu0), ekf->filter))
    return record(ekf, neurov::Status::non_finite_input);
  return record(ekf, neurov::Status::ok);
}

neurov_status neurov_ekf_predict(neurov_ekf* ekf, float dt) {
  if (!valid(ekf)) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.predict(dt));
}

neurov_status neurov_ekf_update_attitude(neurov_ekf* ekf, const float attitude[3]) {
  if (!valid(ekf) || attitude == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.update_attitude(CVec3(attitude)));
}

neurov_status neurov_ekf_update_gyro(neurov_ekf* ekf, const float rates[3]) {
  if (!valid(ekf) || rates == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.update_gyro(CVec3(rates)));
}

neurov_status neurov_ekf_update_dvl(neurov_ekf* ekf, const float velocity[3]) {
  if (!valid(ekf) || velocity == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.update_dvl(CVec3(velocity)));
}

neurov_status neurov_ekf_update_depth(neurov_ekf* ekf, float depth) {
  if (!valid(ekf)) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.update_depth(depth));
}

neurov_status neurov_ekf_update_position(neurov_ekf* ekf, const float position[3], float age) {
  if (!valid(ekf) || position == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  return record(ekf, ekf->filter.update_position(CVec3(position), age));
}

void neurov_ekf_estimate(const neurov_ekf* ekf, float eta[6], float nu[6]) {
  if (!valid(ekf)) {
    zero6(eta);
    zero6(nu);
    return;
  }
  if (eta != nullptr) copy6(ekf->filter.eta(), eta);
  if (nu != nullptr) copy6(ekf->filter.nu(), nu);
}

void neurov_ekf_covariance_diagonal(const neurov_ekf* ekf, float variance[NEUROV_EKF_STATES]) {
  if (variance == nullptr) return;
  for (int i = 0; i < NEUROV_EKF_STATES; ++i)
    variance[i] = valid(ekf) ? ekf->filter.covariance()(i, i) : 0.0f;
}

void neurov_ekf_gyro_bias(const neurov_ekf* ekf, float bias[3]) {
  if (bias == nullptr) return;
  for (int i = 0; i < 3; ++i) bias[i] = valid(ekf) ? ekf->filter.gyro_bias()(i) : 0.0f;
}

neurov_status neurov_ekf_status(const neurov_ekf* ekf) {
  return valid(ekf) ? ekf->last : NEUROV_STATUS_INVALID_ARGUMENT;
}

}  // extern "C"
