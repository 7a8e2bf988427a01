"""One run of a study, (scenario, controller, sample) to a record: the
table row (drawn values and metrics) and the decimated error series the
band plots draw. A batch of runs is the unit of work sent to a worker."""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from neurov.laws.protocol import describe_failures, is_batched, own_failures
from neurov.errors import ControllerError, RefusedStepsWarning
from neurov.results.metrics import METRICS, flat_metrics, metric_names
from neurov.config.scenario import ControllerSpec
from neurov.study.sampling import sample_plant
from neurov.study.spec import Study, vehicle_key
from neurov.laws.registry import build_controller, default_centre_box, make_centres
from neurov.running.many import simulate_many
from neurov.running.simulation import simulate
from neurov.study.basis_rank import BasisRecorder, basis_columns

__all__ = ["SERIES_POINTS", "RunKey", "error_record", "plan_runs", "resolved_spec", "run_batch", "run_one"]

#: Points of the error-over-time series kept per run (for the percentile bands).
SERIES_POINTS = 200


@dataclass(frozen=True)
class RunKey:
    scenario: int
    controller: int
    sample: int


def plan_runs(study: Study) -> list[RunKey]:
    """Every run of the study in the table's order: scenario, controller, sample."""
    return [RunKey(i, j, k) for i in range(len(study.scenarios)) for j in range(len(study.controllers))
            for k in range(study.samples)]


def resolved_spec(study: Study, controller: int, scenario: int) -> ControllerSpec:
    """The spec with its NN centres drawn once per process: they depend on
    the scenario's command, not on the sample."""
    key = (controller, scenario)
    spec = study.cache.get(key)
    if spec is None:
        sc = study.scenarios[scenario]
        spec = study.spec_for(study.controllers[controller], sc)
        if spec.type == "nn" and not isinstance(spec.centres, np.ndarray):
            spec = spec.replace(centres=make_centres(spec, *default_centre_box(sc), sc))
        study.cache[key] = spec
    return spec


def run_one(study: Study, key: RunKey, done: tuple[Any, float] | None = None,
            made: tuple[Any, float] | None = None,
            plant: tuple[Any, dict[str, float]] | None = None) -> dict[str, Any]:
    """Runs one (scenario, controller, sample) and returns its record: the
    table row and the decimated error series. A run that raises (a user's
    controller, ``sys.exit`` in it included) is a result, not the end of the
    study: its record is :func:`error_record`'s, with the error's type and
    message. `done`: the run's (Result, CPU seconds) already simulated in a
    batch (:func:`run_batch`), of which only the record is made here.
    `made`: the run's controller (and the CPU seconds making it took),
    already made by its factory in the batch, which is then not called again.
    `plant`: the run's :func:`sample_plant` already drawn in the batch."""
    earlier = done[1] if done else made[1] if made else 0.0
    cpu_start = time.process_time() - earlier
    try:
        with warnings.catch_warnings():
            # A run's refused steps are its `refused_steps` column; a warning
            # per run from a worker would say it again, thousands of times.
            warnings.simplefilter("ignore", RefusedStepsWarning)
            return _run(study, key, cpu_start, done[0] if done else None, made[0] if made else None, plant)
    except (Exception, SystemExit) as e:  # noqa: BLE001 - any error of the user's code is this run's result
        message = str(e) if not isinstance(e, SystemExit) else f"sys.exit({e.code!r}) in the run"
        return error_record(study, key, "error", type(e).__name__, message,
                            cpu_time=time.process_time() - cpu_start)


