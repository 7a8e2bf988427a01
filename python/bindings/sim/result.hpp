// A SimulationResult as the dict of numpy arrays that run_closed_loop and
// Simulator.result() return.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "neurov/sim/result.hpp"
#include "typed_args.hpp"

namespace neurov::bindings {

/// Copies `r` (a Simulator keeps its result).
neurov::typed::SimulationResultDict result_dict(const SimulationResult<double>& r);
/// Takes the arrays out of `r` without copying them (numpy views them).
neurov::typed::SimulationResultDict result_dict(SimulationResult<double>&& r);
/// The series' names, comma-separated, in the table's order (for docstrings).
std::string result_series_names();

}  // namespace neurov::bindings
