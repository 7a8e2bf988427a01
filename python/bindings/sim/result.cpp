#include "result.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>

#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "neurov/model/regressor.hpp"

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

typed::SimulationResultDict result_dict(const SimulationResult<double>& r) {
  return result_dict(SimulationResult<double>(r));
}

typed::SimulationResultDict result_dict(SimulationResult<double>&& r) {
  py::dict d;
  r.visit([&d](const SeriesSpec& spec, auto& series) {
    d[spec.name] = hand_over(std::move(series));
  });
  d["diverged"] = r.diverged;
  return d;
}

/// Each series' numpy dtype, by its index in kResultSeries: from the type of
/// the member the table declares, not written a second time.
const std::vector<std::string>& series_dtypes() {
  static const std::vector<std::string> dtypes = [] {
    std::vector<std::string> out;
    SimulationResult<double> probe;
    probe.visit([&out](const SeriesSpec&, auto& series) {
      using T = typename std::decay_t<decltype(series)>::Scalar;
      out.push_back(py::str(py::dtype::of<T>()));
    });
    return out;
  }();
  return dtypes;
}

std::string result_series_names() {
  std::string names;
  for (const SeriesSpec& spec : kResultSeries) names += std::string(names.empty() ? "" : ", ") + spec.name;
  return names;
}

void bind_result_series(py::module_& m) {
  // Plain tuples (neurov.columns names their fields): (name, width or None,
  // varies_with, labels, unit, dtype, kind, description).
  static const char* const kinds[] = {"real", "status", "bits"};
  py::list all;
  for (const SeriesSpec& s : kResultSeries) {
    py::list labels;
    if (s.width == kPerParameter) {
      for (int i = 0; i < kRegressorParameters; ++i) labels.append(theta_name(i));
    } else {
      std::istringstream words(s.labels);
      for (std::string w; words >> w;) labels.append(w);
    }
    const char* varies = s.width == kPerThruster ? "thrusters" : s.width == kPerParameter ? "parameters" : "";
    all.append(py::make_tuple(s.name, s.width > 0 ? py::object(py::int_(s.width)) : py::none(), varies,
                              py::tuple(labels), s.unit, series_dtypes()[&s - kResultSeries],
                              kinds[static_cast<int>(s.kind)], s.description));
  }
  m.attr("RESULT_SERIES") = py::tuple(all);
}

}  // namespace neurov::bindings
