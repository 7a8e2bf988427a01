// One function per binding file; module.cpp calls them in order.
#pragma once

#include <pybind11/pybind11.h>

namespace neurov::bindings {

void bind_kinematics(pybind11::module_& m);
void bind_vehicle(pybind11::module_& m);
void bind_controllers(pybind11::module_& m);
void bind_thrusters(pybind11::module_& m);
void bind_sim_config(pybind11::module_& m);
void bind_simulator(pybind11::module_& m);
void bind_closed_loop(pybind11::module_& m);
void bind_bench(pybind11::module_& m);  // private timing helpers (bench/compare.py)

}  // namespace neurov::bindings
