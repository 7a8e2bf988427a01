// neurov/model/thrusters.hpp in Python: the thruster layout (ThrusterConfig,
// field by field) and the allocation of one wrench.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <limits>

#include "bindings.hpp"
#include "fields.hpp"
#include "numpy_args.hpp"
#include "neurov/model/thrusters.hpp"

namespace neurov::bindings {

namespace py = pybind11;

void bind_thrusters(py::module_& m) {
  py::enum_<Saturation>(m, "Saturation", "How thrusts beyond their limits are brought back.")
      .value("scale", Saturation::scale,
             "Every thruster scaled by one factor: the wrench keeps its direction.")
      .value("clip", Saturation::clip, "Each thruster clipped to its limits: the wrench turns.");
  {
    using T = ThrusterConfig<double>;
    py::class_<T> cls(m, "ThrusterConfig",
                      "n thrusters: tau = B u, allocated by the weighted pseudo-inverse, "
                      "saturated, with a first-order lag.");
    Fields<T>(cls, "ThrusterConfig")
        .dynamic_matrix("matrix", &T::matrix, 6, -1, "B (6, n): the wrench of each thruster per unit thrust.")
        .dynamic_vector("min_thrust", &T::min_thrust, "Lower limits [N] (n,), <= 0.")
        .dynamic_vector("max_thrust", &T::max_thrust, "Upper limits [N] (n,), > min_thrust.")
        .dynamic_vector("weights", &T::weights,
               "Allocation weights (n,), > 0; empty means all 1.")
        .value("saturation", &T::saturation, "A Saturation.")
        .value("time_constant", &T::time_constant, "First-order lag [s]; 0 means none.")
        .validator("ThrusterConfig",
                   [](const T& c) {
                     Thrusters<double> t;
                     return Thrusters<double>::create(c, t);
                   })
        .finish();
  }

  m.def(
      "allocate_thrust",
      [](py::handle matrix, py::handle tau, py::handle max_thrust, py::handle min_thrust,
         py::handle saturation, py::handle weights) {
        ThrusterConfig<double> c;
        c.matrix = py_args::dynamic_matrix(matrix, "matrix", 6, -1);
        const auto n = c.matrix.cols();
        c.max_thrust = max_thrust.is_none()
                           ? Eigen::VectorXd::Constant(n, std::numeric_limits<double>::max())
                           : py_args::dynamic_vector(max_thrust, "max_thrust", n);
        c.min_thrust = min_thrust.is_none() ? Eigen::VectorXd(-c.max_thrust)
                                            : py_args::dynamic_vector(min_thrust, "min_thrust", n);
        if (!weights.is_none()) c.weights = py_args::dynamic_vector(weights, "weights", n);
        c.saturation = py_args::choice(saturation, "saturation", {"scale", "clip"}) == "clip"
                           ? Saturation::clip
                           : Saturation::scale;
        Thrusters<double> t;
        py_args::raise_if_invalid(Thrusters<double>::create(c, t), "thrusters");
        t.command(py_args::vector<6>(tau, "tau"));
        t.advance(1.0);
        return py::make_tuple(Eigen::VectorXd(t.thrust()), Vector6<double>(t.wrench()));
      },
      py::arg("matrix"), py::arg("tau"), py::arg("max_thrust") = py::none(),
      py::arg("min_thrust") = py::none(), py::arg("saturation") = "scale",
      py::arg("weights") = py::none(),
      "Allocates a wrench tau (6,) to thrusters with configuration matrix (6, n) by the "
      "weighted pseudo-inverse and saturates ('scale' keeps the direction, 'clip' clips each). "
      "Returns (thrusts (n,), produced wrench (6,)).");
}

}  // namespace neurov::bindings
