// The C interface's estimator (neurov_ekf_*): the same numbers as the C++
// Ekf<float> it wraps, step for step (the filter's statistics are tested in
// test_ekf.cpp); a fix's noise averaged down on a vehicle at rest; bad input
// refused with the estimate and covariance bit for bit unchanged; bad
// parameters named.
#include <cmath>
#include <cstring>
#include <limits>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "neurov/c_api.h"
#include "neurov/estimation/ekf.hpp"
#include "onboard_params.h"

namespace {

using Filter = neurov::Ekf<float>;

struct alignas(NEUROV_STORAGE_ALIGN) Storage {
  unsigned char bytes[NEUROV_EKF_STORAGE_BYTES]{};  // zeroed: the tests compare bytes
};

neurov_ekf_params params() { return onboard_ekf_params(1.0f); }

neurov::EkfConfig<float> config_of(const neurov_ekf_params& p) {
  neurov::EkfConfig<float> c;
  c.linear_acceleration_noise = p.linear_acceleration_noise;
  c.angular_acceleration_noise = p.angular_acceleration_noise;
  c.gyro_bias_walk = p.gyro_bias_walk;
  c.attitude_noise = p.attitude_noise;
  c.gyro_noise = p.gyro_noise;
  c.dvl_noise = p.dvl_noise;
  c.depth_noise = p.depth_noise;
  c.position_noise = p.position_noise;
  for (int i = 0; i < NEUROV_EKF_STATES; ++i) c.initial_std(i) = p.initial_std[i];
  return c;
}

const float kEta0[6] = {1, 2, 3, 0.1f, -0.05f, 0.5f};
const float kNu0[6] = {0.2f, 0, 0, 0, 0, 0.01f};

neurov_ekf* make(Storage& s) {
  const neurov_ekf_params p = params();
  neurov_ekf* f = nullptr;
  EXPECT_EQ(neurov_ekf_create(s.bytes, sizeof s.bytes, &p, kEta0, kNu0, &f, nullptr), NEUROV_STATUS_OK);
  return f;
}

/// A deterministic noise in [-1, 1] (an LCG: the test needs no distribution).
float noise(std::uint32_t& state) {
  state = state * 1664525u + 1013904223u;
  return static_cast<float>(state >> 8) / 8388608.0f - 1.0f;
}

TEST(CEstimator, GivesTheCppFiltersNumbersStepForStep) {
  Storage s;
  neurov_ekf* f = make(s);
  ASSERT_NE(f, nullptr);
  EXPECT_LE(neurov_ekf_storage_size(), sizeof s.bytes);
  Filter ref;
  ASSERT_TRUE(Filter::create(config_of(params()), Eigen::Map<const neurov::Vector6<float>>(kEta0),
                             Eigen::Map<const neurov::Vector6<float>>(kNu0), ref)
                  .ok());
  std::uint32_t state = 7;
  for (int k = 0; k < 200; ++k) {
    ASSERT_EQ(neurov_ekf_predict(f, 0.02f), NEUROV_STATUS_OK);
    ASSERT_EQ(ref.predict(0.02f), neurov::Status::ok);
    const float att[3] = {0.1f + 0.005f * noise(state), -0.05f, 0.5f};
    const float gyro[3] = {0.001f * noise(state), 0, 0.01f};
    ASSERT_EQ(neurov_ekf_update_attitude(f, att), NEUROV_STATUS_OK);
    ASSERT_EQ(ref.update_attitude(neurov::Vector3<float>(att)), neurov::Status::ok);
    ASSERT_EQ(neurov_ekf_update_gyro(f, gyro), NEUROV_STATUS_OK);
    ASSERT_EQ(ref.update_gyro(neurov::Vector3<float>(gyro)), neurov::Status::ok);
    if (k % 10 == 0) {
      const float dvl[3] = {0.2f + 0.01f * noise(state), 0, 0};
      ASSERT_EQ(neurov_ekf_update_dvl(f, dvl), NEUROV_STATUS_OK);
      ASSERT_EQ(ref.update_dvl(neurov::Vector3<float>(dvl)), neurov::Status::ok);
      const float depth = 3.0f + 0.02f * noise(state);
      ASSERT_EQ(neurov_ekf_update_depth(f, depth), NEUROV_STATUS_OK);
      ASSERT_EQ(ref.update_depth(depth), neurov::Status::ok);
    }
    if (k % 50 == 49) {
      const float fix[3] = {1.0f + 0.2f * k * 0.02f, 2.0f + noise(state), 3.0f};
      ASSERT_EQ(neurov_ekf_update_position(f, fix, 0.5f), NEUROV_STATUS_OK);
      ASSERT_EQ(ref.update_position(neurov::Vector3<float>(fix), 0.5f), neurov::Status::ok);
    }
  }
  float eta[6], nu[6], var[NEUROV_EKF_STATES], bias[3];
  neurov_ekf_estimate(f, eta, nu);
  neurov_ekf_covariance_diagonal(f, var);
  neurov_ekf_gyro_bias(f, bias);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(eta[i], ref.eta()(i));
    EXPECT_EQ(nu[i], ref.nu()(i));
  }
  for (int i = 0; i < NEUROV_EKF_STATES; ++i) EXPECT_EQ(var[i], ref.covariance()(i, i));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bias[i], ref.gyro_bias()(i));
}

