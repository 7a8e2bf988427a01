"""Studies: every controller on every scenario, over many perturbed plants.

A study file (TOML) names scenarios, controllers and how to perturb the
plant; :func:`run_study` runs every (scenario x controller x sample) and
writes a tidy table (one row per run), a league table and plots. The runs go
through Dask when it is installed (a local cluster, or an existing one by
address) and through local processes otherwise; both give the same table for
the same seed. See docs/studies.md for the file format::

    name = "robustness"
    seed = 2026                 # with the sample index, fixes every plant and noise draw
    samples = 20                # perturbed plants per scenario
    after = 10.0                # metrics over t >= after [s]
    scenarios = ["nerov_square_disturbed", "../my_scenario.toml"]

    [ranking]
    metric = "rmse_position_m"  # controllers ranked per scenario by its median

    [failure]                   # a run fails if a metric exceeds its bound or is not finite
    rmse_position_m = 1.0

    [controllers.nn]            # fields as in a scenario's [controller]
    type = "nn"
    [controllers.nn.nerov]      # per vehicle (the vehicle file's stem): merged over the above
    kd = [200, 200, 200, 50, 50, 50]

    [[perturbations]]
    parameter = "added_mass"    # a vehicle parameter, scaled by a factor per element
    relative = 0.3              # uniform in [0.7, 1.3]
    [[perturbations]]
    parameter = "current_speed" # an absolute quantity
    range = [0.0, 0.5]          # m/s

The controller is built for the nominal vehicle file; only the plant, the
current, the noise and the disturbances change from sample to sample.
"""

from __future__ import annotations

import csv
import dataclasses
import difflib
import hashlib
import json
import math
import os
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from neurov.files import read_text
from neurov.scenario import (
    ControllerSpec,
    Scenario,
    ScenarioError,
    _controller,
    _Reader,
    load_scenario,
)
from neurov.vehicle_file import load_vehicle_parameters

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "Perturbation",
    "Study",
    "StudyError",
    "StudyOutcome",
    "draw_sample",
    "failed",
    "league_markdown",
    "load_study",
    "metric_names",
    "percentile",
    "plan_runs",
    "read_table",
    "run_study",
    "sample_plant",
    "shipped_studies",
    "study_from_mapping",
    "study_path",
    "summarise",
    "write_table",
]

STUDY_DIR = Path(__file__).with_name("studies")
SCENARIO_DIR = Path(__file__).with_name("scenarios")

# Vehicle parameters a study may scale (keys of a vehicle file).
VEHICLE_PARAMETERS = ("mass", "inertia", "added_mass", "linear_damping", "quadratic_damping",
                      "weight", "buoyancy")
# Quantities of the environment, drawn as absolute values.
ENVIRONMENT_PARAMETERS = {
    "current_speed": "horizontal current speed [m/s], replacing the scenario's",
    "current_direction": "direction the current flows to [deg from north, towards east]",
    "noise_scale": "factor on the scenario's measurement-noise standard deviations",
    "disturbance_scale": "factor on the amplitudes of the scenario's disturbances",
}
# Absolute quantities that must stay >= 0.
_NON_NEGATIVE = {"current_speed", "noise_scale", "disturbance_scale"}
# Truncation of the normal distribution, in standard deviations: a perturbed
# plant must stay physical (a factor of 1 - 2 * 0.3 is still positive).
NORMAL_TRUNCATION = 2.0


class StudyError(ValueError):
    """A study that cannot be run: names the file and the field."""


@dataclass(frozen=True)
class Perturbation:
    """One perturbed quantity. Vehicle parameters are scaled by a factor
    (uniform in [1 - relative, 1 + relative], or normal with standard
    deviation `relative` truncated at two); environment quantities take
    absolute values (uniform in `low`..`high`, or normal `mean`, `std`
    truncated at two)."""

    parameter: str
    distribution: str = "uniform"
    relative: float = 0.0
    low: float = 0.0
    high: float = 0.0
    mean: float = 0.0
    std: float = 0.0
    per_element: bool = True

    @property
    def is_vehicle(self) -> bool:
        return self.parameter in VEHICLE_PARAMETERS

    def draw(self, rng: np.random.Generator, n: int) -> np.ndarray:
        """n values: factors for a vehicle parameter, values otherwise."""
        z = _truncated_normal(rng, n) if self.distribution == "normal" else rng.uniform(-1.0, 1.0, n)
        if self.is_vehicle:
            return 1.0 + self.relative * z
        if self.distribution == "normal":
            return self.mean + self.std * z
        return self.low + (self.high - self.low) * (z + 1.0) / 2.0


def _truncated_normal(rng: np.random.Generator, n: int) -> np.ndarray:
    out = rng.standard_normal(n)
    # Redraw in place: the number of draws depends only on the generator's
    # stream, so a seed still fixes the values.
    while True:
        bad = np.abs(out) > NORMAL_TRUNCATION
        if not bad.any():
            return out
        out[bad] = rng.standard_normal(int(bad.sum()))


