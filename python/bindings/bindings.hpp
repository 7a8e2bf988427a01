// One function per binding file; module.cpp calls them in order (a type is
// bound before the functions whose signatures name it).
#pragma once

#include <pybind11/pybind11.h>

namespace neurov::bindings {

// core/
void bind_errors(pybind11::module_& m);
void bind_status(pybind11::module_& m);
// model/
void bind_kinematics(pybind11::module_& m);
void bind_vehicle(pybind11::module_& m);
void bind_regressor(pybind11::module_& m);
void bind_linearization(pybind11::module_& m);
void bind_thrusters(pybind11::module_& m);
// control/
void bind_tracking_error(pybind11::module_& m);
void bind_reference_model(pybind11::module_& m);
void bind_rbf_network(pybind11::module_& m);
void bind_controller_configs(pybind11::module_& m);
void bind_controllers(pybind11::module_& m);
// sim/
void bind_sim_config(pybind11::module_& m);
void bind_result_series(pybind11::module_& m);
void bind_simulator(pybind11::module_& m);
void bind_closed_loop(pybind11::module_& m);
void bind_batch(pybind11::module_& m);
void bind_tracking_task(pybind11::module_& m);

}  // namespace neurov::bindings
