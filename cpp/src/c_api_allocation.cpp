// The C interface's thrust allocation (neurov/c_api.h): ThrustAllocator in
// float for up to NEUROV_C_MAX_THRUSTERS thrusters, with its curve tables
// after the object in the caller's storage (a vehicle whose thrusters share
// one curve pays for one table, not eight).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <array>
#include <new>
#include <type_traits>

#include <Eigen/Core>

#include "c_api_internal.hpp"
#include "neurov/c_api.h"
#include "neurov/model/thrust_allocation.hpp"
#include "neurov/model/thruster_curve.hpp"
#include "neurov/model/thruster_geometry.hpp"

namespace {

using namespace neurov::c_api;

constexpr int kMaxThrusters = NEUROV_C_MAX_THRUSTERS;
using Allocator = neurov::ThrustAllocator<float, kMaxThrusters>;
using Curve = neurov::ThrusterCurve<float>;

static_assert(NEUROV_C_CURVE_POINTS == neurov::kThrusterCurveCapacity,
              "c_api.h and thruster_curve.hpp disagree on the table's capacity");
static_assert(static_cast<int>(NEUROV_SATURATION_SCALE) == static_cast<int>(neurov::Saturation::scale) &&
                  static_cast<int>(NEUROV_SATURATION_CLIP) == static_cast<int>(neurov::Saturation::clip),
              "neurov_saturation must mirror neurov::Saturation");

constexpr std::uint32_t kAllocatorCanary = 0x414c6331u;  // "ALc1"

}  // namespace

struct neurov_allocator {
  std::uint32_t canary;
  neurov_status last;
  std::uint32_t curve_count;
  std::uint8_t curve_of[kMaxThrusters];
  Allocator allocator;
};

