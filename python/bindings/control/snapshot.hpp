// Snapshots of the controllers, the reference model and the RBF network
// (and the network's views, shared by the network and the NN controller):
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

/// The (N,) vector a snapshot holds under `key`, errors naming the key.
template <int N>
Eigen::Matrix<double, N, 1> snapshot_vector(const py::dict& d, const char* key) {
  return py_args::vector<N>(snapshot_field(d, key), key);
}

inline TrackingError<double> tracking_from_dict(const py::dict& d) {
  const py::dict t = snapshot_field(d, "tracking").cast<py::dict>();
  TrackingError<double> e;
  for (const TrackingField& f : kTrackingFields) e.*(f.member) = snapshot_vector<6>(t, f.name);
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

/// An RBF network's structure in a snapshot: centres, widths, input normalisation.
template <typename Network>
void network_state(const Network& n, py::dict& d) {
  d["centres"] = Eigen::MatrixXd(n.centres());
  d["widths"] = Eigen::VectorXd(n.widths());
  d["input_offset"] = Eigen::VectorXd(n.input_offset());
  d["input_scale"] = Eigen::VectorXd(n.input_scale());
}

/// The network of a snapshot (weights zero); `inputs` -1 for any number.
template <typename Network>
Network network_from_state(const py::dict& d, Eigen::Index inputs, const char* what) {
  const Eigen::MatrixXd c = py_args::dynamic_matrix(snapshot_field(d, "centres"), "centres", -1, inputs);
  Network n;
  py_args::raise_if_invalid(
      Network::create(c, py_args::dynamic_vector(snapshot_field(d, "widths"), "widths", c.rows()),
                      py_args::dynamic_vector(snapshot_field(d, "input_offset"), "input_offset", c.cols()),
                      py_args::dynamic_vector(snapshot_field(d, "input_scale"), "input_scale", c.cols()),
                      n),
      what);
  return n;
}

/// The read-only views of the network `net(x)` of each x: centres, widths,
/// input normalisation, N.
template <typename T, typename Net>
void def_network_views(py::class_<T>& cls, Net net) {
  cls.def_property_readonly("centres", [net](const T& x) { return Eigen::MatrixXd(net(x).centres()); },
                            "Centres, shape (N, n_in).")
      .def_property_readonly("widths", [net](const T& x) { return Eigen::VectorXd(net(x).widths()); },
                             "Widths sigma_j, shape (N,).")
      .def_property_readonly("input_offset",
                             [net](const T& x) { return Eigen::VectorXd(net(x).input_offset()); },
                             "Input offset of the network's normalisation, shape (n_in,).")
      .def_property_readonly("input_scale",
                             [net](const T& x) { return Eigen::VectorXd(net(x).input_scale()); },
                             "Input scale of the network's normalisation, shape (n_in,).")
      .def_property_readonly("n_centres", [net](const T& x) { return net(x).centres_count(); },
                             "Number of centres N.");
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

}  // namespace neurov::bindings