def error_record(study: Study, key: RunKey, kind: str, error_type: str, message: str,
                 cpu_time: float = 0.0) -> dict[str, Any]:
    """The record of a run that gave no result: `kind` ``"error"`` (it raised)
    or ``"crash"`` (its worker process died). Its row has the run's key, its
    plant's draws and nan metrics, so the tables count it as failed; it has no
    error series."""
    scenario = study.scenarios[key.scenario]
    controller = study.controllers[key.controller]
    row: dict[str, Any] = {"scenario": scenario.name, "vehicle": vehicle_key(scenario),
                           "controller": controller, "sample": key.sample}
    try:
        plant, columns = sample_plant(study, scenario, key.sample)
        row.update({"noise_seed": plant.seed, **columns})
    except Exception:  # noqa: BLE001, S110 - the draws only fill columns; the error is what is recorded
        pass
    row.update({k: math.nan for k in metric_names()})
    return {"key": [scenario.name, controller, key.sample], "row": row, "series": None,
            "error": {"kind": kind, "type": error_type, "message": message},
            "wall_time": 0.0, "cpu_time": cpu_time}


def _run(study: Study, key: RunKey, cpu_start: float, batched: Any = None, made: Any = None,
         drawn: tuple[Any, dict[str, float]] | None = None) -> dict[str, Any]:
    scenario = study.scenarios[key.scenario]
    controller = study.controllers[key.controller]
    plant, columns = drawn if drawn is not None else sample_plant(study, scenario, key.sample)
    factory = study.factories.get(controller)
    if batched is not None or factory is not None:
        # The factory sees the nominal scenario, as a built-in controller is designed for it.
        if batched is not None:
            result = batched
        else:
            assert factory is not None  # the condition above
            ctrl = made if made is not None else factory.make(scenario)
            result = simulate(plant, ctrl, label=controller)
        own = own_failures(result.extra.get("controller_errors") or {})
        if own:  # warned about in a single run; in a study, a failed run
            raise ControllerError(f"controller {controller!r}: {describe_failures(own, len(result.t))}")
    else:
        spec = resolved_spec(study, key.controller, key.scenario)
        if spec.type == "nn" and study.basis_rank:
            recorder = BasisRecorder(build_controller(spec, plant))
            result = recorder.log_weight_norm(simulate(plant, recorder, label=controller))
            columns = {**columns, **basis_columns(recorder.matrix())}
        else:
            result = simulate(plant, spec)
    # A diverged run's metrics cover what it simulated (all of it if it
    # stopped before `after`); its error metrics are inf here so that it
    # ranks as the failure it is, whatever its errors before it stopped.
    metrics = flat_metrics(result.metrics(after=study.after))
    if result.diverged:
        metrics.update({k: math.inf for k in metrics if METRICS[k].error})
    row: dict[str, Any] = {
        "scenario": scenario.name,
        "vehicle": vehicle_key(scenario),
        "controller": controller,
        "sample": key.sample,
        "noise_seed": plant.seed,
        **columns,
        **metrics,
    }
    err = result.error
    # The stride comes from the planned length, not the run's: a run that
    # diverged stops early, and its series must share the others' time grid.
    planned = int(round(scenario.duration / scenario.dt)) + 1
    stride = max(1, math.ceil(planned / SERIES_POINTS))
    pos = np.linalg.norm(err[::stride, :3], axis=1)
    yaw = np.abs(err[::stride, 5])
    series = {
        "t0": float(result.t[0]),
        "dt": float(stride * scenario.dt),
        # Six significant digits: plenty for a plot, a third of the file.
        "position_error": [float(f"{x:.6g}") for x in pos],
        "yaw_error": [float(f"{x:.6g}") for x in yaw],
    }
    # Timings stay out of the row: the table must not depend on the machine.
    return {"key": [scenario.name, controller, key.sample], "row": row, "series": series,
            "wall_time": result.wall_time, "cpu_time": time.process_time() - cpu_start}


def run_batch(study: Study, keys: Sequence[tuple[int, int, int]]) -> list[dict[str, Any]]:
    """Runs a batch (the unit of work sent to a worker): the runs of built-in
    controllers together in C++ (:func:`neurov.simulate_many`), those of a
    factory's batched policy together per (controller, scenario)
    (:func:`_simulate_policies`), the others one by one; the records are
    those of :func:`run_one` run by run."""
    runs = [RunKey(*k) for k in keys]
    # A plant is drawn once per batch: the controllers of a scenario share its samples.
    plants: dict[tuple[int, int], tuple[Any, dict[str, float]]] = {}
    for k in runs:
        if (k.scenario, k.sample) not in plants:
            try:
                plants[(k.scenario, k.sample)] = sample_plant(study, study.scenarios[k.scenario], k.sample)
            except Exception:  # noqa: BLE001, S112 - drawn again by run_one, which records the error
                continue
    done = _simulate_built_ins(study, [k for k in runs if _batchable(study, k)], plants)
    policies, made = _simulate_policies(study, [k for k in runs if study.controllers[k.controller] in study.factories],
                                        plants)
    done.update(policies)
    return [run_one(study, k, done.get(k), made.get(k), plants.get((k.scenario, k.sample))) for k in runs]