namespace {

constexpr std::size_t round_up(std::size_t n, std::size_t a) { return (n + a - 1) / a * a; }
// The curves follow the object, each aligned as a Curve.
constexpr std::size_t kCurvesOffset = round_up(sizeof(neurov_allocator), alignof(Curve));

static_assert(kCurvesOffset <= 1024u && sizeof(Curve) <= 2112u,
              "the allocator outgrew NEUROV_ALLOCATOR_STORAGE_BYTES in c_api.h");
static_assert(alignof(neurov_allocator) <= NEUROV_STORAGE_ALIGN && alignof(Curve) <= NEUROV_STORAGE_ALIGN,
              "the allocator needs more than NEUROV_STORAGE_ALIGN");
static_assert(std::is_trivially_destructible<neurov_allocator>::value &&
                  std::is_trivially_destructible<Curve>::value,
              "C objects must be trivially destructible");

Curve* curves_of(neurov_allocator* a) {
  return reinterpret_cast<Curve*>(reinterpret_cast<unsigned char*>(a) + kCurvesOffset);
}

bool valid(const neurov_allocator* a) { return created(a, kAllocatorCanary); }

/// B from the params: the matrix as given, or column i = [d_i; r_i x d_i]
/// through the one function that builds it (thruster_geometry.hpp).
neurov::ValidationError layout_matrix(const neurov_allocator_params& p, int n, Allocator::Matrix& b) {
  b.resize(6, n);
  if (p.matrix != nullptr) {
    for (int k = 0; k < 6; ++k)
      for (int i = 0; i < n; ++i) b(k, i) = p.matrix[k * n + i];
    return {};
  }
  for (int i = 0; i < n; ++i) {
    std::array<neurov::ThrusterGeometry<float>, 1> one;
    one[0].position = Eigen::Map<const neurov::Vector3<float>>(p.positions + 3 * i);
    one[0].direction = Eigen::Map<const neurov::Vector3<float>>(p.directions + 3 * i);
    Eigen::Matrix<float, 6, 1> column;
    neurov::ValidationError e = neurov::allocation_matrix(one, column);
    if (e) {
      e.index = i;
      return e;
    }
    b.col(i) = column;
  }
  return {};
}

/// Thruster i's curve: curve_of[i], or i (one per thruster) or 0 (shared).
neurov::ValidationError curve_indices(const neurov_allocator_params& p, int n, std::uint8_t* of) {
  const std::uint32_t count = p.curve_count;
  if (count == 0) return {};
  if (p.curve_of == nullptr && count != 1 && count != static_cast<std::uint32_t>(n))
    return neurov::detail::invalid("curve_of", -1, static_cast<double>(count),
                                   "one index per thruster unless curve_count is 1 or thrusters");
  for (int i = 0; i < n; ++i) {
    const std::uint32_t k = p.curve_of != nullptr ? p.curve_of[i] : (count == 1 ? 0u : static_cast<std::uint32_t>(i));
    if (k >= count)
      return neurov::detail::invalid("curve_of", i, static_cast<double>(k), "< curve_count");
    of[i] = static_cast<std::uint8_t>(k);
  }
  return {};
}

neurov::ValidationError build_curve(const neurov_thruster_curve& c, Curve& out) {
  if (c.points < 2 || c.points > static_cast<std::uint32_t>(NEUROV_C_CURVE_POINTS))
    return neurov::detail::invalid("thruster_curve.points", -1, static_cast<double>(c.points),
                                   "2 to NEUROV_C_CURVE_POINTS rows");
  if (c.command == nullptr)
    return neurov::detail::invalid("thruster_curve.command", -1, 0.0, "`points` floats, not NULL");
  if (c.thrust == nullptr)
    return neurov::detail::invalid("thruster_curve.thrust", -1, 0.0, "`points` floats, not NULL");
  // Built in place: the configuration is 2 KiB, too much for a second copy
  // on the stack of a small target.
  new (&out) Curve{};
  neurov::ThrusterCurveConfig<float> cfg{};
  cfg.points = static_cast<int>(c.points);
  for (std::uint32_t i = 0; i < c.points; ++i) {
    cfg.command[i] = c.command[i];
    cfg.thrust[i] = c.thrust[i];
  }
  cfg.neutral = c.neutral;
  cfg.dead_band = c.dead_band;
  cfg.reference_voltage = c.reference_voltage;
  cfg.voltage_exponent = c.voltage_exponent;
  return Curve::create(cfg, out);
}

}  // namespace

namespace neurov::c_api {
std::size_t allocator_align() { return alignof(neurov_allocator) > alignof(Curve) ? alignof(neurov_allocator) : alignof(Curve); }
}  // namespace neurov::c_api

