// neurov/sim/config.hpp in Python: SimulationConfig<double> and the structs it
// holds, each bound from its description beside it in C++ (config_fields);
// validate() is the C++ validator. DISTURBANCE_TABLES names the scenario
// tables of the disturbance parts that have one, for the generic reader
// (neurov/config/sea.py).
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <cstring>
#include <optional>
#include <tuple>
#include <type_traits>
#include <vector>

#include "bindings.hpp"
#include "fields.hpp"
#include "numpy_args.hpp"
#include "neurov/sim/config.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

template <typename T>
void bind(py::module_& m, const char* name, const char* doc) {
  Fields<T>::described(m, name, doc).finish();
}

template <typename P, typename = void>
struct has_table : std::false_type {};
template <typename P>
struct has_table<P, std::void_t<decltype(P::kTable)>> : std::true_type {};

/// (key, class, many) of a part whose scenario table is SimulationConfig's
/// field `key`: an optional struct ([key]) or a list of them ([[key]]).
template <typename D>
void table_row(py::list& out, const char* key) {
  if constexpr (FieldKind<D>::kind == 2)
    out.append(py::make_tuple(key, py::type::of<typename D::value_type>(), false));
  else if constexpr (FieldKind<D>::kind == 3)
    out.append(py::make_tuple(key, py::type::of<typename D::value_type>(), true));
}

template <typename P, typename = void>
struct has_settings_class : std::false_type {};
template <typename P>
struct has_settings_class<P, std::void_t<decltype(P::kSettingsClass)>> : std::true_type {};

/// The configuration struct of each part that names its Python class.
template <template <typename> class... Parts>
void bind_part_settings(py::module_& m, parts::PartList<double, Parts...>*) {
  const auto one = [&m](auto* part) {
    using P = std::remove_pointer_t<decltype(part)>;
    if constexpr (has_settings_class<P>::value)
      bind<typename P::Settings>(m, P::kSettingsClass, P::kSettingsDoc);
  };
  (one(static_cast<Parts<double>*>(nullptr)), ...);
}

template <template <typename> class... Parts>
py::tuple disturbance_tables(parts::PartList<double, Parts...>*) {
  py::list out;
  const auto one = [&out](auto* part) {
    using P = std::remove_pointer_t<decltype(part)>;
    if constexpr (has_table<P>::value)
      std::apply(
          [&out](const auto&... s) {
            ((std::strcmp(s.name, P::kTable) == 0
                  ? table_row<typename std::decay_t<decltype(s)>::Type>(out, s.name)
                  : void()),
             ...);
          },
          config_fields(static_cast<const SimulationConfig<double>*>(nullptr)));
  };
  (one(static_cast<Parts<double>*>(nullptr)), ...);
  return py::tuple(out);
}

}  // namespace