def _batchable(study: Study, key: RunKey) -> bool:
    """A run of a built-in controller spec, which needs no Python per step."""
    controller = study.controllers[key.controller]
    if controller in study.factories:
        return False
    return not (study.basis_rank and study.spec_for(controller, study.scenarios[key.scenario]).type == "nn")


def _simulate_built_ins(study: Study, keys: list[RunKey], plants: Mapping[tuple[int, int], tuple[Any, Any]]
                        ) -> dict[RunKey, tuple[Any, float]]:
    """The runs' results simulated as one batch, with each run's share of the
    CPU time; empty if anything fails, and each run is then simulated alone
    by :func:`run_one`, which records its own error."""
    if len(keys) < 2:
        return {}
    cpu_start = time.process_time()
    try:
        runs = [(plants[(k.scenario, k.sample)][0], resolved_spec(study, k.controller, k.scenario)) for k in keys]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RefusedStepsWarning)
            results = simulate_many(runs, threads=1)
    except Exception:  # noqa: BLE001 - run alone, each run's error is its own record
        return {}
    cpu = (time.process_time() - cpu_start) / len(keys)
    return {k: (r, cpu) for k, r in zip(keys, results)}


def _simulate_policies(study: Study, keys: list[RunKey], plants: Mapping[tuple[int, int], tuple[Any, Any]]
                       ) -> tuple[dict[RunKey, tuple[Any, float]], dict[RunKey, tuple[Any, float]]]:
    """The runs of factories whose product is batched, one batch per
    (controller, scenario): the factory called once for it, on the nominal
    scenario as for a per-run controller, its product stepping every
    perturbed plant of the group at once (a run it fails in is rerun alone
    by :func:`run_batched_policy` and fails alone). A factory that raises
    or makes a per-run controller leaves its runs to :func:`run_one`. Which
    kind it makes is what its product declares (``batched = True``), learnt
    from that one call per process and scenario; a per-run controller it
    made is the first run's, so the factory is still called once per run.
    Returns the batched runs' (Result, CPU seconds) and those controllers
    already made, with the CPU seconds each took."""
    groups: dict[tuple[int, int], list[RunKey]] = {}
    for k in keys:
        groups.setdefault((k.controller, k.scenario), []).append(k)
    out: dict[RunKey, tuple[Any, float]] = {}
    made: dict[RunKey, tuple[Any, float]] = {}
    for (controller, scenario), group in groups.items():
        kind = ("batched", controller, scenario)
        if study.cache.get(kind) is False:
            continue
        cpu_start = time.process_time()
        label = study.controllers[controller]
        try:
            policy = study.factories[label].make(study.scenarios[scenario])
            # Which kind a factory makes is learnt once per process, from its
            # first product, which a per-run factory's first run then runs.
            study.cache[kind] = is_batched(policy)
            if not study.cache[kind]:
                made[group[0]] = (policy, time.process_time() - cpu_start)
                continue
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RefusedStepsWarning)
                # simulate_many, the one place that chooses how runs go, steps them as one batch.
                results = simulate_many([(plants[(scenario, k.sample)][0], policy) for k in group], threads=1)
        except Exception:  # noqa: BLE001 - run alone, each run's error is its own record
            continue
        cpu = (time.process_time() - cpu_start) / len(group)
        # A run that failed even alone is left to run_one, which records its own error.
        out.update({k: (r, cpu) for k, r in zip(group, results) if "error" not in r.extra})
    return out, made
