#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <tuple>

#include "bindings.hpp"
#include "controller_bindings.hpp"
#include "neurov/control/reference_model.hpp"
#include "numpy_args.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;

void bind_reference_model(py::module_& m) {
  using Reference = ReferenceModel<double>;
  py::class_<Reference> reference(
      m, "ReferenceModel",
      "Reference model of eq. 12-13: nu_d_dot = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d), "
      "eta_d_dot = J(eta_d) nu_d. Turns a commanded pose r into a smooth desired trajectory.");
  reference
      .def(py::init([](const typed::ArrayLike& lambda_d, const typed::ArrayLike& omega, const typed::OptionalArrayLike& eta0) {
             const Vec6 ld = py_args::vector<6>(lambda_d, "lambda_d");
             const Vec6 om = py_args::vector<6>(omega, "omega");
             const Vec6 e0 = eta0.is_none() ? Vec6::Zero() : py_args::vector<6>(eta0, "eta0");
             ReferenceModel<double> r;
             py_args::raise_if_invalid(ReferenceModel<double>::create(ld, om, e0, r),
                                       "reference model");
             return r;
           }),
           py::arg("lambda_d"), py::arg("omega"), py::arg("eta0") = py::none(),
           "lambda_d: damping diagonal (6,), > 0; omega: stiffness diagonal (6,), > 0; eta0: "
           "initial pose (6,), default zero. Starts at rest.")
      .def(
          "step",
          [](ReferenceModel<double>& r, const typed::ArrayLike& cmd, const typed::Real& dt) {
            const Vec6 rc = py_args::vector<6>(cmd, "r");
            const double h = py_args::step(dt, "dt");
            DesiredState<double> d;
            const Status s = r.step(rc, h, d);
            if (s != Status::ok) raise_step_status(s);
            return std::make_tuple(Vec6(d.eta_d), Vec6(d.eta_d_dot), Vec6(d.eta_d_ddot));
          },
          py::arg("r"), py::arg("dt"),
          "Advances by dt with the commanded pose r (6,) held (RK4); returns (eta_d, eta_d_dot, "
          "eta_d_ddot). A refused step raises ValueError and changes nothing.")
      .def(
          "reset",
          [](ReferenceModel<double>& r, const typed::ArrayLike& eta0) {
            r.reset(py_args::vector<6>(eta0, "eta0"));
          },
          py::arg("eta0"), "Back to rest at eta0 (6,).")
      .def_property_readonly("eta_d", [](const ReferenceModel<double>& r) { return Vec6(r.eta_d()); },
                             "Current desired pose (6,).")
      .def_property_readonly("nu_d", [](const ReferenceModel<double>& r) { return Vec6(r.nu_d()); },
                             "Current desired body velocity (6,).")
      .def_property_readonly("lambda_d",
                             [](const ReferenceModel<double>& r) { return Vec6(r.lambda_d()); },
                             "Damping diagonal (6,).")
      .def_property_readonly("omega", [](const ReferenceModel<double>& r) { return Vec6(r.omega()); },
                             "Stiffness diagonal (6,).")
      .def_property_readonly(
          "pitch_limited", [](const ReferenceModel<double>& r) { return r.pitch_limited(); },
          "True when the last accepted step limited the pitch to +-(pi/2 - 0.2) rad: the "
          "command's (clamped) or the reference's own (held at the limit). Such a step is taken "
          "and returns normally. False after construction and reset().");
  def_copy<Reference>(reference);
  reference.def(py::pickle(
      [](const Reference& r) {
        py::dict d;
        d["lambda_d"] = Vec6(r.lambda_d());
        d["omega"] = Vec6(r.omega());
        d["eta_d"] = Vec6(r.eta_d());
        d["nu_d"] = Vec6(r.nu_d());
        d["desired_eta_d"] = Vec6(r.desired().eta_d);
        d["desired_eta_d_dot"] = Vec6(r.desired().eta_d_dot);
        d["desired_eta_d_ddot"] = Vec6(r.desired().eta_d_ddot);
        d["pitch_limited"] = r.pitch_limited();
        return d;
      },
      [](const py::dict& d) {
        const Vec6 eta_d = snapshot_vector<6>(d, "eta_d");
        Reference r;
        // create() checks the gains (and puts eta_d in the singular band out).
        py_args::raise_if_invalid(Reference::create(snapshot_vector<6>(d, "lambda_d"),
                                                    snapshot_vector<6>(d, "omega"), eta_d, r),
                                  "reference model");
        DesiredState<double> desired;
        desired.eta_d = snapshot_vector<6>(d, "desired_eta_d");
        desired.eta_d_dot = snapshot_vector<6>(d, "desired_eta_d_dot");
        desired.eta_d_ddot = snapshot_vector<6>(d, "desired_eta_d_ddot");
        raise_unless_restored(r.restore(eta_d, snapshot_vector<6>(d, "nu_d"), desired,
                                        snapshot_field(d, "pitch_limited").cast<bool>()),
                              "reference model");
        return r;
      }));
}

}  // namespace neurov::bindings
