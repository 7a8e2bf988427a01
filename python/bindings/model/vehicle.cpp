#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "neurov/model/integrator.hpp"
#include "neurov/model/vehicle.hpp"
#include "numpy_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;
using Vec3 = Vector3<double>;
using Vec6 = Vector6<double>;
using Mat6 = Matrix6<double>;
using Params = VehicleParameters<double>;

namespace {

CoriolisForm parse_coriolis_form(const py::handle& obj) {
  return py_args::choice(obj, "coriolis_form", {"velocity_independent", "kirchhoff"}) ==
                 "kirchhoff"
             ? CoriolisForm::kirchhoff
             : CoriolisForm::velocity_independent;
}

const char* coriolis_form_name(CoriolisForm f) {
  return f == CoriolisForm::kirchhoff ? "kirchhoff" : "velocity_independent";
}

Vehicle<double> make_vehicle(const Params& p) {
  Vehicle<double> v;
  py_args::raise_if_invalid(Vehicle<double>::create(p, v), "vehicle parameter");
  return v;
}

typed::AnyDict parameters_dict(const Params& p) {
  py::dict d;
  d["mass"] = p.mass;
  d["inertia"] = Matrix3<double>(p.inertia);
  d["centre_of_gravity"] = Vec3(p.centre_of_gravity);
  d["centre_of_buoyancy"] = Vec3(p.centre_of_buoyancy);
  d["weight"] = p.weight;
  d["buoyancy"] = p.buoyancy;
  d["added_mass"] = Mat6(p.added_mass);
  d["linear_damping"] = Vec6(p.linear_damping);
  d["quadratic_damping"] = Vec6(p.quadratic_damping);
  d["coriolis_form"] = coriolis_form_name(p.coriolis_form);
  return d;
}

void raise_status(Status s, const char* what) {
  switch (s) {
    case Status::ok:
      return;
    case Status::near_singularity:
      throw py::value_error(std::string(what) +
                            ": argument 'eta' has its pitch at the Euler-angle singularity "
                            "(cos(theta) = 0)");
    case Status::non_finite_output:
      throw py::value_error(std::string(what) +
                            ": the result overflowed to a non-finite number; the inputs are "
                            "outside the model's range");
    default:
      throw py::value_error(std::string(what) + " failed: " + to_string(s));
  }
}

/// The arguments of neurov::rk4_segments (model/integrator.hpp) checked, and
/// its velocities as a (sum(steps) + S, 6) array.
py::array_t<double> rk4_segments(const Vehicle<double>& v, const py::handle& eta0_in, const py::handle& nu0_in,
                                 const py::handle& steps_in, const py::handle& tau_in, const py::handle& dt_in,
                                 const py::handle& current_in, const py::handle& substeps_in) {
  const char* where = "rk4_segments";
  const py::array steps_any = py::array::ensure(steps_in);
  if (!steps_any || steps_any.ndim() != 1 || (steps_any.dtype().kind() != 'i' && steps_any.dtype().kind() != 'u'))
    throw py::type_error(std::string(where) + ": argument 'steps' must be a 1-d integer array (intervals per "
                         "segment), got " + std::string(py::str(py::type::handle_of(steps_in).attr("__name__"))));
  const auto steps = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(steps_any);
  const py::ssize_t segments = steps.shape(0);
  py::ssize_t intervals = 0;
  for (py::ssize_t i = 0; i < segments; ++i) {
    if (steps.data()[i] < 0)
      throw py::value_error(std::string(where) + ": argument 'steps' must be >= 0; element " + std::to_string(i) +
                            " is " + std::to_string(steps.data()[i]));
    intervals += steps.data()[i];
  }
  const int substeps = py_args::integer<int>(substeps_in, "substeps");
  if (substeps < 1) throw py::value_error(std::string(where) + ": substeps must be >= 1, got " + std::to_string(substeps));
  const auto eta0 = py_args::real_rows(eta0_in, "eta0", segments, 6);
  const auto nu0 = py_args::real_rows(nu0_in, "nu0", segments, 6);
  const auto tau = py_args::real_rows(tau_in, "tau", intervals, 6);
  const auto dt = py_args::real_rows(dt_in, "dt", intervals, -1);
  py::array_t<double, py::array::c_style> current;
  if (!current_in.is_none()) current = py_args::real_rows(current_in, "current", intervals, 3);
  for (py::ssize_t k = 0; k < intervals; ++k)
    if (detail::check_step("dt", dt.data()[k] / substeps))
      throw py::value_error(std::string(where) + ": argument 'dt' divided by substeps must be > 0 and <= " +
                            py_args::num(kMaxStep) + " s; element " + std::to_string(k) + " is " +
                            py_args::num(dt.data()[k]));
  py::array_t<double> out(std::vector<py::ssize_t>{intervals + segments, 6});
  SegmentFailure failed;
  {
    py::gil_scoped_release release;
    failed = rk4_segments(v, static_cast<std::size_t>(segments), eta0.data(), nu0.data(), steps.data(), tau.data(),
                          dt.data(), current.size() ? current.data() : nullptr, substeps, out.mutable_data());
  }
  if (failed.status != Status::ok)
    raise_status(failed.status, (std::string(where) + ": segment " + std::to_string(failed.segment) + ", step " +
                                 std::to_string(failed.step))
                                    .c_str());
  return out;
}

/// A read-only property: a copy of the vehicle's parameter `member`.
template <typename D>
void def_parameter(py::class_<Vehicle<double>>& cls, const char* name, D Params::*member,
                   const char* doc) {
  cls.def_property_readonly(
      name, [member](const Vehicle<double>& v) { return D(v.parameters().*member); }, doc);
}

/// `name(arg)`: f of the vehicle and one (6,) argument, checked and named
/// `arg` in its errors.
template <typename F>
void def_of_vector6(py::class_<Vehicle<double>>& cls, const char* name, const char* arg, F f,
                    const char* doc) {
  cls.def(
      name,
      [arg, f](const Vehicle<double>& v, const typed::ArrayLike& x) { return f(v, py_args::vector<6>(x, arg)); },
      py::arg(arg), doc);
}

}  // namespace

