#include "result.hpp"

#include <pybind11/eigen.h>

namespace neurov::bindings {

pybind11::dict result_dict(const SimulationResult<double>& r) {
  pybind11::dict d;
  d["t"] = r.t;
  d["eta"] = r.eta;
  d["nu"] = r.nu;
  d["eta_d"] = r.eta_d;
  d["eta_d_dot"] = r.eta_d_dot;
  d["tau_demanded"] = r.tau_demanded;
  d["tau_applied"] = r.tau_applied;
  d["disturbance"] = r.disturbance;
  d["s"] = r.s;
  d["thrusts"] = r.thrusts;
  d["theta"] = r.theta;
  d["adaptive_norm"] = r.adaptive_norm;
  d["controller_status"] = r.controller_status;
  d["plant_status"] = r.plant_status;
  d["faults"] = r.faults;
  d["current"] = r.current;
  d["wave_velocity"] = r.wave_velocity;
  d["wave_elevation"] = r.wave_elevation;
  d["payload_mass"] = r.payload_mass;
  d["diverged"] = r.diverged;
  return d;
}

}  // namespace neurov::bindings