@dataclass
class Study:
    name: str
    scenarios: list[Scenario]
    controllers: list[str]
    """Controller keys, in the file's order."""
    controller_specs: dict[tuple[str, str], ControllerSpec]
    """(controller key, vehicle key) -> the spec for that vehicle."""
    perturbations: list[Perturbation] = field(default_factory=list)
    samples: int = 1
    seed: int = 0
    after: float = 0.0
    ranking_metric: str = "rmse_position_m"
    also_show: list[str] = field(default_factory=list)
    """Further metrics whose medians the league table shows beside the ranking."""
    failure: dict[str, float] = field(default_factory=dict)
    head_to_head: list[tuple[str, str]] = field(default_factory=list)
    description: str = ""
    source: str = ""
    cache: dict[Any, Any] = field(default_factory=dict, repr=False, compare=False)
    """Per-process memo of the NN centres (a Sobol draw costs about a third
    of a short run); not part of the study."""

    def label(self, controller: str) -> str:
        specs = [s for (c, _), s in self.controller_specs.items() if c == controller]
        return specs[0].label if specs and specs[0].label else controller

    def spec_for(self, controller: str, scenario: Scenario) -> ControllerSpec:
        return self.controller_specs[(controller, vehicle_key(scenario))]

    def fingerprint(self) -> str:
        """A hash of everything that decides a run's numbers. The sample count,
        failure thresholds and ranking are left out: adding samples or
        changing how runs are judged reuses the runs already made."""
        from neurov import __version__

        payload = {
            "version": __version__,
            "seed": self.seed,
            "after": self.after,
            "perturbations": [dataclasses.asdict(p) for p in self.perturbations],
            "scenarios": [_canonical(dataclasses.asdict(s) | {"source": ""}) for s in self.scenarios],
            "controllers": {f"{c}@{v}": _canonical(dataclasses.asdict(s))
                            for (c, v), s in sorted(self.controller_specs.items())},
        }
        text = json.dumps(payload, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


def _canonical(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return [float(v) for v in x.ravel()] + [list(x.shape)]
    if isinstance(x, Mapping):
        return {str(k): _canonical(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_canonical(v) for v in x]
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    return x


def vehicle_key(scenario: Scenario) -> str:
    """The name a study's per-vehicle gains are filed under: the vehicle
    file's stem (``nerov``, ``bluerov2_heavy``)."""
    return Path(scenario.vehicle).stem


# --- loading -------------------------------------------------------------------


def shipped_studies() -> list[str]:
    return sorted(p.stem for p in STUDY_DIR.glob("*.toml"))


def study_path(name_or_path: str | Path) -> Path:
    """A study file by path, or a shipped study by name (``robustness``)."""
    p = Path(name_or_path)
    # A folder of that name (say, the output of an earlier `neurov study
    # league --out league`) must not hide the shipped study.
    if p.suffix == ".toml" or p.is_file():
        return p
    shipped = STUDY_DIR / f"{p.name}.toml"
    if shipped.is_file():
        return shipped
    raise StudyError(f"{name_or_path}: no such study file, and no shipped study of that name "
                     f"(shipped: {', '.join(shipped_studies())})")


def _scenario_path(ref: str, base: Path) -> Path:
    p = Path(ref)
    if p.suffix == ".toml":
        return p if p.is_absolute() else base / p
    return SCENARIO_DIR / f"{ref}.toml"


class _MergedReader(_Reader):
    """Reads a controller's fields merged with one vehicle's sub-table,
    naming the sub-table in errors about the fields it gave."""

    def __init__(self, base: Mapping[str, Any], over: Mapping[str, Any], where: str, origin: str,
                 vehicle: str) -> None:
        super().__init__({**base, **over}, where, origin)
        self._over = set(over)
        self._vehicle = vehicle

    def _name(self, key: str) -> str:
        root = key.split(".")[0]
        prefix = f"{self.where}.{self._vehicle}" if root in self._over else self.where
        return f"{prefix}.{key}"


def _perturbation(r: _Reader) -> Perturbation:
    known = (*VEHICLE_PARAMETERS, *ENVIRONMENT_PARAMETERS)
    name = r.string("parameter")
    if name not in known:
        close = difflib.get_close_matches(name, known, n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise r.error("parameter", f"expected one of {list(known)}, got {name!r}{hint}")
    dist = r.string("distribution", "uniform", choices=("uniform", "normal"))
    p: dict[str, Any] = {"parameter": name, "distribution": dist}
    if name in VEHICLE_PARAMETERS:
        rel = r.number("relative", minimum=0.0)
        # The factor must stay > 0 at its extreme: the plant must stay physical.
        bound = 1.0 if dist == "uniform" else 1.0 / NORMAL_TRUNCATION
        if rel >= bound:
            raise r.error("relative", f"expected a number < {bound:g} for a {dist} perturbation "
                          f"(the factor must stay positive), got {rel}")
        p["relative"] = rel
        if r.has("per_element"):
            if name in ("mass", "weight", "buoyancy"):
                raise r.error("per_element", f"{name!r} is a single number")
            p["per_element"] = r.boolean("per_element", True)
    else:
        if dist == "uniform":
            lo_hi = r.array("range", 2, broadcast=False)
            if lo_hi[1] < lo_hi[0]:
                raise r.error("range", f"expected [low, high] with low <= high, got {list(lo_hi)}")
            p["low"], p["high"] = float(lo_hi[0]), float(lo_hi[1])
            lowest = p["low"]
        else:
            p["mean"] = r.number("mean")
            p["std"] = r.number("std", minimum=0.0)
            lowest = p["mean"] - NORMAL_TRUNCATION * p["std"]
        if name in _NON_NEGATIVE and lowest < 0:
            raise r.error("range" if dist == "uniform" else "std",
                          f"{name} must stay >= 0, but the draws reach {lowest:g}")
    r.finish()
    return Perturbation(**p)


def study_from_mapping(data: Mapping[str, Any], origin: str = "<study>") -> Study:
    """A study from a parsed TOML table; errors name `origin` and the field."""
    r = _Reader(data, "", origin)
    base = Path(origin).parent if origin != "<study>" else Path.cwd()
    try:
        name = r.string("name", Path(origin).stem if origin != "<study>" else "study")
        description = r.string("description", "")
        seed = r.integer("seed", 0)
        samples = r.integer("samples", 1, minimum=1)
        after = r.number("after", 0.0, minimum=0.0)

        refs = r.raw("scenarios")
        if refs is None:
            raise r.error("scenarios", "missing (expected a list of scenario names or files)")
        if not isinstance(refs, list) or not refs or not all(isinstance(x, str) for x in refs):
            raise r.error("scenarios", f"expected a non-empty list of scenario names or .toml paths, got {refs!r}")
        scenarios: list[Scenario] = []
        for k, ref in enumerate(refs):
            path = _scenario_path(ref, base)
            if not path.is_file():
                shipped = sorted(p.stem for p in SCENARIO_DIR.glob("*.toml"))
                close = difflib.get_close_matches(ref, shipped, n=1)
                hint = f"; did you mean {close[0]!r}?" if close else ""
                raise r.error(f"scenarios[{k}]", f"no scenario {ref!r} (not a shipped name nor a file "
                              f"{path}){hint}")
            scenarios.append(load_scenario(path))
        names = [s.name for s in scenarios]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise r.error("scenarios", f"two scenarios share the name {dup[0]!r}; names label the rows")
        vehicles = sorted({vehicle_key(s) for s in scenarios})

        ctable = r.raw("controllers")
        if not isinstance(ctable, Mapping) or not ctable:
            raise r.error("controllers", "missing (expected tables [controllers.NAME] with a 'type')")
        controllers: list[str] = []
        specs: dict[tuple[str, str], ControllerSpec] = {}
        for key, table in ctable.items():
            where = f"controllers.{key}"
            if not isinstance(table, Mapping):
                raise StudyError(f"{origin}: {where}: expected a table")
            common = {k: v for k, v in table.items() if not (isinstance(v, Mapping) and k != "centres")}
            per_vehicle = {k: v for k, v in table.items() if isinstance(v, Mapping) and k != "centres"}
            for v in per_vehicle:
                if v not in vehicles:
                    # A misspelt table field ("centers") lands here too.
                    close = difflib.get_close_matches(v, [*vehicles, "centres"], n=1)
                    hint = f"; did you mean {close[0]!r}?" if close else ""
                    raise StudyError(f"{origin}: {where}.{v}: no scenario of this study uses a vehicle "
                                     f"{v!r} (vehicles: {vehicles}){hint}")
            for v in vehicles:
                if per_vehicle and v not in per_vehicle:
                    raise StudyError(f"{origin}: {where}: gives gains for {sorted(per_vehicle)} but not "
                                     f"for vehicle {v!r}; add [{where}.{v}]")
                reader = _MergedReader(common, per_vehicle.get(v, {}), where, origin, v)
                spec = _controller(reader)
                if not spec.label:
                    spec.label = key
                specs[(key, v)] = spec
            controllers.append(key)

        perturbations = []
        plist = r.raw("perturbations", [])
        if not isinstance(plist, list):
            raise r.error("perturbations", "expected an array of tables [[perturbations]]")
        for k, p in enumerate(plist):
            perturbations.append(_perturbation(_Reader(p, f"perturbations[{k}]", origin)))
        seen = [p.parameter for p in perturbations]
        dup = sorted({n for n in seen if seen.count(n) > 1})
        if dup:
            raise r.error("perturbations", f"{dup[0]!r} is perturbed twice")

        rk = r.table_of("ranking")
        ranking = rk.string("metric", "rmse_position_m")
        also = rk.raw("also_show", [])
        if not isinstance(also, list) or not all(isinstance(x, str) for x in also):
            raise rk.error("also_show", f"expected a list of metric names, got {also!r}")
        rk.finish()
        fr = r.table_of("failure")
        failure = {k: fr.number(k) for k in list(fr.table)}
        fr.finish()

        pairs: list[tuple[str, str]] = []
        h2h = r.raw("head_to_head", [])
        if not isinstance(h2h, list):
            raise r.error("head_to_head", "expected a list of [controller, controller] pairs")
        for k, pair in enumerate(h2h):
            if not (isinstance(pair, list) and len(pair) == 2 and all(x in controllers for x in pair)):
                raise r.error(f"head_to_head[{k}]", f"expected two of {controllers}, got {pair!r}")
            pairs.append((pair[0], pair[1]))
        r.finish()
    except ScenarioError as e:
        raise StudyError(str(e)) from None

    study = Study(name=name, scenarios=scenarios, controllers=controllers, controller_specs=specs,
                  perturbations=perturbations, samples=samples, seed=seed, after=after,
                  ranking_metric=ranking, also_show=list(also), failure=failure, head_to_head=pairs,
                  description=description, source=origin)
    _check_metrics(study, origin)
    _check_plants(study, origin)
    _check_controllers(study, origin, {k: bool(t and any(isinstance(v, Mapping) and n != "centres"
                                                        for n, v in t.items()))
                                       for k, t in ctable.items()})
    return study


def _check_controllers(study: Study, origin: str, per_vehicle: Mapping[str, bool]) -> None:
    """Builds every controller once per vehicle, so a configuration the C++
    refuses (say, modification = "sigma" without sigma_m) is named here and
    not in a worker halfway through the study."""
    from neurov.simulation import build_controller

    first: dict[str, int] = {}
    for i, s in enumerate(study.scenarios):
        first.setdefault(vehicle_key(s), i)
    for j, key in enumerate(study.controllers):
        for v, i in first.items():
            where = f"controllers.{key}.{v}" if per_vehicle.get(key) else f"controllers.{key}"
            try:
                build_controller(_resolved_spec(study, j, i), study.scenarios[i])
            except (ValueError, TypeError) as e:
                raise StudyError(f"{origin}: {where}: {e}") from None


def _check_metrics(study: Study, origin: str) -> None:
    known = metric_names()
    checks = [(study.ranking_metric, "ranking.metric")]
    checks += [(k, f"ranking.also_show[{i}]") for i, k in enumerate(study.also_show)]
    checks += [(k, f"failure.{k}") for k in study.failure]
    for key, where in checks:
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise StudyError(f"{origin}: {where}: unknown metric {key!r}{hint}")
    for s in study.scenarios:
        if study.after >= s.duration:
            raise StudyError(f"{origin}: after: {study.after} s leaves no samples of scenario "
                             f"{s.name!r} ({s.duration} s)")


def _check_plants(study: Study, origin: str) -> None:
    """Every scenario's vehicle must survive the extremes of the perturbation
    (a scaled mass matrix must stay positive definite, for instance)."""
    from neurov import _core

    vehicle_p = [p for p in study.perturbations if p.is_vehicle]
    if not vehicle_p:
        return
    for s in study.scenarios:
        nominal = _nominal_parameters(s)
        for corner in (-1.0, 1.0):
            params = dict(nominal)
            for p in vehicle_p:
                spread = p.relative * (NORMAL_TRUNCATION if p.distribution == "normal" else 1.0)
                params[p.parameter] = _scaled(params[p.parameter], 1.0 + corner * spread, False)
            try:
                _core.Vehicle(**params)
            except ValueError as e:
                raise StudyError(f"{origin}: perturbations: scenario {s.name!r}: at the extreme factors "
                                 f"({'low' if corner < 0 else 'high'}) the vehicle is not valid: {e}") from None


def load_study(path: str | Path) -> Study:
    """Reads a study file (or a shipped study by name); raises
    :class:`StudyError` naming the file and the field."""
    path = study_path(path)
    try:
        data = tomllib.loads(read_text(path, StudyError))
    except FileNotFoundError:
        raise StudyError(f"{path}: no such study file") from None
    except tomllib.TOMLDecodeError as e:
        raise StudyError(f"{path}: not valid TOML: {e}") from None
    return study_from_mapping(data, str(path))


# --- the plant of one sample ---------------------------------------------------------


def _nominal_parameters(scenario: Scenario) -> dict[str, Any]:
    params = load_vehicle_parameters(scenario.vehicle_path())
    params.update(scenario.vehicle_parameters or {})
    return params


def _scaled(value: Any, factors: Any, per_element: bool) -> Any:
    """value scaled by factors: a number, a vector (elementwise), or a
    symmetric matrix as S A S with S = diag(sqrt(factors)), which keeps it
    symmetric positive definite and scales its diagonal by the factors."""
    a = np.asarray(value, dtype=np.float64)
    f = np.atleast_1d(np.asarray(factors, dtype=np.float64))
    if a.ndim == 0:
        return float(a * f[0])
    n = a.shape[0]
    f = f[:n] if per_element else np.full(n, f[0])
    if a.ndim == 1:
        return (a * f).tolist()
    s = np.sqrt(f)
    return (s[:, None] * a * s[None, :]).tolist()


def _length(value: Any) -> int:
    a = np.asarray(value)
    return 1 if a.ndim == 0 else int(a.shape[0])


def sample_seeds(seed: int, sample: int) -> tuple[np.random.Generator, int]:
    """The perturbation generator and the noise seed of one sample: derived
    from (study seed, sample index) alone, so a sample's plant does not depend
    on the worker, the order of the runs, the scenario or the controller (every
    controller meets the same plants and the same noise: a paired
    comparison)."""
    params_ss, noise_ss = np.random.SeedSequence([seed, sample]).spawn(2)
    return np.random.default_rng(params_ss), int(noise_ss.generate_state(1)[0] & 0x7FFFFFFF)


def draw_sample(study: Study, sample: int) -> tuple[dict[str, np.ndarray], int]:
    """The drawn values of every perturbation (6 per vehicle vector, 3 for
    inertia, 1 otherwise) and the noise seed of `sample`. The same draws apply
    to every scenario; a vehicle's vector uses as many as it has entries."""
    rng, noise_seed = sample_seeds(study.seed, sample)
    draws: dict[str, np.ndarray] = {}
    for p in study.perturbations:
        n = {"inertia": 3, "added_mass": 6, "linear_damping": 6, "quadratic_damping": 6}.get(p.parameter, 1)
        values = p.draw(rng, n if p.per_element else 1)
        draws[p.parameter] = values if p.per_element else np.full(n, values[0])
    return draws, noise_seed


def sample_plant(study: Study, scenario: Scenario, sample: int) -> tuple[Scenario, dict[str, float]]:
    """The scenario as sample `sample` sees it (perturbed vehicle, current,
    noise, disturbances and noise seed) and the drawn values, flat, for the
    table."""
    draws, noise_seed = draw_sample(study, sample)
    changes: dict[str, Any] = {"seed": noise_seed}
    params = _nominal_parameters(scenario)
    columns: dict[str, float] = {}
    touched_vehicle = False
    for p in study.perturbations:
        values = draws[p.parameter]
        if p.is_vehicle:
            n = _length(params[p.parameter])
            params[p.parameter] = _scaled(params[p.parameter], values[:n], True)
            touched_vehicle = True
            if len(values) == 1 or not p.per_element:
                columns[f"p_{p.parameter}"] = float(values[0])
            else:
                for i in range(n):
                    columns[f"p_{p.parameter}_{i}"] = float(values[i])
        else:
            columns[f"p_{p.parameter}"] = float(values[0])
    if touched_vehicle:
        changes["vehicle_parameters"] = params
    current = np.array(scenario.current, dtype=np.float64)
    if "current_speed" in draws or "current_direction" in draws:
        speed = float(draws["current_speed"][0]) if "current_speed" in draws else float(np.hypot(*current[:2]))
        if "current_direction" in draws:
            heading = math.radians(float(draws["current_direction"][0]))
        else:
            heading = math.atan2(current[1], current[0]) if np.any(current[:2]) else 0.0
        current[:2] = speed * np.array([math.cos(heading), math.sin(heading)])
        changes["current"] = current
    if "noise_scale" in draws:
        k = float(draws["noise_scale"][0])
        changes["noise_eta"] = scenario.noise_eta * k
        changes["noise_nu"] = scenario.noise_nu * k
    if "disturbance_scale" in draws:
        k = float(draws["disturbance_scale"][0])
        changes["disturbances"] = [dataclasses.replace(d, amplitude=d.amplitude * k) for d in scenario.disturbances]
    return scenario.replace(**changes), columns


# --- one run ---------------------------------------------------------------------------

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


def _flat_metrics(m: Mapping[str, Any]) -> dict[str, float]:
    out: dict[str, float] = {}
    for key, v in m.items():
        if isinstance(v, Mapping):
            for k2, x in v.items():
                out[f"{key}_{k2}"] = float(x)
        elif isinstance(v, (list, tuple)):
            for i, x in enumerate(v):
                out[f"{key}_{i}"] = float(x)
        else:
            out[key] = float(v)
    return out


def metric_names() -> list[str]:
    """The metric columns of a run's row (Result.metrics, flattened)."""
    return list(_METRIC_NAMES)


_METRIC_NAMES = (
    "rmse_position_m", "max_position_error_m", "rmse_yaw_rad", "max_yaw_error_rad",
    *(f"{k}_{d}" for k in ("rmse", "max_abs_error", "iae") for d in ("x", "y", "z", "roll", "pitch", "yaw")),
    "mean_abs_tau", "max_abs_tau",
    *(f"{k}_{i}" for k in ("mean_abs_tau_dof", "max_abs_tau_dof") for i in range(6)),
    "control_energy", "final_adaptive_norm", "max_adaptive_norm", "refused_steps", "diverged",
)


def _resolved_spec(study: Study, controller: int, scenario: int) -> ControllerSpec:
    """The spec with its NN centres drawn once per process: they depend on
    the scenario's command, not on the sample."""
    key = (controller, scenario)
    spec = study.cache.get(key)
    if spec is None:
        from neurov.scenario import make_centres
        from neurov.simulation import default_centre_box

        sc = study.scenarios[scenario]
        spec = study.spec_for(study.controllers[controller], sc)
        if spec.type == "nn" and not isinstance(spec.centres, np.ndarray):
            spec = dataclasses.replace(spec, centres=make_centres(spec, *default_centre_box(sc)))
        study.cache[key] = spec
    return spec


def run_one(study: Study, key: RunKey) -> dict[str, Any]:
    """Runs one (scenario, controller, sample) and returns its record: the
    table row and the decimated error series."""
    from neurov.simulation import simulate

    cpu_start = time.process_time()
    scenario = study.scenarios[key.scenario]
    controller = study.controllers[key.controller]
    plant, columns = sample_plant(study, scenario, key.sample)
    result = simulate(plant, _resolved_spec(study, key.controller, key.scenario))
    if result.diverged and not np.any(result.t >= study.after):
        # Diverged before the transient ended: every error metric is inf.
        metrics = _flat_metrics(result.metrics(after=0.0))
    else:
        metrics = _flat_metrics(result.metrics(after=study.after))
    row: dict[str, Any] = {
        "scenario": scenario.name,
        "vehicle": vehicle_key(scenario),
        "controller": controller,
        "sample": key.sample,
        "noise_seed": plant.seed,
        **columns,
        **{k: metrics[k] for k in _METRIC_NAMES},
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
    """Runs a batch (the unit of work sent to a worker)."""
    return [run_one(study, RunKey(*k)) for k in keys]


# Local-process workers keep the study from their initialiser, so each task
# ships only its run indices.
_WORKER_STUDY: Study | None = None


def _init_process_worker(study: Study) -> None:
    global _WORKER_STUDY
    _WORKER_STUDY = study


def _run_batch_in_process(keys: Sequence[tuple[int, int, int]]) -> list[dict[str, Any]]:
    assert _WORKER_STUDY is not None, "worker started without its study"
    return run_batch(_WORKER_STUDY, keys)


# --- executors ------------------------------------------------------------------------------


def dask_available() -> bool:
    try:
        import dask.distributed  # noqa: F401
    except ImportError:
        return False
    return True


def _batches(keys: Sequence[RunKey], size: int) -> list[list[tuple[int, int, int]]]:
    flat = [(k.scenario, k.controller, k.sample) for k in keys]
    return [flat[i:i + size] for i in range(0, len(flat), size)]


def default_batch_size(runs: int, workers: int) -> int:
    """Runs per task. A run costs about 10 ms of CPU and a Dask task about
    4 ms of worker CPU on top (the league study: 2.6 s with one run per task,
    1.8 s with 50), so a task of up to 64 runs keeps that under 1 %; at least
    eight tasks per worker keep the load balanced and the progress bar moving."""
    return max(1, min(64, math.ceil(runs / (8 * max(1, workers)))))


# Each worker is one process running one run at a time: a BLAS thread pool in
# every worker only competes for the same cores (Dask's nanny sets the same).
_SINGLE_THREADED = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def _run_with_processes(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                        on_done: Callable[[list[dict[str, Any]]], None]) -> None:
    import concurrent.futures as cf
    import multiprocessing

    # spawn, not fork: forking a process that has threads (a Dask client, BLAS)
    # can deadlock, and spawn behaves the same on every platform. Spawned
    # children take the environment as it is when they start, and the pool
    # starts them on the first submits, so the variables stay set until the
    # pool is done; a user's own setting wins.
    ctx = multiprocessing.get_context("spawn")
    added = {k: v for k, v in _SINGLE_THREADED.items() if k not in os.environ}
    os.environ.update(added)
    try:
        with cf.ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_process_worker,
                                    initargs=(study,)) as pool:
            futures = [pool.submit(_run_batch_in_process, b) for b in batches]
            for fut in cf.as_completed(futures):
                on_done(fut.result())
    finally:
        for k in added:
            os.environ.pop(k, None)


def _run_with_dask(study: Study, batches: list[list[tuple[int, int, int]]], workers: int,
                   scheduler: str | None, on_done: Callable[[list[dict[str, Any]]], None],
                   dask_processes: bool) -> int:
    """Runs the batches on a Dask cluster; returns the number of workers used."""
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler:
        client = Client(scheduler)
    else:
        # One thread per worker: a run holds the GIL for its Python set-up, and
        # the C++ loop is single-threaded, so threads add nothing per core.
        # Port 0 lets the OS pick the HTTP port: Dask's default 8787 may be
        # taken (another cluster), and None still binds 8787 for health checks.
        # Worker processes talk over loopback TCP; threads in this process
        # use Dask's in-process transport, which takes no host.
        local = {"host": "127.0.0.1"} if dask_processes else {}
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=dask_processes,
                               dashboard_address="127.0.0.1:0", **local)
        client = Client(cluster)
    try:
        n_workers = len(client.scheduler_info().get("workers", {})) or workers
        study_future = client.scatter(study, broadcast=True)
        futures = [client.submit(run_batch, study_future, b, pure=False) for b in batches]
        for fut in as_completed(futures):
            on_done(fut.result())
            fut.release()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return n_workers


# --- progress ---------------------------------------------------------------------------------


class _Progress:
    """A text progress bar with runs per second and time left, on stderr."""

    def __init__(self, total: int, enabled: bool) -> None:
        self.total = max(total, 1)
        self.done = 0
        self.enabled = enabled
        self.start = time.perf_counter()

    def advance(self, n: int) -> None:
        self.done += n
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.done) / rate if rate > 0 else float("inf")
        filled = int(30 * self.done / self.total)
        eta = f"{left:5.0f} s left" if math.isfinite(left) else ""
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (30 - filled)}] {self.done}/{self.total} "
                         f"{rate:5.1f} runs/s {eta}")
        sys.stderr.flush()

    def close(self) -> None:
        if self.enabled:
            sys.stderr.write("\n")
            sys.stderr.flush()


