#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <utility>

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
}

}  // namespace neurov::bindings