void bind_sim_config(py::module_& m) {
  m.attr("MAX_SUBSTEPS") = kMaxSubsteps;
  m.attr("MAX_WAVE_COMPONENTS") = kMaxWaveComponents;
  m.def(
      "buoyancy_in_water",
      [](double water_density, double displaced_volume) {
        double b = 0.0;
        py_args::raise_if_invalid(buoyancy_in_water(water_density, displaced_volume, b),
                                  "buoyancy_in_water");
        return b;
      },
      py::arg("water_density"), py::arg("displaced_volume"),
      "B = rho g V [N]: the buoyancy of displaced_volume [m^3] in water of water_density "
      "[kg/m^3]. ValueError naming an argument that is not > 0 and finite.");
  py::enum_<SensorFaultKind>(m, "SensorFaultKind", "What a sensor fault does to a measurement.")
      .value("freeze", SensorFaultKind::freeze, "Repeats the last measurement delivered.")
      .value("dropout", SensorFaultKind::dropout, "NaN, which the controller refuses.")
      .value("noise_burst", SensorFaultKind::noise_burst, "Extra white noise.");
  py::enum_<RefusedStepPolicy>(m, "RefusedStepPolicy",
                               "The force applied when the controller refuses a step.")
      .value("zero", RefusedStepPolicy::zero, "No force.")
      .value("hold", RefusedStepPolicy::hold, "The last force the controller accepted.");
  py::enum_<CurrentModel>(m, "CurrentModel", "The model of the current a run uses.")
      .value("constant", CurrentModel::constant,
             "Mean + sinusoid + steps (current, current_amplitude, current_period, "
             "current_steps).")
      .value("gauss_markov", CurrentModel::gauss_markov,
             "First-order Gauss-Markov speed and direction (gauss_markov_current).");
  py::enum_<WaveSpectrum>(m, "WaveSpectrum", "The spectrum the waves realise.")
      .value("jonswap", WaveSpectrum::jonswap, "JONSWAP (hs, tp, gamma).")
      .value("pierson_moskowitz", WaveSpectrum::pierson_moskowitz,
             "Two-parameter Pierson-Moskowitz (Bretschneider/ITTC: hs, tp).");

  bind<GaussMarkovCurrentConfig<double>>(m, "GaussMarkovCurrentConfig",
      "A current whose speed, direction and vertical angle wander about their means as "
      "first-order Gauss-Markov processes (Fossen 2011, 8.3).");
  {
    using T = WaveConfig<double>;
    auto cls = Fields<T>::described(m, "WaveConfig",
        "Linear deep-water waves realised from a spectrum as a sum of seeded components.").finish();
    // The target S(omega) drawn beside a run's realised spectrum: the C++
    // density itself, so the plot cannot drift from what the waves realise.
    cls.def(
        "spectral_density",
        [](const T& c, const py::array_t<double, py::array::c_style | py::array::forcecast>& omega) {
          const SpectralDensity density = SpectralDensity::from(c);
          py::array_t<double> out(omega.request().shape);
          const double* w = omega.data();
          double* s = out.mutable_data();
          for (py::ssize_t i = 0; i < omega.size(); ++i) s[i] = density(w[i]);
          return out;
        },
        py::arg("omega"),
        "S(omega) [m^2 s/rad] of this spectrum at the circular frequencies `omega` [rad/s] "
        "(0 for omega <= 0); JONSWAP normalised so that its m0 is hs^2/16.");
  }
  bind<PayloadEvent<double>>(m, "PayloadEvent",
      "A change of the vehicle at `time` that the controller is not told about: mass, "
      "buoyancy, damping and added mass.");

  bind_part_settings(m, static_cast<DisturbanceParts<double>*>(nullptr));

  py::enum_<EstimatorType>(m, "EstimatorType", "What the controller is given from the sensors.")
      .value("none", EstimatorType::none, "Each sensor's latest reading, as it is.")
      .value("ekf", EstimatorType::ekf, "The extended Kalman filter's estimate.");
  bind<UsblConfig<double>>(m, "UsblConfig",
      "An acoustic position fix (USBL-like): NED position.");
  bind<DvlConfig<double>>(m, "DvlConfig",
      "A Doppler velocity log: body velocity over ground.");
  bind<DepthConfig<double>>(m, "DepthConfig",
      "A pressure depth sensor: z, down positive.");
  bind<ImuConfig<double>>(m, "ImuConfig",
      "An AHRS/IMU: attitude and gyro rates, the gyro's bias walking.");
  {
    using T = SensorsConfig<double>;
    auto cls = Fields<T>::described(m, "SensorsConfig",
        "The sensors of a run, each optional; none configured: ideal sensing.").finish();
    cls.def("any", &T::any, "Some sensor is configured.");
  }
  bind<EstimatorConfig<double>>(m, "EstimatorConfig",
      "What the controller is given from the sensors; the EKF's measurement noises are "
      "the sensors' own.");
  bind<SinusoidalDisturbance<double>>(m, "SinusoidalDisturbance",
      "A force or moment in one body DOF: amplitude * sin(2 pi frequency (t - start) + "
      "phase) for t >= start.");
  bind<ThrusterFailure<double>>(m, "ThrusterFailure",
      "Thruster `index` works at `efficiency` (0: failed) from `time` on.");
  bind<SensorFault<double>>(m, "SensorFault",
      "A sensor fault over [start, end): the measurement of eta and/or nu freezes, "
      "drops out (NaN) or gets extra white noise.");
  bind<CurrentStep<double>>(m, "CurrentStep",
      "From `time` on, the mean current is `velocity`.");
  {
    using T = Command<double>;
    auto cls = Fields<T>::described(m, "Command",
        "Commanded poses at increasing times; held before the first and after the last; "
        "between them linear or held.").finish();
    cls.def("at", &T::at, py::arg("t"), "The commanded pose at time t.");
  }
  Fields<SimulationConfig<double>>::described(m, "SimulationConfig",
      "Everything of a closed-loop run but the vehicle and the controller. Rows of a "
      "run are at t_k = k dt; the force is held over each control period and the plant "
      "integrated by RK4 at dt / substeps.")
      .validator("SimulationConfig")
      .finish();
  m.attr("DISTURBANCE_TABLES") =
      disturbance_tables(static_cast<DisturbanceParts<double>*>(nullptr));
}

}  // namespace neurov::bindings
