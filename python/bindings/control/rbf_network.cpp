#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <string>

#include "bindings.hpp"
#include "neurov/control/rbf_network.hpp"
#include "numpy_args.hpp"
#include "snapshot.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Network = RbfNetwork<double>;  // dynamic inputs and centres

namespace {

Eigen::VectorXd widths_arg(py::handle width, Eigen::Index n) {
  if (py::isinstance<py::float_>(width) || py::isinstance<py::int_>(width))
    return Eigen::VectorXd::Constant(n, py_args::scalar(width, "width"));
  return py_args::dynamic_vector(width, "width", n);
}

}  // namespace

void bind_rbf_network(py::module_& m) {
  m.attr("MAX_CENTRES") = kMaxCentres;
  py::class_<Network> network(m, "RbfNetwork",
                      "Radial-basis-function network (eq. 30): g_j(x) = exp(-||x_hat - xi_j||^2 / "
                      "(2 sigma_j^2)), output W g(x) with W (6, N); x_hat = (x - input_offset) * "
                      "input_scale.");
  network
      .def(py::init([](const typed::ArrayLike& centres, const typed::RealOrArrayLike& width, const typed::OptionalArrayLike& input_offset,
                       const typed::OptionalArrayLike& input_scale) {
             // One centre per row: a 1-D array is a common slip, named as such.
             const auto arr = py_args::real_array(centres, "centres", "(N, n_in)");
             if (arr.ndim() != 2)
               throw py::value_error(
                   "argument 'centres' must have shape (N, n_in), one centre per row; got " +
                   py_args::shape_string(arr));
             const Eigen::MatrixXd c = py_args::dynamic_matrix(centres, "centres", -1, -1);
             if (c.rows() < 1 || c.cols() < 1)
               throw py::value_error("argument 'centres' must have at least one row and column");
             const Eigen::VectorXd w = widths_arg(width, c.rows());
             const Eigen::VectorXd off = input_offset.is_none()
                                             ? Eigen::VectorXd::Zero(c.cols())
                                             : py_args::dynamic_vector(input_offset, "input_offset",
                                                                       c.cols());
             const Eigen::VectorXd sc = input_scale.is_none()
                                            ? Eigen::VectorXd::Ones(c.cols())
                                            : py_args::dynamic_vector(input_scale, "input_scale",
                                                                      c.cols());
             Network n;
             py_args::raise_if_invalid(Network::create(c, w, off, sc, n), "RBF network");
             return n;
           }),
           py::arg("centres"), py::arg("width"), py::arg("input_offset") = py::none(),
           py::arg("input_scale") = py::none(),
           "centres: (N, n_in) array, one centre per row, N at most MAX_CENTRES (65536); width: "
           "sigma for every centre, or "
           "(N,) per centre, > 0; input_offset and input_scale: (n_in,) input normalisation, "
           "default identity (the paper's choice). Weights start at zero.")
      .def(
          "basis",
          [](const Network& n, const typed::ArrayLike& x) {
            const Eigen::VectorXd xv = py_args::dynamic_vector(x, "x", n.inputs());
            Eigen::VectorXd g(n.centres_count());
            n.basis(xv, g);
            return g;
          },
          py::arg("x"), "Basis values g(x), shape (N,).")
      .def(
          "output",
          [](const Network& n, const typed::ArrayLike& x) {
            const Eigen::VectorXd xv = py_args::dynamic_vector(x, "x", n.inputs());
            Eigen::VectorXd g(n.centres_count());
            Eigen::Matrix<double, 6, 1> y;
            n.output(xv, g, y);
            return Vec6(y);
          },
          py::arg("x"), "Network output W g(x), shape (6,).")
      .def_property(
          "weights", [](const Network& n) { return Eigen::MatrixXd(n.weights()); },
          [](Network& n, const typed::ArrayLike& w) {
            const Eigen::MatrixXd wm = py_args::dynamic_matrix(w, "weights", 6, n.centres_count());
            n.set_weights(wm);
          },
          "Output weights W, shape (6, N); assignable.")
      .def_property_readonly("n_inputs", &Network::inputs, "Number of inputs n_in.");
  def_network_views(network, [](const Network& n) -> const Network& { return n; });
  def_copy<Network>(network);
  network.def(py::pickle(
      [](const Network& n) {
        py::dict d;
        network_state(n, d);
        d["weights"] = Eigen::MatrixXd(n.weights());
        return d;
      },
      [](const py::dict& d) {
        Network n = network_from_state<Network>(d, -1, "RBF network");
        raise_unless_restored(
            n.set_weights(py_args::dynamic_matrix(snapshot_field(d, "weights"), "weights", 6,
                                                  n.centres_count())),
            "RBF network");
        return n;
      }));
  // Private: neurov.kernels.kernel_path() is the public face (NEUROV_KERNEL pins it).
  m.def("_kernel_isa", [] { return std::string(detail::kernel_isa_name()); },
        "Which copy of the RBF loops runs on this CPU (avx512, avx2, generic).");
}

}  // namespace neurov::bindings
