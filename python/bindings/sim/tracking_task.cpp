// neurov/sim/tracking_task.hpp and tracking_lanes.hpp in Python: the
// Gymnasium tracking task's constants (TrackingTaskConfig, bound from its
// description) and TrackingTask, which steps one Simulator (the single env)
// or every lane of a BatchSimulator (the vector env, the GIL released) in
// one call and returns the observation, reward, flags and info arrays, so
// that a step runs no per-row Python. Its row functions (clip, forces, observe_rows,
// score_rows) serve a batch written in Python and the tests.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/typing.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "fields.hpp"
#include "numpy_args.hpp"
#include "neurov/sim/batch.hpp"
#include "neurov/sim/tracking_lanes.hpp"
#include "typed_args.hpp"

namespace neurov::bindings {

namespace py = pybind11;

namespace {

using Task = TrackingTask<double>;
using Config = TrackingTaskConfig<double>;
using Sim = Simulator<double>;
using Batch = BatchSimulator<double>;
using Rows = TrackingRows<double>;
using Readout = LaneReadout<double>;
using Scores = TrackingScores<double>;
constexpr py::ssize_t kObs = kTrackingObservationSize;

using F64 = py::array_t<double>;
using F32 = py::array_t<float>;
using Bools = py::array_t<bool>;
/// One step's return: (observation, reward, terminated, truncated, info, clipped, outside).
template <typename Obs, typename Real, typename Flag>
using StepTuple = py::typing::Tuple<Obs, Real, Flag, Flag, typed::AnyDict, Flag, Flag>;

/// A (k,) array of bools (dtype bool) or of integers (dtype int/uint), C-contiguous.
template <typename T>
py::array_t<T, py::array::c_style> flags_of(const py::handle& obj, const char* name, py::ssize_t k) {
  return py_args::numpy_array<T>(obj, {k}, [&](py_args::Refusal why, const std::string& got) {
    const std::string message = std::string("argument '") + name + "' must be a " +
                                (std::is_same_v<T, bool> ? "bool" : "int") + " array of shape (" +
                                std::to_string(k) + ",), got " + got;
    if (why == py_args::Refusal::type) throw py::type_error(message);
    throw py::value_error(message);
  });
}

/// The actions (k rows; k < 0: one action of shape (n,)) checked and clipped
/// into `out` with clipped[i] per row; ValueError naming the rows that are
/// not finite (nothing is written then).
void clip_checked(const Task& task, const py::handle& obj, const char* name, py::ssize_t k, double* out,
                  bool* clipped) {
  const py::ssize_t n = task.action_size();
  const auto a = k < 0 ? py_args::real_rows(obj, name, n, -1, false) : py_args::real_rows(obj, name, k, n, false);
  const std::size_t rows = k < 0 ? 1 : static_cast<std::size_t>(k);
  const std::ptrdiff_t bad = clip_actions(rows, n, a.data(), out, clipped);
  if (bad < 0) return;
  std::string row = "[", all = "[";
  for (py::ssize_t j = 0; j < n; ++j) row += (j ? ", " : "") + py_args::num(a.data()[bad * n + j]);
  for (std::size_t i = 0; i < rows; ++i) {
    bool finite = true;
    for (py::ssize_t j = 0; j < n; ++j) finite = finite && std::isfinite(a.data()[i * n + j]);
    if (!finite) all += (all.size() > 1 ? ", " : "") + std::to_string(i);
  }
  throw py::value_error(std::string("argument '") + name + "' must be finite, got " + row + "] in row " +
                        std::to_string(bad) + " (rows " + all + "] are not)");
}

/// The arrays a step reads K lanes into (one row of shape (6,) for a single
/// Simulator): t, the measured eta and nu, eta_d, the true eta and nu, which
/// info() hands over, and what only the scores read.
class LaneArrays {
 public:
  LaneArrays(std::size_t k, bool single)
      : k_(k), single_(single), t_(k), eta_d_dot_(6 * k), eta_d_ddot_(6 * k), steps_left_(k),
        diverged_(new bool[k]), done_(new bool[k]) {
    // The storage, taken while the GIL is held: a step reads into it without.
    for (const auto& [array, field] : {std::pair{&eta_, &Readout::eta}, std::pair{&nu_, &Readout::nu},
                                       std::pair{&eta_d_, &Readout::eta_d}, std::pair{&eta_true_, &Readout::eta_true},
                                       std::pair{&nu_true_, &Readout::nu_true}}) {
      *array = single ? F64(py::ssize_t(6)) : F64({static_cast<py::ssize_t>(k), py::ssize_t(6)});
      readout.*field = array->mutable_data();
    }
    readout.t = t_.data();
    readout.eta_d_dot = eta_d_dot_.data();
    readout.eta_d_ddot = eta_d_ddot_.data();
    readout.diverged = diverged_.get();
    readout.done = done_.get();
    readout.steps_left = steps_left_.data();
  }