# --- output -----------------------------------------------------------------------------------

LOG_NAME = "runs.jsonl"


def _read_log(path: Path) -> dict[tuple[str, str, int], dict[str, Any]]:
    """Records already made. A line cut short by an interrupted write is
    dropped (that run is simply redone)."""
    done: dict[tuple[str, str, int], dict[str, Any]] = {}
    if not path.exists():
        return done
    with path.open() as f:
        for line in f:
            try:
                rec = json.loads(line)
                key = (str(rec["key"][0]), str(rec["key"][1]), int(rec["key"][2]))
                rec["row"], rec["series"]  # noqa: B018 - both must be there
            except (json.JSONDecodeError, KeyError, IndexError, TypeError, ValueError):
                continue
            done[key] = rec
    return done


def _write_atomic(path: Path, write: Callable[[Any], None], mode: str = "w") -> None:
    tmp = path.with_name(path.name + ".tmp")
    with tmp.open(mode, newline="" if "b" not in mode else None) as f:
        write(f)
    os.replace(tmp, path)


def _fmt(x: Any) -> str:
    if isinstance(x, float):
        return repr(x)
    return str(x)


def write_table(rows: list[dict[str, Any]], path: Path) -> Path:
    """The tidy table: CSV (repr floats, so it reads back exactly), or
    Parquet when `path` ends in .parquet (needs pyarrow)."""
    columns: list[str] = []
    for r in rows:
        for k in r:
            if k not in columns:
                columns.append(k)
    if path.suffix == ".parquet":
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise StudyError("writing Parquet needs pyarrow (pip install pyarrow); use --format csv") from None
        table = pa.table({c: [r.get(c) for r in rows] for c in columns})
        tmp = path.with_name(path.name + ".tmp")
        pq.write_table(table, tmp)
        os.replace(tmp, path)
        return path

    def write(f: Any) -> None:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(columns)
        for r in rows:
            w.writerow([_fmt(r.get(c, "")) for c in columns])

    _write_atomic(path, write)
    return path