TEST(CEstimator, AveragesTheFixesNoiseOnAVehicleAtRest) {
  Storage s;
  const float origin[6] = {0}, rest[6] = {0};
  neurov_ekf_params p = params();
  p.linear_acceleration_noise = 0.001f;
  neurov_ekf* f = nullptr;
  ASSERT_EQ(neurov_ekf_create(s.bytes, sizeof s.bytes, &p, origin, rest, &f, nullptr), NEUROV_STATUS_OK);
  std::uint32_t state = 11;
  double raw = 0.0;
  for (int k = 1; k <= 100; ++k) {  // 100 s at 5 Hz DVL, 1 Hz fixes of +-0.5 m uniform noise
    for (int j = 0; j < 5; ++j) {
      ASSERT_EQ(neurov_ekf_predict(f, 0.2f), NEUROV_STATUS_OK);
      const float zero3[3] = {0, 0, 0};
      ASSERT_EQ(neurov_ekf_update_dvl(f, zero3), NEUROV_STATUS_OK);
      ASSERT_EQ(neurov_ekf_update_attitude(f, zero3), NEUROV_STATUS_OK);
    }
    const float fix[3] = {0.5f * noise(state), 0.5f * noise(state), 0.5f * noise(state)};
    raw = std::max(raw, static_cast<double>(std::abs(fix[0])));
    ASSERT_EQ(neurov_ekf_update_position(f, fix, 0.0f), NEUROV_STATUS_OK);
  }
  float eta[6], var[NEUROV_EKF_STATES];
  neurov_ekf_estimate(f, eta, nullptr);
  neurov_ekf_covariance_diagonal(f, var);
  // A mean of ~100 fixes with std 0.5/sqrt(3) m: a std of about 0.03 m.
  EXPECT_LT(std::hypot(eta[0], eta[1]), 0.1f);
  EXPECT_GT(raw, 0.3);
  EXPECT_LT(var[0], 0.01f);
  EXPECT_GT(var[0], 0.0f);
}

TEST(CEstimator, BadInputChangesNothing) {
  Storage s;
  neurov_ekf* f = make(s);
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(neurov_ekf_predict(f, 0.1f), NEUROV_STATUS_OK);
  unsigned char snapshot[sizeof s.bytes];
  std::memcpy(snapshot, s.bytes, sizeof snapshot);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float bad3[3] = {0, nan, 0}, inf3[3] = {inf, 0, 0}, good3[3] = {0, 0, 0};
  const float good6[6] = {0}, bad6[6] = {0, 0, 0, nan, 0, 0};
  const struct {
    neurov_status got, expected;
    const char* what;
  } cases[] = {
      {neurov_ekf_predict(f, nan), NEUROV_STATUS_NON_FINITE_INPUT, "predict NaN dt"},
      {neurov_ekf_predict(f, 0.0f), NEUROV_STATUS_INVALID_ARGUMENT, "predict dt 0"},
      {neurov_ekf_predict(f, -0.1f), NEUROV_STATUS_INVALID_ARGUMENT, "predict dt < 0"},
      {neurov_ekf_predict(f, 10.5f), NEUROV_STATUS_INVALID_ARGUMENT, "predict dt > 10 s"},
      {neurov_ekf_update_attitude(f, bad3), NEUROV_STATUS_NON_FINITE_INPUT, "attitude NaN"},
      {neurov_ekf_update_gyro(f, inf3), NEUROV_STATUS_NON_FINITE_INPUT, "gyro Inf"},
      {neurov_ekf_update_dvl(f, bad3), NEUROV_STATUS_NON_FINITE_INPUT, "DVL NaN"},
      {neurov_ekf_update_depth(f, nan), NEUROV_STATUS_NON_FINITE_INPUT, "depth NaN"},
      {neurov_ekf_update_position(f, bad3, 0.5f), NEUROV_STATUS_NON_FINITE_INPUT, "fix NaN"},
      {neurov_ekf_update_position(f, good3, nan), NEUROV_STATUS_NON_FINITE_INPUT, "fix age NaN"},
      {neurov_ekf_update_position(f, good3, -1.0f), NEUROV_STATUS_INVALID_ARGUMENT, "fix age < 0"},
      {neurov_ekf_update_dvl(f, nullptr), NEUROV_STATUS_INVALID_ARGUMENT, "DVL NULL"},
      {neurov_ekf_reset(f, bad6, good6), NEUROV_STATUS_NON_FINITE_INPUT, "reset NaN eta0"},
      {neurov_ekf_reset(f, good6, nullptr), NEUROV_STATUS_INVALID_ARGUMENT, "reset NULL nu0"},
  };
  for (const auto& c : cases) EXPECT_EQ(c.got, c.expected) << c.what;
  EXPECT_EQ(neurov_ekf_status(f), NEUROV_STATUS_NON_FINITE_INPUT);  // the last that reached the filter
  reinterpret_cast<neurov_status*>(s.bytes + 4)[0] = NEUROV_STATUS_OK;  // all but the status
  EXPECT_EQ(std::memcmp(snapshot, s.bytes, sizeof snapshot), 0);
  // Reset returns to a given start with the initial covariance.
  ASSERT_EQ(neurov_ekf_reset(f, good6, good6), NEUROV_STATUS_OK);
  float eta[6], var[NEUROV_EKF_STATES];
  neurov_ekf_estimate(f, eta, nullptr);
  neurov_ekf_covariance_diagonal(f, var);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(eta[i], 0.0f);
  for (int i = 0; i < NEUROV_EKF_STATES; ++i) EXPECT_EQ(var[i], 1.0f);
}

