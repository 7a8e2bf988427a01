#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "controller_bindings.hpp"
#include "neurov/control/tracking_error.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

void bind_tracking_error(py::module_& m) {
  m.def(
      "tracking_error",
      [](const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& eta_d, const typed::ArrayLike& eta_d_dot,
         const typed::ArrayLike& eta_d_ddot, const typed::ArrayLike& lambda_) {
        TrackingError<double> e;
        const Status s = compute_tracking_error<double>(
            py_args::vector<6>(eta, "eta"), py_args::vector<6>(nu, "nu"),
            py_args::vector<6>(eta_d, "eta_d"), py_args::vector<6>(eta_d_dot, "eta_d_dot"),
            py_args::vector<6>(eta_d_ddot, "eta_d_ddot"), py_args::vector<6>(lambda_, "lambda_"),
            e);
        raise_step_status(s);
        return tracking_dict(e);
      },
      py::arg("eta"), py::arg("nu"), py::arg("eta_d"), py::arg("eta_d_dot"), py::arg("eta_d_ddot"),
      py::arg("lambda_"),
      "Tracking error and virtual reference (eq. 11, 14-16) with the diagonal Lambda (6,): a "
      "dict of (6,) arrays eta_tilde, eta_tilde_dot, s, eta_r_dot, eta_r_ddot, nu_r, nu_r_dot.");
}

}  // namespace neurov::bindings