def read_table(path: str | Path) -> list[dict[str, Any]]:
    """Rows of a table written by :func:`write_table`, numbers as numbers."""
    path = Path(path)
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        return list(pq.read_table(path).to_pylist())
    out = []
    with path.open(newline="") as f:
        for r in csv.DictReader(f):
            row: dict[str, Any] = {}
            for k, v in r.items():
                try:
                    row[k] = int(v) if k in ("sample", "noise_seed") else float(v)
                except ValueError:
                    row[k] = v
            out.append(row)
    return out


# --- summaries ---------------------------------------------------------------------------------


def percentile(values: Sequence[float], q: float) -> float:
    """Linear-interpolation percentile that treats inf as larger than any
    number (numpy would give nan between two infs)."""
    v = sorted(float("inf") if not math.isfinite(x) else float(x) for x in values)
    if not v:
        return float("nan")
    pos = (len(v) - 1) * q / 100.0
    lo, hi = math.floor(pos), math.ceil(pos)
    if lo == hi or v[lo] == v[hi]:
        return v[lo]
    if math.isinf(v[hi]):
        return float("inf")
    return v[lo] + (v[hi] - v[lo]) * (pos - lo)


def failed(row: Mapping[str, Any], thresholds: Mapping[str, float]) -> bool:
    """A failure: the run diverged, a judged metric is not finite, or a metric
    is above its stated bound."""
    if float(row.get("diverged", 0.0)) != 0.0:
        return True
    for k in ("rmse_position_m", "rmse_yaw_rad", *thresholds):
        if not math.isfinite(float(row[k])):
            return True
    return any(float(row[k]) > bound for k, bound in thresholds.items())


