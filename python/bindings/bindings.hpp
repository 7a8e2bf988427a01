// One function per binding file, bind_<name>(m), listed once here in the
// order module.cpp calls them: a type is bound before the functions whose
// signatures name it. The files mirror the C++ layers.
#pragma once

#include <pybind11/pybind11.h>

#define NEUROV_BINDINGS(X)                                                          \
  /* core/ */ X(errors) X(status)                                                   \
  /* model/ */ X(kinematics) X(vehicle) X(linearization) X(thrusters) X(regressor)  \
  /* control/ */ X(tracking_error) X(reference_model) X(rbf_network)                \
  X(controller_configs) X(controllers)                                              \
  /* sim/ */ X(sim_config) X(result_series) X(simulator) X(closed_loop) X(batch)    \
  X(tracking_task)

namespace neurov::bindings {

#define NEUROV_DECLARE_BINDING(name) void bind_##name(pybind11::module_& m);
NEUROV_BINDINGS(NEUROV_DECLARE_BINDING)
#undef NEUROV_DECLARE_BINDING

}  // namespace neurov::bindings
