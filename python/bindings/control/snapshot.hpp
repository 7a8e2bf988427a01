// Snapshots of the controllers, the reference model and the RBF network:
// pickle stores the configuration and every remembered quantity as named
// fields (numpy arrays and numbers, never the object's bytes), and restores
// through create() and the classes' own restore(), so a restored object
// steps exactly as the original. copy and deepcopy use the C++ copy.
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "controller_bindings.hpp"
#include "neurov/control/tracking_error.hpp"
#include "neurov/core/status.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

/// The value a snapshot holds under `key`; ValueError naming the key if absent.
inline py::object snapshot_field(const py::dict& d, const char* key) {
  if (!d.contains(key))
    throw py::value_error(std::string("snapshot: field '") + key + "' is missing");
  return d[key];
}

inline TrackingError<double> tracking_from_dict(const py::dict& d) {
  const py::dict t = snapshot_field(d, "tracking").cast<py::dict>();
  TrackingError<double> e;
  e.eta_tilde = py_args::vector<6>(snapshot_field(t, "eta_tilde"), "eta_tilde");
  e.eta_tilde_dot = py_args::vector<6>(snapshot_field(t, "eta_tilde_dot"), "eta_tilde_dot");
  e.s = py_args::vector<6>(snapshot_field(t, "s"), "s");
  e.eta_r_dot = py_args::vector<6>(snapshot_field(t, "eta_r_dot"), "eta_r_dot");
  e.eta_r_ddot = py_args::vector<6>(snapshot_field(t, "eta_r_ddot"), "eta_r_ddot");
  e.nu_r = py_args::vector<6>(snapshot_field(t, "nu_r"), "nu_r");
  e.nu_r_dot = py_args::vector<6>(snapshot_field(t, "nu_r_dot"), "nu_r_dot");
  return e;
}

/// The fields every controller's snapshot has: config, tracking, status.
template <typename Controller>
py::dict controller_state(const Controller& c) {
  py::dict d;
  d["config"] = py::cast(c.config());
  d["tracking"] = tracking_dict(c.tracking());
  d["status"] = static_cast<int>(c.last_status());
  return d;
}

inline Status status_from_dict(const py::dict& d) {
  return static_cast<Status>(snapshot_field(d, "status").cast<std::uint8_t>());
}

inline void raise_unless_restored(bool ok, const char* what) {
  if (!ok)
    throw py::value_error(std::string("snapshot of the ") + what +
                          " holds a non-finite value, an unknown status or a wrong size");
}

/// __copy__ and __deepcopy__ through the C++ copy constructor.
template <typename T, typename Class>
void def_copy(Class& cls) {
  cls.def("__copy__", [](const T& self) { return T(self); })
      .def("__deepcopy__", [](const T& self, const py::dict&) { return T(self); },
           py::arg("memo"));
}

/// Pickle and copy for a controller built by create(config): `extra(c, d)`
/// adds its own fields to the state dict, `restore(c, d, e, s)` puts the
/// whole state back (false for a bad one).
template <typename Controller, typename Class, typename Extra, typename Restore>
void def_controller_snapshot(Class& cls, const char* what, Extra extra, Restore restore) {
  def_copy<Controller>(cls);
  cls.def(py::pickle(
      [extra](const Controller& c) {
        py::dict d = controller_state(c);
        extra(c, d);
        return d;
      },
      [what, restore](const py::dict& d) {
        Controller c = from_config<Controller>(
            snapshot_field(d, "config").cast<typename Controller::Config>(), what);
        raise_unless_restored(restore(c, d, tracking_from_dict(d), status_from_dict(d)), what);
        return c;
      }));
}

/// The snapshot's last model output f of a controller on ModelControllerBase.
inline Vector6<double> model_output_from(const py::dict& d) {
  return py_args::vector<6>(snapshot_field(d, "model_output"), "model_output");
}

/// The read-only property model_output of a controller on ModelControllerBase.
template <typename Controller, typename Class>
void def_model_output(Class& cls, const char* doc) {
  cls.def_property_readonly(
      "model_output", [](const Controller& c) { return Vector6<double>(c.model_output()); }, doc);
}

/// Snapshot and model_output of a controller whose only state of its own is
/// the last model output (sliding mode, computed torque).
template <typename Controller, typename Class>
void def_model_controller(Class& cls, const char* what, const char* output_doc) {
  def_controller_snapshot<Controller>(
      cls, what,
      [](const Controller& c, py::dict& d) {
        d["model_output"] = Vector6<double>(c.model_output());
      },
      [](Controller& c, const py::dict& d, const TrackingError<double>& e, Status s) {
        return c.restore(e, s, model_output_from(d));
      });
  def_model_output<Controller>(cls, output_doc);
}

}  // namespace neurov::bindings