@dataclass
class Summary:
    scenario: str
    controller: str
    label: str
    n: int
    median: float
    p5: float
    p95: float
    failure_rate: float
    rank: int = 0
    also: dict[str, float] = field(default_factory=dict)
    """Medians of the study's also_show metrics."""


def summarise(study: Study, rows: Sequence[Mapping[str, Any]]) -> list[Summary]:
    """Per scenario and controller: median and 5th/95th percentile of the
    ranking metric and the failure rate; ranked per scenario by the median
    (then failure rate, then 95th percentile)."""
    metric = study.ranking_metric
    out: list[Summary] = []
    for s in study.scenarios:
        group = []
        for c in study.controllers:
            vals = [r for r in rows if r["scenario"] == s.name and r["controller"] == c]
            if not vals:
                continue
            m = [float(r[metric]) for r in vals]
            group.append(Summary(
                scenario=s.name, controller=c, label=study.label(c), n=len(vals),
                median=percentile(m, 50), p5=percentile(m, 5), p95=percentile(m, 95),
                failure_rate=sum(failed(r, study.failure) for r in vals) / len(vals),
                also={k: percentile([float(r[k]) for r in vals], 50) for k in study.also_show},
            ))
        group.sort(key=lambda g: (g.median, g.failure_rate, g.p95, study.controllers.index(g.controller)))
        for i, g in enumerate(group):
            g.rank = i + 1
        out += group
    return out


