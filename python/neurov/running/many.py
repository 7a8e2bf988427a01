"""neurov.simulate_many: a list of runs in the order given, the built-in
controllers' runs as C++ batches (threads, no Python per step), the Python
controllers' runs one by one through :func:`neurov.simulate`, and a batched
Python policy's runs (:class:`neurov.laws.protocol.BatchedController`) as
batches it steps in one call per step (:func:`run_batched_policy`).

A run is a scenario and its controller (a :class:`ControllerSpec`, a
controller object, or None: the scenario's). The runs are given as a list
of scenarios, as one scenario with a list of per-run overrides (each a dict
of :meth:`Scenario.replace`'s fields), or as (scenario, controller) pairs.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from neurov import _core
from neurov.config.scenario import ControllerSpec, Scenario
from neurov.laws.protocol import is_batched, is_built_in, require_controller
from neurov.laws.registry import build_controller, default_centre_box, make_centres
from neurov.progress import progress_bar
from neurov.results.columns import RESULT_SERIES
from neurov.results.metrics import MetricsWindow, metrics_start
from neurov.results.timeseries import Result
from neurov.running.plant import build_vehicle, simulation_config
from neurov.running.policy_loop import run_batched_policy
from neurov.running.simulation import simulate

__all__ = ["BATCH_RUNS", "simulate_many"]

#: Runs per call into C++ (each call splits its runs over the threads): full
#: results of a batch are held until it returns, so this bounds the memory.
BATCH_RUNS = 256

Run = tuple[Scenario, Any]


def _runs(runs: Scenario | Iterable[Scenario | tuple[Scenario, Any]],
          overrides: Sequence[Mapping[str, Any]] | None) -> list[Run]:
    if isinstance(runs, Scenario):
        if overrides is None:
            return [(runs, None)]
        if isinstance(overrides, (Mapping, str)):
            raise TypeError("argument 'overrides' must be a list of dicts of Scenario fields, one per run, "
                            f"got {type(overrides).__name__}")
        out = []
        for i, o in enumerate(overrides):
            if not isinstance(o, Mapping):
                raise TypeError(f"argument 'overrides'[{i}] must be a dict of Scenario fields, "
                                f"got {type(o).__name__}")
            try:
                out.append((runs.replace(**o), None))
            except (TypeError, ValueError) as e:
                raise run_error(e, i, f"overrides[{i}]") from e
        return out
    if overrides is not None:
        raise TypeError("argument 'overrides' goes with one Scenario as 'runs' (a list of runs takes none)")
    out = []
    for i, r in enumerate(runs):
        if isinstance(r, Scenario):
            out.append((r, None))
        elif isinstance(r, tuple) and len(r) == 2 and isinstance(r[0], Scenario):
            out.append((r[0], r[1]))
        else:
            raise TypeError(f"argument 'runs'[{i}] must be a Scenario or a (Scenario, controller) pair, "
                            f"got {type(r).__name__}")
    return out


class _Resolver:
    """Each run's controller, built: a spec's NN centres drawn once per
    (spec, command box), not once per run (the draw costs a millisecond)."""

    def __init__(self) -> None:
        self._centres: dict[tuple[int, bytes], ControllerSpec] = {}

    def build(self, scenario: Scenario, controller: Any) -> tuple[Any, str]:
        if controller is not None and not isinstance(controller, ControllerSpec):
            if not is_batched(controller):
                require_controller(controller)
            return controller, type(controller).__name__
        spec = controller or scenario.controller
        name = spec.name
        if spec.type == "nn" and not isinstance(spec.centres, np.ndarray):
            low, high = default_centre_box(scenario)
            key = (id(spec), low.tobytes() + high.tobytes())
            resolved = self._centres.get(key)
            if resolved is None:
                resolved = spec.replace(centres=make_centres(spec, low, high))
                self._centres[key] = resolved
            spec = resolved
        return build_controller(spec, scenario), name


def run_error(error: Exception, index: int, what: str) -> Exception:
    """`error` again, of the same type and attributes (a ValidationError's
    ``field``, ``index``, ...), its message naming the run: ``"run 3
    (scenario 'x'): ..."``; the run's 0-based index as its ``run``."""
    try:
        named = type(error)(f"run {index} ({what}): {error}")
        named.__dict__.update(error.__dict__)
    except Exception:  # noqa: BLE001 - an exception type that takes no message: a ValueError says it
        named = ValueError(f"run {index} ({what}): {type(error).__name__}: {error}")
    named.run = index  # type: ignore[attr-defined]
    return named