  typed::AnyDict info() const {
    typed::AnyDict d;
    d["t"] = single_ ? py::object(py::float_(t_[0])) : py::object(F64(py::ssize_t(k_), t_.data()));
    d["eta"] = eta_;
    d["nu"] = nu_;
    d["eta_d"] = eta_d_;
    d["eta_true"] = eta_true_;
    d["nu_true"] = nu_true_;
    return d;
  }

  Readout readout;  ///< where the lanes are read: the storage below

 private:
  std::size_t k_;
  bool single_;
  std::vector<double> t_, eta_d_dot_, eta_d_ddot_;
  std::vector<std::int64_t> steps_left_;
  std::unique_ptr<bool[]> diverged_, done_;
  F64 eta_, nu_, eta_d_, eta_true_, nu_true_;
};

/// The outputs of K rows' scores.
struct ScoreArrays {
  explicit ScoreArrays(py::ssize_t k) : reward(k), terminated(k), truncated(k), outside(k) {}
  Scores scores() {
    return {reward.mutable_data(), terminated.mutable_data(), truncated.mutable_data(), outside.mutable_data()};
  }
  F64 reward;
  Bools terminated, truncated, outside;
};

StepTuple<F32, double, bool> step_one(const Task& task, Sim& sim, const typed::ArrayLike& action) {
  if (sim.done())
    throw std::runtime_error(std::string("TrackingTask.step: the run is done (") +
                             (sim.diverged() ? "the plant diverged" : "every row is simulated") +
                             "); reset the simulator first");
  if (sim.log_full())
    throw std::runtime_error("TrackingTask.step: the simulator's log window is full; drain() it");
  if (sim.logged_parameters() != 0)
    throw py::value_error("argument 'simulator' must log no parameters (logged_parameters = 0), got " +
                          std::to_string(sim.logged_parameters()));
  std::vector<double> a(static_cast<std::size_t>(task.action_size()));
  bool clipped = false;
  clip_checked(task, action, "action", -1, a.data(), &clipped);
  LaneArrays lane(1, true);
  F32 obs(kObs);
  double reward = 0;
  bool terminated = false, truncated = false, outside = false;
  const Status plant = tracking_step(task, sim, a.data(), lane.readout, obs.mutable_data(),
                                     Scores{&reward, &terminated, &truncated, &outside});
  typed::AnyDict info = lane.info();
  info["plant_status"] = plant;
  return StepTuple<F32, double, bool>(py::make_tuple(obs, reward, terminated, truncated, info, clipped, outside));
}

StepTuple<F32, F64, Bools> step_batch(const Task& task, Batch& batch, const typed::ArrayLike& actions,
                                      const typed::OptionalArrayLike& mask_in, unsigned threads) {
  const std::size_t k = batch.size();
  const auto rows = static_cast<py::ssize_t>(k);
  std::vector<double> a(k * static_cast<std::size_t>(task.action_size()));
  Bools clipped(rows);
  clip_checked(task, actions, "actions", rows, a.data(), clipped.mutable_data());
  py::array_t<bool, py::array::c_style> mask;
  if (!mask_in.is_none()) mask = flags_of<bool>(mask_in, "mask", rows);
  py::array_t<std::uint8_t> statuses(rows);
  LaneArrays lanes(k, false);
  F32 obs({rows, kObs});
  ScoreArrays s(rows);
  // The arrays' storage, taken while the GIL is held.
  const bool* stepped = mask_in.is_none() ? nullptr : mask.data();
  std::uint8_t* status = statuses.mutable_data();
  float* observations = obs.mutable_data();
  const Scores scores = s.scores();
  {
    py::gil_scoped_release release;
    tracking_step_batch(task, batch, a.data(), stepped, status, lanes.readout, observations, scores, threads,
                        shared_pool(threads));
  }
  typed::AnyDict info = lanes.info();
  info["plant_status"] = statuses;
  return StepTuple<F32, F64, Bools>(
      py::make_tuple(obs, s.reward, s.terminated, s.truncated, info, clipped, s.outside));
}

/// (observations, info) of k lanes, run(i) the i-th run.
template <typename Run>
py::typing::Tuple<F32, typed::AnyDict> observe_lanes(const Task& task, std::size_t k, bool single, Run run) {
  LaneArrays lanes(k, single);
  F32 obs = single ? F32(kObs) : F32({static_cast<py::ssize_t>(k), kObs});
  tracking_observe(task, k, run, lanes.readout, obs.mutable_data());
  return py::typing::Tuple<F32, typed::AnyDict>(py::make_tuple(obs, lanes.info()));
}

Task make_task(const Config& config) {
  Task t;
  py_args::raise_if_invalid(Task::create(config, t), "TrackingTaskConfig");
  return t;
}

}  // namespace

void bind_tracking_task(py::module_& m) {
  m.attr("TRACKING_OBSERVATION_SIZE") = kTrackingObservationSize;

  Fields<Config>::described(m, "TrackingTaskConfig",
                 "The Gymnasium tracking task's constants (docs/gymnasium.md): the reward's weights, "
                 "the bounding box, the observation's velocity bound and the action's scale.")
      .validator("TrackingTaskConfig")
      .finish();

  py::class_<Task>(m, "TrackingTask",
                   "The tracking task's arithmetic (neurov/sim/tracking_task.hpp): a step of one "
                   "Simulator or of every lane of a BatchSimulator in one call, the action's force, the "
                   "26-entry observation, the reward and the episode's end, written once for the single "
                   "and the vector Gymnasium env.")
      .def(py::init(&make_task), py::arg("config"),
           "From a TrackingTaskConfig (copied); ValidationError naming a bad field.")
      .def_property_readonly("config", [](const Task& t) { return t.config(); }, "A copy of the configuration.")
      .def_property_readonly("action_size", &Task::action_size, "n, the components of one action.")
      .def_property_readonly("reach", &Task::reach,
                             "|box_high - box_low| [m], the bound of the observation's position entries.")
      .def_property_readonly("termination_cost", &Task::termination_cost,
                             "What ending early costs per step not simulated: position_weight reach^2.")
      .def_property_readonly(
          "observation_high",
          [](const Task& t) { return F32(kObs, t.observation_high().data()); },
          "(26,) float32: observation entry i lies in [-high[i], high[i]].")
      .def("step", &step_one, py::arg("simulator"), py::arg("action"),
           "One control period of `simulator` (a Simulator) under `action` (n,), clipped to [-1, 1]: "
           "returns (observation (26,) float32, reward, terminated, truncated, info, clipped, outside), "
           "info holding t, eta, nu, eta_d, eta_true, nu_true and plant_status (a Status). ValueError "
           "for a wrong shape or a non-finite action, TypeError for one that is not real numbers "
           "(nothing is stepped then); RuntimeError for a done simulator.")
      .def("step_batch", &step_batch, py::arg("batch"), py::arg("actions"), py::arg("mask") = py::none(),
           py::arg("threads") = 1u,
           "One control period of every lane of `batch` (a BatchSimulator) whose mask is True (None: "
           "every lane) and that is not done, under actions (K, n) clipped to [-1, 1], in one call with "
           "the GIL released: returns (observations (K, 26) float32, rewards (K,), terminated, truncated, "
           "info, clipped, outside ((K,) bool each)), info holding t (K,), eta, nu, eta_d, eta_true, "
           "nu_true (K, 6) and plant_status (K,) uint8 (LANE_NOT_STEPPED for a lane not stepped, which "
           "scores reward 0 and no flag). Bad actions raise as step() does, and nothing is stepped. "
           "threads: the lanes' plants stepped over that many threads, as BatchSimulator.step does.")
      .def(
          "observe",
          [](const Task& t, const Sim& sim) {
            return observe_lanes(t, 1, true, [&sim](std::size_t) -> const Sim& { return sim; });
          },
          py::arg("simulator"),
          "(observation (26,) float32, info) of a Simulator as it stands (info as step()'s, without "
          "plant_status).")
      .def(
          "observe_batch",
          [](const Task& t, const Batch& b) {
            return observe_lanes(t, b.size(), false, [&b](std::size_t i) -> const Sim& { return b.lane(i); });
          },
          py::arg("batch"), "(observations (K, 26) float32, info) of every lane of a BatchSimulator.")
      .def(
          "clip",
          [](const Task& t, const typed::ArrayLike& actions) {
            const auto k = py_args::real_rows(actions, "actions", -1, t.action_size(), false).shape(0);
            F64 out({k, py::ssize_t(t.action_size())});
            Bools clipped(k);
            clip_checked(t, actions, "actions", k, out.mutable_data(), clipped.mutable_data());
            return py::typing::Tuple<F64, Bools>(py::make_tuple(out, clipped));
          },
          py::arg("actions"),
          "(the actions (K, n) clipped to [-1, 1], which rows needed it (K,) bool); ValueError naming "
          "the rows that are not finite.")
      .def(
          "forces",
          [](const Task& t, const typed::ArrayLike& actions) {
            const auto a = py_args::real_rows(actions, "actions", -1, t.action_size(), true);
            F64 tau({a.shape(0), py::ssize_t(6)});
            tracking_forces(t, static_cast<std::size_t>(a.shape(0)), a.data(), tau.mutable_data());
            return tau;
          },
          py::arg("actions"), "The body forces tau (K, 6) of clipped actions (K, n).")
      .def(
          "observe_rows",
          [](const Task& t, const typed::ArrayLike& eta, const typed::ArrayLike& nu, const typed::ArrayLike& eta_d,
             const typed::ArrayLike& eta_d_dot, const typed::ArrayLike& eta_d_ddot) {
            const auto e = py_args::real_rows(eta, "eta", -1, 6, false);
            const py::ssize_t k = e.shape(0);
            const auto n = py_args::real_rows(nu, "nu", k, 6, false);
            const auto d = py_args::real_rows(eta_d, "eta_d", k, 6, true);
            const auto dd = py_args::real_rows(eta_d_dot, "eta_d_dot", k, 6, true);
            const auto ddd = py_args::real_rows(eta_d_ddot, "eta_d_ddot", k, 6, true);
            Rows r;
            r.eta = e.data();
            r.nu = n.data();
            r.eta_d = d.data();
            r.eta_d_dot = dd.data();
            r.eta_d_ddot = ddd.data();
            F32 obs({k, kObs});
            tracking_observation(t, static_cast<std::size_t>(k), r, obs.mutable_data());
            return obs;
          },
          py::arg("eta"), py::arg("nu"), py::arg("eta_d"), py::arg("eta_d_dot"), py::arg("eta_d_ddot"),
          "The observations (K, 26) float32 of the measured eta, nu (K, 6; NaN allowed) and the desired "
          "state (K, 6 each).")
      .def(
          "score_rows",
          [](const Task& t, const typed::ArrayLike& eta_true, const typed::ArrayLike& eta_d,
             const typed::ArrayLike& actions, const typed::ArrayLike& diverged, const typed::ArrayLike& done,
             const typed::ArrayLike& steps_left) {
            const auto e = py_args::real_rows(eta_true, "eta_true", -1, 6, false);
            const py::ssize_t k = e.shape(0);
            const auto d = py_args::real_rows(eta_d, "eta_d", k, 6, true);
            const auto a = py_args::real_rows(actions, "actions", k, t.action_size(), true);
            const auto div = flags_of<bool>(diverged, "diverged", k);
            const auto dn = flags_of<bool>(done, "done", k);
            const auto left = flags_of<std::int64_t>(steps_left, "steps_left", k);
            Rows r;
            r.eta_true = e.data();
            r.eta_d = d.data();
            r.actions = a.data();
            r.diverged = div.data();
            r.done = dn.data();
            r.steps_left = left.data();
            ScoreArrays s(k);
            tracking_score(t, static_cast<std::size_t>(k), r, s.scores());
            return py::typing::Tuple<F64, Bools, Bools, Bools>(
                py::make_tuple(s.reward, s.terminated, s.truncated, s.outside));
          },
          py::arg("eta_true"), py::arg("eta_d"), py::arg("actions"), py::arg("diverged"), py::arg("done"),
          py::arg("steps_left"),
          "(reward, terminated, truncated, outside), each (K,), of the true poses eta_true and eta_d "
          "(K, 6), the clipped actions (K, n), and per row (K,) the plant's divergence and end (bool) "
          "and the steps not simulated (int).");
}

}  // namespace neurov::bindings