def _num(x: float, digits: int = 4) -> str:
    if math.isinf(x):
        return "inf"
    if math.isnan(x):
        return "-"
    return f"{x:.{digits}g}" if abs(x) < 1e4 else f"{x:.3e}"


def _ratio(x: float, y: float) -> float:
    """x / y where a failed run (inf or nan) counts as infinitely bad: a
    finite x against a failed y is 0, the reverse inf, two failures a tie."""
    fx, fy = math.isfinite(x), math.isfinite(y)
    if fx and fy:
        return x / y if y > 0 else (1.0 if x == 0 else float("inf"))
    if fx:
        return 0.0
    return float("inf") if fy else 1.0


def head_to_head(study: Study, rows: Sequence[Mapping[str, Any]], a: str, b: str,
                 metric: str | None = None) -> list[dict[str, Any]]:
    """Per scenario, A against B on the same plants (same sample): the share
    of samples where A's metric (the ranking metric unless given) is lower,
    and the median of A / B."""
    metric = metric or study.ranking_metric
    by = {(r["scenario"], r["controller"], int(r["sample"])): float(r[metric]) for r in rows}
    out = []
    for s in study.scenarios:
        pairs = [(by[(s.name, a, k)], by[(s.name, b, k)]) for k in range(study.samples)
                 if (s.name, a, k) in by and (s.name, b, k) in by]
        if not pairs:
            continue
        ratios = [_ratio(x, y) for x, y in pairs]
        wins = sum(r < 1 for r in ratios)
        out.append({"scenario": s.name, "n": len(pairs), "a_wins": wins,
                    "median_ratio": percentile(ratios, 50), "p5_ratio": percentile(ratios, 5),
                    "p95_ratio": percentile(ratios, 95)})
    return out


def league_markdown(study: Study, rows: Sequence[Mapping[str, Any]]) -> str:
    """The league table: per scenario, controllers ranked by the median of
    the ranking metric, then the mean rank over all scenarios and the
    head-to-head comparisons the study asks for."""
    summ = summarise(study, rows)
    metric = study.ranking_metric
    bounds = ", ".join(f"{k} > {v:g}" for k, v in study.failure.items())
    lines = [
        f"# League table: {study.name}",
        "",
        study.description,
        "",
        f"{study.samples} sample(s) per scenario and controller, seed {study.seed}; metrics over "
        f"t >= {study.after:g} s. Ranked by the median of `{metric}` (lower is better). A run fails "
        f"if it diverges or a metric is not finite{'; or ' + bounds if bounds else ''}.",
        "",
    ]
    if study.perturbations:
        lines += ["Perturbed per sample: " + ", ".join(_describe_perturbation(p) for p in study.perturbations) + ".", ""]
    for s in study.scenarios:
        group = [g for g in summ if g.scenario == s.name]
        if not group:
            continue
        best = group[0].median
        extra_head = "".join(f" median {k} |" for k in study.also_show)
        lines += [f"## {s.name}", "", f"{s.description}", "",
                  f"| rank | controller | median {metric} | 5th-95th percentile | failure rate | median / best |"
                  + extra_head,
                  "|---|---|---|---|---|---|" + "---|" * len(study.also_show)]
        for g in group:
            ratio = g.median / best if best > 0 and math.isfinite(best) else float("nan")
            extra = "".join(f" {_num(g.also[k])} |" for k in study.also_show)
            lines.append(f"| {g.rank} | {g.label} | {_num(g.median)} | {_num(g.p5)} - {_num(g.p95)} | "
                         f"{100 * g.failure_rate:.0f} % | {_num(ratio, 3)} |" + extra)
        lines.append("")
    ranks: dict[str, list[int]] = {c: [] for c in study.controllers}
    fails: dict[str, list[float]] = {c: [] for c in study.controllers}
    for g in summ:
        ranks[g.controller].append(g.rank)
        fails[g.controller].append(g.failure_rate)
    overall = sorted((c for c in study.controllers if ranks[c]),
                     key=lambda c: (float(np.mean(ranks[c])), study.controllers.index(c)))
    if len(study.scenarios) > 1 and overall:
        lines += ["## Over all scenarios", "",
                  "| controller | mean rank | first places | mean failure rate |", "|---|---|---|---|"]
        for c in overall:
            lines.append(f"| {study.label(c)} | {np.mean(ranks[c]):.2f} | {ranks[c].count(1)} | "
                         f"{100 * float(np.mean(fails[c])):.0f} % |")
        lines.append("")
    for a, b in study.head_to_head:
        la, lb = study.label(a), study.label(b)
        others = study.also_show
        lines += [f"## {la} against {lb}", "",
                  f"Same plants and noise per sample. \"better\": samples where {la} has the lower value; "
                  f"ratio: {la} / {lb} (a failed run counts as infinitely bad).", "",
                  f"| scenario | better in `{metric}` | median ratio | 5th-95th percentile of the ratio |"
                  + "".join(f" better in `{k}` | median ratio |" for k in others),
                  "|---|---|---|---|" + "---|---|" * len(others)]
        main = head_to_head(study, rows, a, b)
        extra = {k: {h["scenario"]: h for h in head_to_head(study, rows, a, b, k)} for k in others}
        for h in main:
            cells = "".join(f" {extra[k][h['scenario']]['a_wins']} of {h['n']} | "
                            f"{_num(extra[k][h['scenario']]['median_ratio'], 3)} |" for k in others)
            lines.append(f"| {h['scenario']} | {h['a_wins']} of {h['n']} | {_num(h['median_ratio'], 3)} | "
                         f"{_num(h['p5_ratio'], 3)} - {_num(h['p95_ratio'], 3)} |" + cells)
        lines.append("")
    return "\n".join(lines).rstrip() + "\n"