TEST(CEstimator, CreateNamesTheBadParameter) {
  struct Case {
    const char* field;
    int index;
    void (*change)(neurov_ekf_params&, float* eta0);
  };
  const Case cases[] = {
      {"estimator.linear_acceleration_noise", -1, [](neurov_ekf_params& p, float*) { p.linear_acceleration_noise = -1.0f; }},
      {"estimator.dvl_noise", -1, [](neurov_ekf_params& p, float*) { p.dvl_noise = 0.0f; }},
      {"estimator.position_noise", -1, [](neurov_ekf_params& p, float*) { p.position_noise = NAN; }},
      {"estimator.initial_std", 12, [](neurov_ekf_params& p, float*) { p.initial_std[12] = 0.0f; }},
      {"estimator.initial_eta", 2, [](neurov_ekf_params&, float* eta0) { eta0[2] = INFINITY; }},
  };
  for (const Case& c : cases) {
    neurov_ekf_params p = params();
    float eta0[6] = {0}, nu0[6] = {0};
    c.change(p, eta0);
    Storage s;
    std::memset(s.bytes, 0xCD, sizeof s.bytes);
    neurov_ekf* f = reinterpret_cast<neurov_ekf*>(&p);
    neurov_validation_error e{};
    EXPECT_EQ(neurov_ekf_create(s.bytes, sizeof s.bytes, &p, eta0, nu0, &f, &e), NEUROV_STATUS_INVALID_ARGUMENT);
    EXPECT_EQ(f, nullptr);
    ASSERT_NE(e.field, nullptr) << c.field;
    EXPECT_STREQ(e.field, c.field);
    EXPECT_EQ(e.index, c.index) << c.field;
    EXPECT_EQ(neurov_ekf_predict(reinterpret_cast<neurov_ekf*>(s.bytes), 0.1f), NEUROV_STATUS_INVALID_ARGUMENT);
  }
  Storage s;
  const neurov_ekf_params p = params();
  neurov_ekf* f = nullptr;
  neurov_validation_error e{};
  EXPECT_EQ(neurov_ekf_create(s.bytes, neurov_ekf_storage_size() - 1, &p, kEta0, kNu0, &f, &e),
            NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_STREQ(e.field, "size");
  EXPECT_EQ(neurov_ekf_create(s.bytes, sizeof s.bytes, &p, nullptr, kNu0, &f, &e), NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_STREQ(e.field, "eta0");
}

TEST(CEstimator, ABufferCreateNeverSawIsRefused) {
  Storage s;
  std::memset(s.bytes, 0xCD, sizeof s.bytes);
  auto* f = reinterpret_cast<neurov_ekf*>(s.bytes);
  const float z[3] = {0, 0, 0};
  EXPECT_EQ(neurov_ekf_predict(f, 0.1f), NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_EQ(neurov_ekf_update_dvl(f, z), NEUROV_STATUS_INVALID_ARGUMENT);
  EXPECT_EQ(neurov_ekf_status(f), NEUROV_STATUS_INVALID_ARGUMENT);
  float eta[6] = {1, 1, 1, 1, 1, 1}, var[NEUROV_EKF_STATES];
  neurov_ekf_estimate(f, eta, nullptr);
  neurov_ekf_covariance_diagonal(f, var);
  for (float v : eta) EXPECT_EQ(v, 0.0f);
  for (float v : var) EXPECT_EQ(v, 0.0f);
  EXPECT_EQ(neurov_ekf_predict(nullptr, 0.1f), NEUROV_STATUS_INVALID_ARGUMENT);
}

}  // namespace
