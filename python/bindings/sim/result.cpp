#include "result.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>

#include <utility>

namespace neurov::bindings {

namespace py = pybind11;

namespace {

/// A numpy array viewing `m` without a copy: the matrix is moved to the heap
/// and owned by a capsule, so a 24-hour run's arrays exist once, not twice.
/// The result's matrices are row-major, numpy's default (C) order, so the
/// strides are those of a C-contiguous array.
template <typename Matrix>
py::array hand_over(Matrix&& m) {
  using Plain = std::decay_t<Matrix>;
  using T = typename Plain::Scalar;
  auto* owned = new Plain(std::move(m));
  py::capsule owner(owned, [](void* p) { delete static_cast<Plain*>(p); });
  if constexpr (Plain::ColsAtCompileTime == 1) {
    return py::array_t<T>({owned->rows()}, {py::ssize_t(sizeof(T))}, owned->data(), owner);
  } else {
    static_assert(Plain::IsRowMajor, "SimulationResult's tables are row-major (C order)");
    return py::array_t<T>({owned->rows(), owned->cols()},
                          {py::ssize_t(sizeof(T)) * owned->cols(), py::ssize_t(sizeof(T))},
                          owned->data(), owner);
  }
}

}  // namespace

py::dict result_dict(const SimulationResult<double>& r) {
  return result_dict(SimulationResult<double>(r));
}

py::dict result_dict(SimulationResult<double>&& r) {
  py::dict d;
  d["t"] = hand_over(std::move(r.t));
  d["eta"] = hand_over(std::move(r.eta));
  d["nu"] = hand_over(std::move(r.nu));
  d["eta_d"] = hand_over(std::move(r.eta_d));
  d["eta_d_dot"] = hand_over(std::move(r.eta_d_dot));
  d["tau_demanded"] = hand_over(std::move(r.tau_demanded));
  d["tau_applied"] = hand_over(std::move(r.tau_applied));
  d["disturbance"] = hand_over(std::move(r.disturbance));
  d["s"] = hand_over(std::move(r.s));
  d["eta_estimate"] = hand_over(std::move(r.eta_estimate));
  d["nu_estimate"] = hand_over(std::move(r.nu_estimate));
  d["thrusts"] = hand_over(std::move(r.thrusts));
  d["theta"] = hand_over(std::move(r.theta));
  d["adaptive_norm"] = hand_over(std::move(r.adaptive_norm));
  d["controller_status"] = hand_over(std::move(r.controller_status));
  d["plant_status"] = hand_over(std::move(r.plant_status));
  d["faults"] = hand_over(std::move(r.faults));
  d["current"] = hand_over(std::move(r.current));
  d["wave_velocity"] = hand_over(std::move(r.wave_velocity));
  d["wave_elevation"] = hand_over(std::move(r.wave_elevation));
  d["payload_mass"] = hand_over(std::move(r.payload_mass));
  d["diverged"] = r.diverged;
  return d;
}

}  // namespace neurov::bindings
