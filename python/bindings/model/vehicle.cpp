#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "fields.hpp"
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

CoriolisForm parse_coriolis_form(const py::handle& obj, const char* name) {
  const auto form = py_args::choice(obj, name, {"velocity_independent", "kirchhoff"});
  return form == to_string(CoriolisForm::kirchhoff) ? CoriolisForm::kirchhoff
                                                    : CoriolisForm::velocity_independent;
}

Vehicle<double> make_vehicle(const Params& p) {
  Vehicle<double> v;
  py_args::raise_if_invalid(Vehicle<double>::create(p, v), "vehicle parameter");
  return v;
}

/// f(spec) for each field of VehicleParameters' description, in its order.
template <typename F>
void for_each_parameter(F f) {
  std::apply([&f](const auto&... s) { (f(s), ...); }, config_fields(static_cast<const Params*>(nullptr)));
}

template <typename D>
D python_value(const D& x) { return x; }  // a number or a fresh array
std::string python_value(CoriolisForm f) { return to_string(f); }

/// Keyword argument `name` as its field, named "argument 'name'" in errors.
template <typename D>
D argument(const py::handle& v, const char* name, unsigned flags) {
  if constexpr (std::is_same_v<D, CoriolisForm>) return parse_coriolis_form(v, name);
  else if constexpr (std::is_floating_point_v<D>) return py_args::scalar(v, name);
  else if constexpr (D::ColsAtCompileTime == 1) return py_args::vector<D::RowsAtCompileTime>(v, name);
  else if (flags & kDiagonal) return py_args::matrix_or_diagonal<D::RowsAtCompileTime>(v, name);
  else return D(py_args::dynamic_matrix(v, name, D::RowsAtCompileTime, D::ColsAtCompileTime));
}

/// Vehicle(**kw): each field a keyword argument (None or absent: the default
/// of one not required); TypeError for a missing or unknown one.
Vehicle<double> from_keywords(const py::kwargs& kw) {
  Params p;
  std::string names;
  const auto unused = py::reinterpret_steal<py::dict>(PyDict_Copy(kw.ptr()));
  for_each_parameter([&](const auto& s) {
    names += (names.empty() ? "" : ", ") + std::string(s.name);
    const py::object v = unused.attr("pop")(s.name, py::none());
    if ((s.flags & kRequired) && !kw.contains(s.name))
      throw py::type_error(std::string("Vehicle() missing required keyword argument '") + s.name + "'");
    if (!v.is_none() || (s.flags & kRequired))
      p.*s.member = argument<typename std::decay_t<decltype(s)>::Type>(v, s.name, s.flags);
  });
  for (const auto& item : unused)
    throw py::type_error("Vehicle() got an unexpected keyword argument '" + std::string(py::str(item.first)) +
                         "'; the parameters are " + names);
  return make_vehicle(p);
}

typed::AnyDict parameters_dict(const Params& p) {
  py::dict d;
  for_each_parameter([&](const auto& s) { d[s.name] = python_value(p.*s.member); });
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
                         "segment), got " + py_args::type_name(steps_in));
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

/// The Coriolis form by its name, 'velocity_independent' or 'kirchhoff'.
template <>
struct FieldForm<CoriolisForm> {
  static constexpr bool custom = true;
  template <typename T>
  static void bind(Fields<T>& f, const char* name, CoriolisForm T::*m, const char* doc) {
    f.field(name, [m](const T& c) { return python_value(c.*m); },
            [m](T& c, const typed::Str& v, const std::string& q) { c.*m = parse_coriolis_form(v, q.c_str()); },
            doc);
  }
};

void bind_vehicle(py::module_& m) {
  Fields<Params>::described(m, "VehicleParameters",
                            "A vehicle's parameters (SI units, body axes with z down): Vehicle's "
                            "keyword arguments, its properties and the vehicle files' keys.")
      .validator("vehicle parameter")
      .finish();
  py::class_<Vehicle<double>> vehicle(
      m, "Vehicle",
      "A 6-DOF vehicle in Fossen's form, M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau.\n\n"
      "Build one with Vehicle.nerov(), Vehicle.preset('bluerov2_heavy'), Vehicle.from_file(path) "
      "or Vehicle(mass=..., ...). Parameters are validated: a bad one raises ValueError "
      "naming the field.");
  vehicle
      .def(py::init(&from_keywords),
           "Builds a vehicle from its parameters, each a keyword argument named as a field of "
           "VehicleParameters (FIELDS gives its unit, rule and shape; a square matrix may be given "
           "as its diagonal). The required ones must be given; the others, absent or None, are "
           "zero and 'velocity_independent'.")
      .def_static(
          "nerov", [] { return make_vehicle(nerov_parameters<double>()); },
          "NEROV, the paper's vehicle, with the numbers of its section 5.")
      .def("__copy__", [](const Vehicle<double>& v) { return Vehicle<double>(v); })
      .def("__deepcopy__", [](const Vehicle<double>& v, const py::dict&) { return Vehicle<double>(v); },
           py::arg("memo"))
      // Unpickled by the keyword constructor: validated like any other.
      .def(py::pickle([](const Vehicle<double>& v) { return parameters_dict(v.parameters()); },
                      [](const py::dict& d) { return from_keywords(py::kwargs(d)); }))
      .def("parameters", [](const Vehicle<double>& v) { return parameters_dict(v.parameters()); },
           "The parameters as a dict of keyword arguments: Vehicle(**v.parameters()) "
           "rebuilds the vehicle, so a perturbed copy is one dict edit away.");
  for_each_parameter([&](const auto& s) {  // read-only copies, documented as the fields
    const std::string doc = py::str(py::type::of<Params>().attr(s.name).attr("__doc__"));
    vehicle.def_property_readonly(
        s.name, [m = s.member](const Vehicle<double>& v) { return python_value(v.parameters().*m); },
        doc.c_str());
  });
  vehicle
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