void bind_vehicle(py::module_& m) {
  py::class_<Vehicle<double>> vehicle(
      m, "Vehicle",
      "A 6-DOF vehicle in Fossen's form, M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau.\n\n"
      "Build one with Vehicle.nerov(), Vehicle.preset('bluerov2_heavy'), Vehicle.from_file(path) "
      "or Vehicle(mass=..., ...). Parameters are validated: a bad one raises ValueError "
      "naming the field.");
  vehicle
      .def(py::init([](const typed::Real& mass, const typed::ArrayLike& inertia, const typed::Real& weight, const typed::Real& buoyancy,
                       const typed::ArrayLike& added_mass, const typed::ArrayLike& linear_damping,
                       const typed::ArrayLike& quadratic_damping, const typed::OptionalArrayLike& centre_of_gravity,
                       const typed::OptionalArrayLike& centre_of_buoyancy, const typed::Str& coriolis_form) {
             Params p;
             p.mass = py_args::scalar(mass, "mass");
             p.inertia = py_args::matrix_or_diagonal<3>(inertia, "inertia");
             p.weight = py_args::scalar(weight, "weight");
             p.buoyancy = py_args::scalar(buoyancy, "buoyancy");
             p.added_mass = py_args::matrix_or_diagonal<6>(added_mass, "added_mass");
             p.linear_damping = py_args::vector<6>(linear_damping, "linear_damping");
             p.quadratic_damping = py_args::vector<6>(quadratic_damping, "quadratic_damping");
             if (!centre_of_gravity.is_none())
               p.centre_of_gravity = py_args::vector<3>(centre_of_gravity, "centre_of_gravity");
             if (!centre_of_buoyancy.is_none())
               p.centre_of_buoyancy = py_args::vector<3>(centre_of_buoyancy, "centre_of_buoyancy");
             p.coriolis_form = parse_coriolis_form(coriolis_form);
             return make_vehicle(p);
           }),
           py::kw_only(), py::arg("mass"), py::arg("inertia"), py::arg("weight"),
           py::arg("buoyancy"), py::arg("added_mass"), py::arg("linear_damping"),
           py::arg("quadratic_damping"), py::arg("centre_of_gravity") = py::none(),
           py::arg("centre_of_buoyancy") = py::none(),
           py::arg("coriolis_form") = "velocity_independent",
           "Builds a vehicle from its parameters (SI units, body axes with z down):\n"
           "mass [kg]; inertia (3, 3) about the body origin, or its diagonal (3,);\n"
           "weight W and buoyancy B [N]; added_mass M_A (6, 6) or its diagonal (6,), "
           "positive (M_A = -diag(X_udot, ...));\n"
           "linear_damping and quadratic_damping (6,): D(nu) = diag(lin + quad * |nu|);\n"
           "centre_of_gravity r_g and centre_of_buoyancy r_b (3,) [m], default zero;\n"
           "coriolis_form: 'velocity_independent' (the paper's eq. 39, default) or "
           "'kirchhoff'.")
      .def_static(
          "nerov", [] { return make_vehicle(nerov_parameters<double>()); },
          "NEROV, the paper's vehicle, with the numbers of its section 5.")
      .def("__copy__", [](const Vehicle<double>& v) { return Vehicle<double>(v); })
      .def("__deepcopy__", [](const Vehicle<double>& v, const py::dict&) { return Vehicle<double>(v); },
           py::arg("memo"))
      .def(py::pickle(
          [](const Vehicle<double>& v) { return parameters_dict(v.parameters()); },
          [](const py::dict& d) {
            // The keyword constructor, so an unpickled vehicle is validated like any other.
            return py::type::of<Vehicle<double>>()(**d).cast<Vehicle<double>>();
          }))
      .def("parameters", [](const Vehicle<double>& v) { return parameters_dict(v.parameters()); },
           "The parameters as a dict of keyword arguments: Vehicle(**v.parameters()) "
           "rebuilds the vehicle, so a perturbed copy is one dict edit away.");
  def_parameter(vehicle, "mass", &Params::mass, "m [kg].");
  def_parameter(vehicle, "inertia", &Params::inertia, "I_o about the body origin (3, 3) [kg m^2].");
  def_parameter(vehicle, "centre_of_gravity", &Params::centre_of_gravity,
                "r_g (3,) [m], body axes.");
  def_parameter(vehicle, "centre_of_buoyancy", &Params::centre_of_buoyancy,
                "r_b (3,) [m], body axes (z down).");
  def_parameter(vehicle, "weight", &Params::weight, "W [N].");
  def_parameter(vehicle, "buoyancy", &Params::buoyancy, "B [N].");
  def_parameter(vehicle, "added_mass", &Params::added_mass, "M_A (6, 6), positive definite.");
  def_parameter(vehicle, "linear_damping", &Params::linear_damping, "D_L (6,).");
  def_parameter(vehicle, "quadratic_damping", &Params::quadratic_damping, "D_Q (6,).");
  vehicle
      .def_property_readonly(
          "coriolis_form",
          [](const Vehicle<double>& v) { return coriolis_form_name(v.parameters().coriolis_form); },
          "'velocity_independent' (the paper's eq. 39) or 'kirchhoff'.")
      .def("mass_matrix", [](const Vehicle<double>& v) { return Mat6(v.mass_matrix()); },
           "M = M_RB + M_A, shape (6, 6).");
  def_of_vector6(
      vehicle, "coriolis", "nu",
      [](const Vehicle<double>& v, const Vec6& nu) { return Mat6(v.coriolis(nu)); },
      "C(nu) = C_RB(nu) + C_A(nu), skew-symmetric, shape (6, 6).");
  def_of_vector6(
      vehicle, "damping", "nu",
      [](const Vehicle<double>& v, const Vec6& nu) { return Mat6(v.damping(nu)); },
      "D(nu) = diag(D_L + D_Q |nu|), shape (6, 6).");
  def_of_vector6(
      vehicle, "restoring", "eta",
      [](const Vehicle<double>& v, const Vec6& eta) { return Vec6(v.restoring(eta)); },
      "g(eta): gravity and buoyancy forces and moments, shape (6,).");
  vehicle.def(
      "acceleration",
      [](const Vehicle<double>& v, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& tau,
         const typed::OptionalArrayLike& current) {
        const auto a = py_args::plant_args(eta, nu, tau, current);
        Vec6 nu_dot;
        raise_status(v.acceleration(a.eta, a.nu, a.tau, a.current, nu_dot), "acceleration");
        return nu_dot;
      },
      py::arg("eta"), py::arg("nu"), py::arg("tau"), py::arg("current") = py::none(),
      "nu_dot = M^-1 (tau - C(nu) nu - D(nu) nu - g(eta)), shape (6,). With `current` "
      "(3,), a constant NED current velocity [m/s], the hydrodynamic terms use the "
      "relative velocity nu - nu_c.");

  m.def(
      "rk4_step",
      [](const Vehicle<double>& v, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& tau, const typed::Real& dt,
         const typed::OptionalArrayLike& current) {
        auto a = py_args::plant_args(eta, nu, tau, current);
        const double h = py_args::step(dt, "dt");
        raise_status(rk4_step(v, a.eta, a.nu, a.tau, h, a.current), "rk4_step");
        return std::make_pair(a.eta, a.nu);
      },
      py::arg("vehicle"), py::arg("eta"), py::arg("nu"), py::arg("tau"), py::arg("dt"),
      py::arg("current") = py::none(),
      "One fixed-step RK4 step of the 12-state plant with tau held over the step; returns "
      "the new (eta, nu). `current` (3,) is a constant NED current velocity [m/s].");
  m.def(
      "rk4_segments",
      [](const Vehicle<double>& v, const typed::ArrayLike& eta0, const typed::ArrayLike& nu0,
         const typed::ArrayLike& steps, const typed::ArrayLike& tau, const typed::ArrayLike& dt,
         const typed::OptionalArrayLike& current, const typed::Index& substeps) {
        return rk4_segments(v, eta0, nu0, steps, tau, dt, current, substeps);
      },
      py::arg("vehicle"), py::arg("eta0"), py::arg("nu0"), py::arg("steps"), py::arg("tau"), py::arg("dt"),
      py::arg("current") = py::none(), py::arg("substeps") = 1,
      "S open-loop runs of the vehicle, each from its own state, driven by recorded forces (the "
      "output error's shooting segments): segment i starts from eta0[i], nu0[i] ((S, 6) each) and "
      "takes steps[i] intervals ((S,) integers >= 0); interval k, counted over the segments in "
      "order (N = sum(steps)), holds tau[k] ((N, 6)) and current[k] ((N, 3) NED [m/s], None: still "
      "water) over dt[k] ((N,) [s]), in `substeps` rk4_step calls of dt[k] / substeps. Returns the "
      "body velocities at each segment's rows 0..steps[i], stacked: (N + S, 6). The same steps as "
      "rk4_step called in that order, without Python between them; the GIL is released. Raises "
      "ValueError naming the segment and step where a step fails (as rk4_step would).");
}

}  // namespace neurov::bindings