def failed_result(scenario: Scenario, label: str, error: BaseException) -> Result:
    """The result of a run that raised while it ran: no rows, counted as
    diverged (its error metrics inf, as a study's failed run ranks), the
    error in ``extra["error"]`` (``{"type": ..., "message": ...}``)."""
    empty = {spec.name: np.zeros((0,) if spec.width == 1 else (0, spec.width or 0), dtype=spec.dtype)
             for spec in RESULT_SERIES}
    return Result(scenario=scenario, controller=label, diverged=True,
                  extra={"error": {"type": type(error).__name__, "message": str(error)}}, **empty)


def _check(planned: list[Run], resolver: _Resolver) -> dict[int, tuple[Any, str, _core.Vehicle]]:
    """Everything a run can be refused for, before any run: its controller
    built, its vehicle and its checked configuration. The first refusal is
    raised naming the run's 0-based index. The controllers and vehicles of
    the first :data:`BATCH_RUNS` runs are kept for their run (the others are
    built again when their batch comes: a built controller takes tens of kB,
    and a batch holds only its own)."""
    kept: dict[int, tuple[Any, str, _core.Vehicle]] = {}
    for i, (scenario, controller) in enumerate(planned):
        try:
            ctrl, name = resolver.build(scenario, controller)
            plant = build_vehicle(scenario)
            simulation_config(scenario)
        except (TypeError, ValueError) as e:
            raise run_error(e, i, f"scenario {scenario.name!r}") from e
        if i < BATCH_RUNS:
            kept[i] = ctrl, name, plant
    return kept


