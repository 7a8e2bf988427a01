// neurov/model/thrusters.hpp in Python: the thruster layout (ThrusterConfig)
// and its curves (ThrusterCurveConfig), bound from their descriptions beside
// them in C++ (config_fields), and the allocation of one wrench.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "fields.hpp"
#include "numpy_args.hpp"
#include "neurov/model/bluerov2_heavy.hpp"
#include "neurov/model/thruster_curve.hpp"
#include "neurov/model/thruster_geometry.hpp"
#include "neurov/model/thrusters.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

/// The C++ curve of a configuration; ValueError from its validator.
ThrusterCurve<double> curve_of(const ThrusterCurveConfig<double>& c) {
  ThrusterCurve<double> curve;
  py_args::raise_if_invalid(ThrusterCurve<double>::create(c, curve), "ThrusterCurveConfig");
  return curve;
}

}  // namespace

/// A curve's table (ThrusterCurveConfig's description, whose member is the
/// command column): (n, 2) rows of (command, thrust), stored in the command
/// and thrust columns and the count of points.
template <>
struct FieldForm<std::array<double, kThrusterCurveCapacity>> {
  static constexpr bool custom = true;
  template <typename T>
  static void bind(Fields<T>& f, const char* name, std::array<double, kThrusterCurveCapacity> T::*,
                   const char* doc) {
    f.field(
        name,
        [](const T& c) {
          Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor> t(c.points, 2);
          for (int i = 0; i < c.points; ++i) t.row(i) << c.command[i], c.thrust[i];
          py::array a = py::cast(t);
          a.attr("setflags")(py::arg("write") = false);
          return a;
        },
        [](T& c, const typed::ArrayLike& v, const std::string& qualified) {
          const auto t = py_args::dynamic_matrix(v, py_args::field(qualified), -1, 2);
          if (t.rows() > kThrusterCurveCapacity)
            throw py::value_error(qualified + " must have at most " +
                                  std::to_string(kThrusterCurveCapacity) + " rows, got " +
                                  std::to_string(t.rows()));
          c.points = static_cast<int>(t.rows());
          for (int i = 0; i < c.points; ++i) {
            c.command[i] = t(i, 0);
            c.thrust[i] = t(i, 1);
          }
        },
        doc);
  }
};

void bind_thrusters(py::module_& m) {
  py::enum_<Saturation>(m, "Saturation", "How thrusts beyond their limits are brought back.")
      .value("scale", Saturation::scale,
             "Every thruster scaled by one factor: the wrench keeps its direction.")
      .value("clip", Saturation::clip, "Each thruster clipped to its limits: the wrench turns.");
  {
    using T = ThrusterCurveConfig<double>;
    auto cls = Fields<T>::described(m, "ThrusterCurveConfig",
                         "One thruster from command to thrust: a table (linearly interpolated), a "
                         "dead band around the neutral command, supply-voltage scaling, a "
                         "first-order lag and a slew-rate limit.")
        .validator("ThrusterCurveConfig")
        .finish();
    cls.def(
        "static_thrust",
        [](const T& c, double command, double voltage) {
          return curve_of(c).static_thrust(command, voltage);
        },
        py::arg("command"), py::arg("voltage"),
        "Steady thrust [N] at a command and supply voltage (the C++ curve).");
    cls.def(
        "command_for",
        [](const T& c, double thrust, double voltage) {
          return curve_of(c).command_for(thrust, voltage);
        },
        py::arg("thrust"), py::arg("voltage"),
        "The command whose steady thrust is `thrust` at `voltage` (the curve's inverse), "
        "clamped to the table.");
  }
  {
    using T = ThrusterConfig<double>;
    Fields<T>::described(m, "ThrusterConfig",
              "n thrusters: tau = B u, allocated by the weighted pseudo-inverse, saturated, with a "
              "first-order lag.")
        .validator("ThrusterConfig",
                   [](const T& c) {
                     Thrusters<double> t;
                     return Thrusters<double>::create(c, t);
                   })
        .finish();
  }

  m.def(
      "bluerov2_heavy_layout",
      [] {
        const auto g = bluerov2_heavy_layout<double>();
        Eigen::Matrix<double, 8, 3, Eigen::RowMajor> positions, directions;
        py::list names;
        for (int i = 0; i < 8; ++i) {
          positions.row(i) = g[static_cast<std::size_t>(i)].position.transpose();
          directions.row(i) = g[static_cast<std::size_t>(i)].direction.transpose();
          names.append(kBlueRov2HeavyThrusterNames[static_cast<std::size_t>(i)]);
        }
        return py::make_tuple(positions, directions, names);
      },
      "The BlueROV2 Heavy's thruster layout of the C++ core (model/bluerov2_heavy.hpp): "
      "(positions (8, 3) [m], unit thrust directions (8, 3), names), body axes x forward, "
      "y starboard, z down.");

  m.def(
      "allocation_matrix",
      [](const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& positions,
         const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& directions) {
        if (directions.rows() != positions.rows())
          throw py::value_error("argument 'directions' must have " + std::to_string(positions.rows()) +
                                " rows (one per position), got " + std::to_string(directions.rows()));
        std::vector<ThrusterGeometry<double>> layout(static_cast<std::size_t>(positions.rows()));
        for (std::size_t i = 0; i < layout.size(); ++i)
          layout[i] = {positions.row(Eigen::Index(i)).transpose(), directions.row(Eigen::Index(i)).transpose()};
        Eigen::Matrix<double, 6, Eigen::Dynamic> b(6, positions.rows());
        py_args::raise_if_invalid(allocation_matrix(layout.data(), layout.size(), b), "allocation_matrix");
        return b;
      },
      py::arg("positions"), py::arg("directions"),
      "The allocation matrix B (6, n) of n thrusters at positions (n, 3) [m] pushing along unit "
      "directions (n, 3), body axes: column i is [d_i; r_i x d_i] (model/thruster_geometry.hpp).");

  m.def(
      "allocate_thrust",
      [](const typed::ArrayLike& matrix, const typed::ArrayLike& tau, const typed::OptionalArrayLike& max_thrust, const typed::OptionalArrayLike& min_thrust,
         const typed::Str& saturation, const typed::OptionalArrayLike& weights) {
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