extern "C" {

void neurov_allocator_params_init(neurov_allocator_params* params) {
  if (params == nullptr) return;
  std::memset(params, 0, sizeof *params);
  params->saturation = NEUROV_SATURATION_SCALE;
}

size_t neurov_allocator_storage_size(uint32_t curve_count) {
  if (curve_count > static_cast<uint32_t>(kMaxThrusters)) return 0;
  return kCurvesOffset + curve_count * sizeof(Curve);
}

neurov_status neurov_allocator_create(void* storage, size_t size,
                                      const neurov_allocator_params* params,
                                      neurov_allocator** out, neurov_validation_error* error) {
  const neurov_status begun =
      begin_create(storage, size, out, error, "a pointer to receive the allocator");
  if (begun != NEUROV_STATUS_OK) return begun;
  if (params == nullptr) return fail(error, "params", 0.0, "parameters, not NULL");
  const neurov_allocator_params& p = *params;
  if (p.thrusters < 6 || p.thrusters > static_cast<uint32_t>(kMaxThrusters))
    return fail(error, "thrusters", static_cast<double>(p.thrusters), "6 to NEUROV_C_MAX_THRUSTERS");
  const int n = static_cast<int>(p.thrusters);
  if (p.curve_count > p.thrusters)
    return fail(error, "curve_count", static_cast<double>(p.curve_count), "0 to thrusters");
  neurov_status status = NEUROV_STATUS_OK;
  if (!storage_fits<neurov_allocator>(storage, size, error, status,
                                      neurov_allocator_storage_size(p.curve_count)))
    return status;
  if (p.matrix == nullptr && (p.positions == nullptr || p.directions == nullptr))
    return fail(error, "matrix", 0.0, "6 x n floats, or positions and directions (n x 3 each)");
  if (p.min_thrust == nullptr) return fail(error, "min_thrust", 0.0, "n floats, not NULL");
  if (p.max_thrust == nullptr) return fail(error, "max_thrust", 0.0, "n floats, not NULL");
  if (p.curve_count > 0 && p.curves == nullptr)
    return fail(error, "curves", 0.0, "curve_count curves, not NULL");
  std::underlying_type_t<neurov_saturation> raw{};
  std::memcpy(&raw, &p.saturation, sizeof raw);
  const long long saturation = static_cast<long long>(raw);
  if (saturation != NEUROV_SATURATION_SCALE && saturation != NEUROV_SATURATION_CLIP)
    return fail(error, "saturation", static_cast<double>(saturation), "scale or clip");

  Allocator::Matrix b;
  if (auto e = layout_matrix(p, n, b)) return fail(error, e);
  using Vector = Allocator::Vector;
  const Vector lo = Eigen::Map<const Vector>(p.min_thrust, n);
  const Vector hi = Eigen::Map<const Vector>(p.max_thrust, n);
  const Vector w = p.weights != nullptr ? Vector(Eigen::Map<const Vector>(p.weights, n)) : Vector();

  neurov_allocator* a = new (storage) neurov_allocator{};
  if (auto e = curve_indices(p, n, a->curve_of)) return fail(error, e);
  for (std::uint32_t k = 0; k < p.curve_count; ++k)
    if (auto e = build_curve(p.curves[k], curves_of(a)[k])) return fail(error, e);
  if (auto e = Allocator::create(b, lo, hi, w, static_cast<neurov::Saturation>(saturation),
                                 a->allocator))
    return fail(error, e);
  a->curve_count = p.curve_count;
  a->last = NEUROV_STATUS_OK;
  a->canary = kAllocatorCanary;
  *out = a;
  return NEUROV_STATUS_OK;
}

neurov_status neurov_allocator_step(neurov_allocator* alloc, const float tau[6], float voltage,
                                    float* commands, float* thrusts) {
  if (!valid(alloc) || commands == nullptr) return NEUROV_STATUS_INVALID_ARGUMENT;
  const int n = static_cast<int>(alloc->allocator.count());
  const Curve* curves[kMaxThrusters] = {};
  if (alloc->curve_count > 0)
    for (int i = 0; i < n; ++i) curves[i] = &curves_of(alloc)[alloc->curve_of[i]];
  Allocator::Vector u, c;
  neurov::Status s = neurov::Status::invalid_argument;
  if (tau != nullptr) {
    s = alloc->allocator.allocate(CVec6(tau), voltage, curves, u, c);
  } else {  // answered as a refused tau is: no thrust, neutral commands
    u.setZero(n);
    c.setZero(n);
    for (int i = 0; i < n; ++i)
      if (curves[i] != nullptr) c(i) = curves[i]->config().neutral;
  }
  for (int i = 0; i < n; ++i) {
    commands[i] = c(i);
    if (thrusts != nullptr) thrusts[i] = u(i);
  }
  alloc->last = to_c(s);
  return alloc->last;
}

uint32_t neurov_allocator_thrusters(const neurov_allocator* alloc) {
  return valid(alloc) ? static_cast<uint32_t>(alloc->allocator.count()) : 0u;
}

neurov_status neurov_allocator_status(const neurov_allocator* alloc) {
  return valid(alloc) ? alloc->last : NEUROV_STATUS_INVALID_ARGUMENT;
}

}  // extern "C"
