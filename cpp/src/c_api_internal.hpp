// Helpers shared by the C interface's source files (c_api*.cpp): statuses,
// validation errors for C, the storage checks of create() and the canary.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <Eigen/Core>

#include "neurov/c_api.h"
#include "neurov/core/status.hpp"
#include "neurov/core/types.hpp"
#include "neurov/core/validation.hpp"

namespace neurov::c_api {

using Vec6 = neurov::Vector6<float>;
using CVec6 = Eigen::Map<const Vec6>;

inline neurov_status to_c(neurov::Status s) { return static_cast<neurov_status>(s); }

inline neurov_status fail(neurov_validation_error* error, const neurov::ValidationError& e) {
  if (error != nullptr) {
    error->field = e.field;
    error->index = e.index;
    error->value = e.value;
    error->expected = e.expected;
  }
  return NEUROV_STATUS_INVALID_ARGUMENT;
}

inline neurov_status fail(neurov_validation_error* error, const char* field, double value,
                          const char* expected) {
  return fail(error, neurov::detail::invalid(field, -1, value, expected));
}

inline void clear(neurov_validation_error* error) {
  if (error == nullptr) return;
  error->field = nullptr;
  error->index = -1;
  error->value = 0.0;
  error->expected = nullptr;
}

/// The storage checks shared by the create() functions: not NULL, aligned
/// for T, at least `needed` bytes (an object with a variable tail needs more
/// than sizeof(T)).
template <typename T>
bool storage_fits(void* storage, std::size_t size, neurov_validation_error* error,
                  neurov_status& status, std::size_t needed = sizeof(T)) {
  if (storage == nullptr) {
    status = fail(error, "storage", 0.0, "a buffer, not NULL");
    return false;
  }
  if (reinterpret_cast<std::uintptr_t>(storage) % alignof(T) != 0) {
    status = fail(error, "storage", static_cast<double>(reinterpret_cast<std::uintptr_t>(storage) %
                                                        alignof(T)),
                  "aligned to neurov_storage_align() (value: address modulo it)");
    return false;
  }
  if (size < needed) {
    status = fail(error, "size", static_cast<double>(size), "at least the object's storage size");
    return false;
  }
  return true;
}

/// The start of every create(): *out = NULL and `error` cleared, the storage
/// checked, the canary in the buffer cleared (from here a refusal leaves no
/// object in the buffer, whatever it held) and `out` checked; `receives`
/// names what `out` receives. Not NEUROV_STATUS_OK: the status to return.
template <typename T>
neurov_status begin_create(void* storage, std::size_t size, T** out,
                           neurov_validation_error* error, const char* receives) {
  if (out != nullptr) *out = nullptr;
  clear(error);
  neurov_status status = NEUROV_STATUS_OK;
  if (!storage_fits<T>(storage, size, error, status)) return status;
  std::memset(&static_cast<T*>(storage)->canary, 0, sizeof(std::uint32_t));
  if (out == nullptr) return fail(error, "out", 0.0, receives);
  return NEUROV_STATUS_OK;
}

/// create()'s refusal of a parameter that explains a wrong size, reported
/// ahead of the size check (a caller compiled with another N sized its
/// storage for that N): *out = NULL and `error` cleared, the pointer and
/// alignment checked, the canary cleared as begin_create() clears it, then `e`.
template <typename T>
neurov_status refuse_before_size(void* storage, std::size_t size, T** out,
                                 neurov_validation_error* error, const neurov::ValidationError& e) {
  if (out != nullptr) *out = nullptr;
  clear(error);
  neurov_status status = NEUROV_STATUS_OK;
  if (!storage_fits<T>(storage, size, error, status, 0)) return status;
  if (size >= sizeof(T)) std::memset(&static_cast<T*>(storage)->canary, 0, sizeof(std::uint32_t));
  return fail(error, e);
}

inline void zero6(float* v) {
  if (v != nullptr)
    for (int i = 0; i < 6; ++i) v[i] = 0.0f;
}

inline void copy6(const Vec6& from, float* to) {
  for (int i = 0; i < 6; ++i) to[i] = from(i);
}

/// True when all n values are finite (n = 0 or a NULL array: true).
inline bool all_finite(const float* v, int n) {
  if (v == nullptr) return true;
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

/// The canary of the object of type T at p, read as bytes (p may be any
/// pointer a caller passes; it is dereferenced only when aligned for T).
template <typename T>
inline bool created(const T* p, std::uint32_t canary) {
  if (p == nullptr || reinterpret_cast<std::uintptr_t>(p) % alignof(T) != 0) return false;
  std::uint32_t found = 0;
  std::memcpy(&found, &p->canary, sizeof found);
  return found == canary;
}

/// Alignment of the objects of c_api_allocation.cpp and c_api_estimator.cpp,
/// for neurov_storage_align().
std::size_t allocator_align();
std::size_t ekf_align();

}  // namespace neurov::c_api