def _describe_perturbation(p: Perturbation) -> str:
    if p.is_vehicle:
        spread = f"±{100 * p.relative:g} %" if p.distribution == "uniform" else \
            f"normal, sd {100 * p.relative:g} % (truncated at {NORMAL_TRUNCATION:g} sd)"
        each = " per element" if p.per_element and p.parameter not in ("mass", "weight", "buoyancy") else ""
        return f"{p.parameter} {spread}{each}"
    if p.distribution == "uniform":
        return f"{p.parameter} uniform {p.low:g}..{p.high:g}"
    return f"{p.parameter} normal mean {p.mean:g} sd {p.std:g}"


def summary_rows(study: Study, rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    return [{"scenario": g.scenario, "controller": g.controller, "rank": g.rank, "n": g.n,
             "metric": study.ranking_metric, "median": g.median, "p5": g.p5, "p95": g.p95,
             "failure_rate": g.failure_rate, **{f"median_{k}": v for k, v in g.also.items()}}
            for g in summarise(study, rows)]


# --- plots --------------------------------------------------------------------------------------


def plot_boxes(study: Study, rows: Sequence[Mapping[str, Any]], path: Path) -> Path:
    """Box plots of the ranking metric per controller, one panel per scenario."""
    from matplotlib.figure import Figure

    metric = study.ranking_metric
    n = len(study.scenarios)
    cols = min(3, n)
    nrows = math.ceil(n / cols)
    fig = Figure(figsize=(4.8 * cols, 3.6 * nrows), layout="constrained")
    axes = fig.subplots(nrows, cols, squeeze=False)
    for ax, s in zip(axes.flat, study.scenarios):
        data, labels, failures = [], [], []
        for c in study.controllers:
            vals = [float(r[metric]) for r in rows if r["scenario"] == s.name and r["controller"] == c]
            finite = [v for v in vals if math.isfinite(v)]
            if not vals:
                continue
            data.append(finite or [float("nan")])
            labels.append(study.label(c))
            failures.append(len(vals) - len(finite))
        ax.boxplot(data, whis=(5, 95), showfliers=True)
        ax.set_xticks(range(1, len(labels) + 1), labels, rotation=40, ha="right", fontsize=8)
        if all(v > 0 for d in data for v in d if math.isfinite(v)):
            ax.set_yscale("log")
        for i, nf in enumerate(failures):
            if nf:
                ax.annotate(f"{nf} not finite", (i + 1, 1.0), xycoords=("data", "axes fraction"),
                            ha="center", va="top", fontsize=7, color="C3")
        ax.set_title(s.name, fontsize=10)
        ax.set_ylabel(metric, fontsize=8)
        ax.grid(True, axis="y", alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle(f"{study.name}: {metric} over {study.samples} sample(s); whiskers 5th-95th percentile")
    fig.savefig(path, dpi=110)
    return path


def _colour(i: int) -> str:
    # Matplotlib's cycle with black for its grey (C7): grey marks the other controllers.
    return ("C0", "C1", "C2", "C3", "C4", "C5", "C6", "C8", "C9", "k")[i % 10]


def plot_bands(study: Study, records: Mapping[tuple[str, str, int], Mapping[str, Any]],
               scenario: Scenario, path: Path) -> Path:
    """Position error over time, one panel per controller: its median over
    the samples with the 5th-95th percentile band, over the other
    controllers' medians in grey for comparison."""
    from matplotlib.figure import Figure

    curves: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for c in study.controllers:
        series = [records[(scenario.name, c, k)]["series"] for k in range(study.samples)
                  if (scenario.name, c, k) in records]
        if not series:
            continue
        # A diverged run stops early and its last errors are inf or nan: it
        # leaves the statistics from there on (nan), not the whole plot.
        n = max(len(x["position_error"]) for x in series)
        e = np.full((len(series), n), np.nan)
        for k, x in enumerate(series):
            e[k, :len(x["position_error"])] = x["position_error"]
        e = np.where(np.isfinite(e), e, np.nan)
        t = series[0]["t0"] + series[0]["dt"] * np.arange(n)
        curves[c] = (t, e)
    n = max(1, len(curves))
    cols = min(5, n)
    rows = math.ceil(n / cols)
    fig = Figure(figsize=(3.2 * cols, 2.6 * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False, sharex=True, sharey=True)
    medians = {}
    with np.errstate(all="ignore"):
        import warnings

        with warnings.catch_warnings():
            # All-nan columns (every sample diverged there) warn; they plot as gaps.
            warnings.simplefilter("ignore", RuntimeWarning)
            for c, (t, e) in curves.items():
                medians[c] = (t, np.nanmedian(e, axis=0), np.nanpercentile(e, 5, axis=0),
                              np.nanpercentile(e, 95, axis=0))
    positive = np.concatenate([m[1][np.isfinite(m[1]) & (m[1] > 0)] for m in medians.values()] or [np.ones(1)])
    bottom = max(1e-4, float(np.percentile(positive, 1)) / 3) if positive.size else 1e-4
    for i, (ax, c) in enumerate(zip(axes.flat, curves)):
        for other, (t, med, _, _) in medians.items():
            if other != c:
                ax.plot(t, med, color="0.8", lw=0.6)
        t, med, lo, hi = medians[c]
        color = _colour(study.controllers.index(c))
        if study.samples > 1:
            ax.fill_between(t, lo, hi, color=color, alpha=0.25, lw=0)
        ax.plot(t, med, color=color, lw=1.2)
        ax.axvline(study.after, color="0.5", lw=0.6, ls=":")
        ax.set_yscale("log")
        ax.set_ylim(bottom=bottom)
        ax.set_title(study.label(c), fontsize=8)
        ax.grid(True, alpha=0.3)
        if i % cols == 0:
            ax.set_ylabel("position error [m]", fontsize=8)
        if i >= (rows - 1) * cols:
            ax.set_xlabel("t [s]", fontsize=8)
        ax.tick_params(labelsize=7)
    for ax in list(axes.flat)[len(curves):]:
        ax.set_visible(False)
    fig.suptitle(f"{scenario.name}: median and 5th-95th percentile over {study.samples} sample(s); "
                 "grey: the other controllers' medians", fontsize=10)
    fig.savefig(path, dpi=100)
    return path


# --- running ------------------------------------------------------------------------------------


def _load_average() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):  # not on every platform
        return None


@dataclass
class StudyOutcome:
    out_dir: Path
    total: int
    ran: int
    skipped: int
    executor: str
    workers: int
    seconds: float
    table: Path
    league: Path

    @property
    def runs_per_second(self) -> float:
        return self.ran / self.seconds if self.seconds > 0 else float("nan")


def run_study(study: Study | str | Path, out_dir: str | Path, *, workers: int | None = None,
              scheduler: str | None = None, executor: str = "auto", batch_size: int | None = None,
              table_format: str = "csv", plots: bool = True, progress: bool = True,
              dask_processes: bool = True) -> StudyOutcome:
    """Runs every (scenario x controller x sample) not already in `out_dir`
    and writes runs.csv (or runs.parquet), summary.csv, league.md,
    study.json and, with `plots`, box and band plots.

    executor: ``"dask"`` (a LocalCluster of `workers`, or the cluster at
    `scheduler`), ``"processes"`` (local processes) or ``"auto"`` (Dask if
    installed, else processes). The table is the same whichever runs it.
    """
    if not isinstance(study, Study):
        study = load_study(study)
    if executor not in ("auto", "dask", "processes"):
        raise ValueError(f"argument 'executor' must be 'auto', 'dask' or 'processes', got {executor!r}")
    if table_format not in ("csv", "parquet"):
        raise ValueError(f"argument 'table_format' must be 'csv' or 'parquet', got {table_format!r}")
    if scheduler and executor == "processes":
        raise ValueError("a scheduler address needs the Dask executor")
    if executor == "auto":
        executor = "dask" if (scheduler or dask_available()) else "processes"
    if executor == "dask" and not dask_available():
        raise StudyError('the Dask executor needs dask.distributed: pip install "neurov[distributed]"')
    workers = int(workers or os.cpu_count() or 1)
    if workers < 1:
        raise ValueError(f"argument 'workers' must be >= 1, got {workers}")

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    log = out / LOG_NAME
    meta_path = out / "study.json"
    fingerprint = study.fingerprint()
    if meta_path.exists() and log.exists():
        try:
            old = json.loads(meta_path.read_text()).get("fingerprint")
        except json.JSONDecodeError:
            old = None
        if old != fingerprint:
            raise StudyError(f"{out}: holds runs of a different study (seed, scenarios, controllers, "
                             f"perturbations or neurov version differ); use another --out, or delete "
                             f"{log} to start again")
    meta = {"name": study.name, "source": study.source, "fingerprint": fingerprint, "seed": study.seed,
            "samples": study.samples, "scenarios": [s.name for s in study.scenarios],
            "controllers": study.controllers, "ranking_metric": study.ranking_metric,
            "failure": study.failure}
    meta_path.write_text(json.dumps(meta, indent=2) + "\n")

    records = _read_log(log)
    before = set(records)
    plan = plan_runs(study)
    names = {(s.name, c, k) for s in study.scenarios for c in study.controllers for k in range(study.samples)}
    todo = [k for k in plan if (study.scenarios[k.scenario].name, study.controllers[k.controller], k.sample)
            not in records]
    skipped = len(plan) - len(todo)
    size = batch_size or default_batch_size(len(todo), workers)
    batches = _batches(todo, size)
    bar = _Progress(len(todo), progress and bool(todo))

    used_workers = workers
    load_start = _load_average()
    start = time.perf_counter()
    if todo:
        with log.open("a") as f:
            def on_done(recs: list[dict[str, Any]]) -> None:
                for rec in recs:
                    records[tuple(rec["key"])] = rec  # type: ignore[index]
                    f.write(json.dumps(rec) + "\n")
                # A finished batch is on disk before the next is awaited: an
                # interrupted study resumes from here.
                f.flush()
                bar.advance(len(recs))

            if executor == "dask":
                used_workers = _run_with_dask(study, batches, workers, scheduler, on_done, dask_processes)
            elif workers == 1:
                # One worker needs no pool; running here also keeps tracebacks plain.
                for b in batches:
                    on_done(run_batch(study, b))
            else:
                _run_with_processes(study, batches, workers, on_done)
    seconds = time.perf_counter() - start
    bar.close()

    keep = {k: v for k, v in records.items() if k in names}
    new_keys = [k for k in keep if k not in before]
    order = {(s.name, c, k): i for i, (s, c, k) in enumerate(
        (s, c, k) for s in study.scenarios for c in study.controllers for k in range(study.samples))}
    ordered = sorted(keep.values(), key=lambda r: order[tuple(r["key"])])  # type: ignore[index]
    rows = []
    for rec in ordered:
        r = rec["row"]
        # Judged here, not in the worker: changing a threshold needs no rerun.
        row = {k: r[k] for k in ("scenario", "vehicle", "controller", "sample")}
        row["failed"] = int(failed(r, study.failure))
        row.update((k, v) for k, v in r.items() if k not in row)
        rows.append(row)
    table = write_table(rows, out / f"runs.{table_format}")
    write_table(summary_rows(study, rows), out / "summary.csv")
    league = out / "league.md"
    league.write_text(league_markdown(study, rows))
    if plots and rows:
        plot_boxes(study, rows, out / f"boxplot_{study.ranking_metric}.png")
        for s in study.scenarios:
            plot_bands(study, keep, s, out / f"error_bands_{s.name}.png")
    timing: dict[str, Any] = {
        "executor": executor, "workers": used_workers, "batch_size": size, "runs": len(todo),
        "skipped": skipped, "seconds": seconds, "cpus": os.cpu_count(),
        "load_average_at_start_and_end": [load_start, _load_average()],
        "runs_per_second": len(todo) / seconds if seconds > 0 and todo else None,
        # CPU seconds the workers spent on this invocation's runs: on a shared
        # machine the wall-clock rate depends on the other load, runs per CPU
        # second does not.
        "worker_cpu_seconds": sum(records[k].get("cpu_time", 0.0) for k in new_keys),
        "loop_wall_seconds": sum(records[k].get("wall_time", 0.0) for k in new_keys),
    }
    if timing["worker_cpu_seconds"]:
        timing["runs_per_cpu_second"] = len(todo) / timing["worker_cpu_seconds"]
    (out / "timing.json").write_text(json.dumps(timing, indent=2) + "\n")
    return StudyOutcome(out_dir=out, total=len(plan), ran=len(todo), skipped=skipped, executor=executor,
                        workers=used_workers, seconds=seconds, table=table, league=league)


def main_study(path: str, out_dir: str | None, workers: int | None, scheduler: str | None,
               executor: str = "auto", table_format: str = "csv", plots: bool = True,
               batch_size: int | None = None) -> StudyOutcome:
    """What ``neurov study`` does: run, then print where things are."""
    study = load_study(path)
    out = out_dir or f"study-{study.name}"
    outcome = run_study(study, out, workers=workers, scheduler=scheduler, executor=executor,
                        table_format=table_format, plots=plots, batch_size=batch_size)
    rate = f", {outcome.runs_per_second:.2f} runs/s" if outcome.ran else ""
    print(f"{study.name}: {outcome.total} runs ({outcome.skipped} already done, {outcome.ran} run in "
          f"{outcome.seconds:.1f} s on {outcome.workers} {outcome.executor} worker(s){rate})")
    print(f"table: {outcome.table}\nleague table: {outcome.league}")
    return outcome