def simulate_many(runs: Scenario | Iterable[Scenario | tuple[Scenario, Any]],
                  overrides: Sequence[Mapping[str, Any]] | None = None, *, threads: int = 0,
                  metrics_only: bool = False, after: float | None = None,
                  progress: bool = False) -> list[Any]:
    """Runs every run and returns their :class:`Result`\\ s in the order
    given (with `metrics_only`, their :meth:`Result.metrics` dicts instead,
    over t >= `after`, default :func:`metrics_start` of each scenario's
    duration, the rows never kept). Built-in controllers run as C++ batches
    over `threads` threads (0: one per core); each run's result is exactly
    that of :func:`neurov.simulate` alone; its ``wall_time`` is its batch's
    divided by the batch's runs. Python controllers run one by one, except
    batched ones (:func:`neurov.laws.protocol.is_batched`): the runs given
    the same policy object form batches of up to :data:`BATCH_RUNS`, each
    stepped by one ``step_batch`` call per step (:func:`run_batched_policy`:
    a batch the policy fails on is run again run by run, so only the failing
    runs record refused steps); their metrics_only dicts are computed from
    the full results (no C++ sums on that path).

    Every run is checked before any runs (its controller built, its vehicle
    and configuration validated): a refusal raises the validator's error
    naming the run's 0-based index (``"run 600 (scenario 'x'): ..."``, its
    ``run`` attribute). A run that raises while it runs is a failed result
    among the others, as a study's failed run: no rows, ``diverged`` true,
    ``extra["error"]`` its error's type and message (with `metrics_only`,
    its metrics inf or nan and an ``"error"`` key). With `progress`, a
    progress bar on stderr while stderr is a terminal."""
    if not isinstance(threads, int) or isinstance(threads, bool) or threads < 0:
        raise ValueError(f"argument 'threads' must be an int >= 0 (0: one per core), got {threads!r}")
    if after is not None and not np.isfinite(after):
        raise ValueError(f"argument 'after' must be a finite time [s] or None, got {after}")
    planned = _runs(runs, overrides)
    resolver = _Resolver()
    kept = _check(planned, resolver)
    out: list[Any] = [None] * len(planned)
    # A lane: (index, scenario, controller, label, vehicle or None: built when its batch runs).
    batch: list[tuple[int, Scenario, Any, str, Any]] = []
    # A batched policy's runs, by policy object: id -> (policy, label, [(index, scenario, vehicle or None)]).
    policies: dict[int, tuple[Any, str, list[tuple[int, Scenario, Any]]]] = {}

    def window_start(scenario: Scenario) -> float:
        return metrics_start(scenario.duration) if after is None else float(after)

    def finish(i: int, sc: Scenario, result: Result) -> None:
        if not metrics_only:
            out[i] = result
            return
        out[i] = result.metrics(after=window_start(sc))
        if "error" in result.extra:
            out[i]["error"] = result.extra["error"]

    def run_lanes(lanes: list[tuple[int, Scenario, Any, str, Any]]) -> None:
        vehicles = [build_vehicle(sc) if v is None else v for _, sc, _, _, v in lanes]
        configs = [simulation_config(sc) for _, sc, _, _, _ in lanes]
        controllers = [c for _, _, c, _, _ in lanes]
        starts = [window_start(sc) for _, sc, _, _, _ in lanes]
        start = time.perf_counter()
        raws = _core.run_batch(vehicles, controllers, configs, threads=threads, metrics_only=metrics_only,
                               after=np.array(starts) if metrics_only else None)
        wall = (time.perf_counter() - start) / len(lanes)
        for (i, sc, _, name, _), raw in zip(lanes, raws):
            if metrics_only:
                out[i] = MetricsWindow.from_sums(raw, sc.duration, sc.dt).value()
            else:
                diverged = bool(raw.pop("diverged"))
                out[i] = Result(scenario=sc, controller=name, diverged=diverged, wall_time=wall, **raw)

    def flush() -> None:
        if not batch:
            return
        try:
            run_lanes(batch)
        except Exception:  # noqa: BLE001 - a run that fails is a failed result; the others are run alone
            for lane in batch:
                try:
                    run_lanes([lane])
                except Exception as e:  # noqa: BLE001
                    finish(lane[0], lane[1], failed_result(lane[1], lane[3], e))
        bar.update(len(batch))
        batch.clear()

    def run_policy(policy: Any, name: str, runs_of: list[tuple[int, Scenario, Any]]) -> None:
        scenarios = [sc for _, sc, _ in runs_of]
        vehicles = [build_vehicle(sc) if v is None else v for _, sc, v in runs_of]
        lanes = _core.BatchSimulator(vehicles, [simulation_config(sc) for sc in scenarios])
        results = run_batched_policy(lanes, policy, scenarios, vehicles=vehicles, label=name)
        for (i, sc, _), result in zip(runs_of, results):
            finish(i, sc, result)

    def flush_policy(key: int) -> None:
        policy, name, runs_of = policies.pop(key)
        try:
            run_policy(policy, name, runs_of)
        except Exception:  # noqa: BLE001 - as flush(): the failing runs alone are failed results
            for run in runs_of:
                try:
                    run_policy(policy, name, [run])
                except Exception as e:  # noqa: BLE001
                    finish(run[0], run[1], failed_result(run[1], name, e))
        bar.update(len(runs_of))

    with progress_bar(len(planned), "runs", quiet=not progress) as bar:
        for i, (scenario, controller) in enumerate(planned):
            ctrl, name, plant = kept.pop(i) if i in kept else (*resolver.build(scenario, controller), None)
            if is_built_in(ctrl):
                batch.append((i, scenario, ctrl, name, plant))
                if len(batch) >= BATCH_RUNS:
                    flush()
                continue
            if is_batched(ctrl):
                policies.setdefault(id(ctrl), (ctrl, name, []))[2].append((i, scenario, plant))
                if len(policies[id(ctrl)][2]) >= BATCH_RUNS:
                    flush_policy(id(ctrl))
                continue
            try:
                result = simulate(scenario, ctrl, vehicle=plant)
            except Exception as e:  # noqa: BLE001 - a run that fails is a failed result among the others
                result = failed_result(scenario, name, e)
            finish(i, scenario, result)
            bar.update(1)
        flush()
        for key in list(policies):
            flush_policy(key)
    return out
