#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <string>

#include "bindings.hpp"
#include "neurov/model/kinematics.hpp"
#include "numpy_args.hpp"
#include "typed_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec6 = Vector6<double>;
using Mat6 = Matrix6<double>;

namespace {

/// J and J_dot divide by cos(theta): refuse a pose at the singularity.
void require_regular(const EulerTrig<double>& trig, const Vec6& eta, const char* name) {
  if (trig.status == Status::near_singularity) {
    throw py::value_error(std::string("argument '") + name + "': pitch theta = " +
                          py_args::num(eta(4)) +
                          " rad is at the Euler-angle singularity (|cos(theta)| < " +
                          py_args::num(singularity_threshold<double>()) + ")");
  }
}

/// `name(eta)`: f of the pose eta, checked as (6,) and named in its errors.
template <typename F>
void def_of_pose(py::module_& m, const char* name, F f, const char* doc) {
  m.def(
      name, [f](const typed::ArrayLike& eta) { return f(py_args::vector<6>(eta, "eta")); }, py::arg("eta"),
      doc);
}

}  // namespace

void bind_kinematics(py::module_& m) {
  m.def(
      "rotation",
      [](const typed::Real& phi, const typed::Real& theta, const typed::Real& psi) {
        return Matrix3<double>(rotation(py_args::scalar(phi, "phi"),
                                        py_args::scalar(theta, "theta"),
                                        py_args::scalar(psi, "psi")));
      },
      py::arg("phi"), py::arg("theta"), py::arg("psi"),
      "Rotation matrix R = Rz(psi) Ry(theta) Rx(phi) (ZYX Euler angles, body to NED), "
      "shape (3, 3).");

  m.def("singularity_threshold", &singularity_threshold<double>,
        "|cos(theta)| below which the Euler-angle transform counts as singular "
        "(sqrt of machine epsilon).");

  def_of_pose(
      m, "is_near_singularity",
      [](const Vec6& e) {
        return EulerTrig<double>::from_pose(e).status == Status::near_singularity;
      },
      "True if the pose eta (6,) has its pitch at the Euler-angle singularity.");

  def_of_pose(
      m, "jacobian",
      [](const Vec6& e) {
        const auto k = EulerKinematics<double>::from_pose(e);
        require_regular(k.trig, e, "eta");
        return Mat6(k.jacobian());
      },
      "J(eta) = blockdiag(R, T), shape (6, 6), so that eta_dot = J(eta) @ nu. "
      "Raises ValueError at the pitch singularity (cos(theta) = 0).");

  def_of_pose(
      m, "jacobian_inverse",
      [](const Vec6& e) { return Mat6(EulerKinematics<double>::from_pose(e).jacobian_inverse()); },
      "J(eta)^-1 = blockdiag(R^T, T^-1) in closed form, shape (6, 6). T^-1 has no "
      "division, so this is defined (but rank deficient) at the singularity.");

  m.def(
      "to_body",
      [](const typed::ArrayLike& eta_in, const typed::ArrayLike& vectors_in) {
        const auto eta = py_args::real(eta_in, "eta", {-1, 6}, false, "(K, 6)");
        const py::ssize_t k_runs = eta.shape(0);
        const auto v = py_args::real(vectors_in, "vectors", {k_runs, -1, 6}, false,
                                     "(" + std::to_string(k_runs) + ", M, 6)");
        const py::ssize_t m_vectors = v.shape(1);
        py::array_t<double> out({k_runs, m_vectors, py::ssize_t{6}});
        const double* e = eta.data();
        const double* in = v.data();
        double* o = out.mutable_data();
        for (py::ssize_t k = 0; k < k_runs; ++k) {
          const Mat6 j = EulerKinematics<double>::from_pose(Eigen::Map<const Vec6>(e + 6 * k))
                             .jacobian_inverse();
          for (py::ssize_t i = 0; i < m_vectors; ++i) {
            const py::ssize_t at = 6 * (k * m_vectors + i);
            Eigen::Map<Vec6>(o + at).noalias() = j * Eigen::Map<const Vec6>(in + at);
          }
        }
        return out;
      },
      py::arg("eta"), py::arg("vectors"),
      "J(eta_k)^-1 v_ki for K poses eta (K, 6) and M vectors each, vectors (K, M, 6): the "
      "earth-frame vectors in each pose's body frame, shape (K, M, 6), in one call.");

  m.def(
      "jacobian_dot",
      [](const typed::ArrayLike& eta, const typed::ArrayLike& nu) {
        const Vec6 e = py_args::vector<6>(eta, "eta");
        const Vec6 n = py_args::vector<6>(nu, "nu");
        const auto k = EulerKinematics<double>::from_pose(e);
        require_regular(k.trig, e, "eta");
        const Mat6 jd = k.jacobian_dot(n);
        if (!jd.allFinite())
          throw py::value_error("argument 'nu' is so large that J_dot overflows");
        return jd;
      },
      py::arg("eta"), py::arg("nu"),
      "Time derivative of J along the motion eta_dot = J(eta) nu, in closed form, "
      "shape (6, 6). Raises ValueError at the pitch singularity.");
}

}  // namespace neurov::bindings
