"""What a study is: the :class:`Study` a study file becomes, its
perturbations, and the names a study refers to (vehicle parameters,
environment quantities, metrics)."""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from neurov.errors import StudyError
from neurov.results.metrics import metric_names
from neurov.config.scenario import ControllerSpec, Scenario
from neurov.study.factory import ControllerFactory
from neurov._core import __version__

__all__ = ["ENVIRONMENT_PARAMETERS", "NORMAL_TRUNCATION", "SCENARIO_DIR", "STUDY_DIR", "VEHICLE_PARAMETERS",
           "Perturbation", "Study", "StudyError", "identity_differences", "metric_names",
           "vehicle_key"]

_PACKAGE = Path(__file__).resolve().parent.parent

STUDY_DIR = _PACKAGE / "studies"
SCENARIO_DIR = _PACKAGE / "scenarios"

# Vehicle parameters a study may scale (keys of a vehicle file).
VEHICLE_PARAMETERS = ("mass", "inertia", "added_mass", "linear_damping", "quadratic_damping",
                      "weight", "buoyancy")
# Quantities of the environment, drawn as absolute values.
ENVIRONMENT_PARAMETERS = {
    "current_speed": "horizontal current speed [m/s], replacing the scenario's (a Gauss-Markov current's mean)",
    "current_direction": "direction the current flows to [deg from north, towards east] (a Gauss-Markov "
                         "current's mean)",
    "noise_scale": "factor on the scenario's measurement-noise standard deviations",
    "disturbance_scale": "factor on the amplitudes of the scenario's disturbances",
}
# Absolute quantities that must stay >= 0.
NON_NEGATIVE = {"current_speed", "noise_scale", "disturbance_scale"}
# Truncation of the normal distribution, in standard deviations: a perturbed
# plant must stay physical (a factor of 1 - 2 * 0.3 is still positive).
NORMAL_TRUNCATION = 2.0

#: The most runs one study holds (scenarios x controllers x samples): a study
#: plans every run's key before the first runs, about 250 bytes each in
#: memory and one log line each on disk, so 10^6 runs are a quarter of a
#: gigabyte of keys; the shipped robustness study has 3300.
MAX_RUNS = 1_000_000


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
    factories: dict[str, ControllerFactory] = field(default_factory=dict)
    """Controller key -> the user's factory (those keys have no spec)."""
    perturbations: list[Perturbation] = field(default_factory=list)
    samples: int = 1
    seed: int = 0
    after: float = 0.0
    ranking_metric: str = "rmse_position_m"
    also_show: list[str] = field(default_factory=list)
    """Further metrics whose medians the league table shows beside the ranking."""
    failure: dict[str, float] = field(default_factory=dict)
    head_to_head: list[tuple[str, str]] = field(default_factory=list)
    basis_rank: bool = False
    """Record the NN controllers' basis along each run and add its rank
    diagnostic to the runs table (:mod:`neurov.study.basis_rank`)."""
    reference: str = ""
    """The controller the league table's paired statistics compare with
    (``[ranking] reference``; default: the first head-to-head pair's first
    member, else the first controller)."""
    description: str = ""
    source: str = ""
    cache: dict[Any, Any] = field(default_factory=dict, repr=False, compare=False)
    """Per-process memo of the NN centres (a Sobol draw costs about a third
    of a short run); not part of the study."""

    def label(self, controller: str) -> str:
        if controller in self.factories:
            return self.factories[controller].label
        specs = [s for (c, _), s in self.controller_specs.items() if c == controller]
        return specs[0].label if specs and specs[0].label else controller

    def reference_controller(self) -> str:
        if self.reference:
            return self.reference
        return self.head_to_head[0][0] if self.head_to_head else self.controllers[0]

    def spec_for(self, controller: str, scenario: Scenario) -> ControllerSpec:
        return self.controller_specs[(controller, vehicle_key(scenario))]

    def _identity_payload(self) -> dict[str, Any]:
        payload: dict[str, Any] = {
            "version": __version__,
            "seed": self.seed,
            "after": self.after,
            "perturbations": [dataclasses.asdict(p) for p in self.perturbations],
            "scenarios": [_canonical(s.describe()) for s in self.scenarios],
            "controllers": {f"{c}@{v}": _canonical(s.describe())
                            for (c, v), s in sorted(self.controller_specs.items())},
        }
        if self.factories:
            # The path, not the code: a changed module keeps the fingerprint (docs: start a new folder).
            payload["factories"] = {c: [f.path, dict(f.arguments)] if f.arguments else f.path
                                    for c, f in sorted(self.factories.items())}
        return payload

    def fingerprint(self) -> str:
        """A hash of everything that decides a run's numbers. The sample count,
        failure thresholds and ranking are left out: adding samples or
        changing how runs are judged reuses the runs already made."""
        return _hash(self._identity_payload())

    def identity(self) -> dict[str, Any]:
        """What the fingerprint is made of, field by field (the version, seed
        and metrics window as they are, the rest hashed), so that a folder
        holding another study's runs can say which field differs."""
        payload = self._identity_payload()
        out: dict[str, Any] = {k: payload[k] for k in ("version", "seed", "after")}
        out["perturbations"] = _hash(payload["perturbations"])
        out["scenarios"] = {s.name: _hash(d) for s, d in zip(self.scenarios, payload["scenarios"])}
        out["controllers"] = {c: _hash(d) for c, d in payload["controllers"].items()}
        if "factories" in payload:
            out["factories"] = payload["factories"]
        return out


def identity_differences(old: Mapping[str, Any], new: Mapping[str, Any]) -> list[str]:
    """The fields of two :meth:`Study.identity` that differ, as a reader
    names them: ``seed (7 there, 8 here)``, ``controllers (nn@nerov)``."""
    names = {"version": "neurov version", "after": "after (the metrics window)"}
    out = []
    for field_name in ("version", "seed", "after", "perturbations", "scenarios", "controllers", "factories"):
        a, b = old.get(field_name), new.get(field_name)
        if a == b:
            continue
        label = names.get(field_name, field_name)
        if isinstance(a, Mapping) and isinstance(b, Mapping):
            keys = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
            out.append(f"{label} ({', '.join(keys)})")
        elif field_name == "perturbations":
            out.append(label)
        else:
            out.append(f"{label} ({a!r} there, {b!r} here)")
    return out


def _hash(x: Any) -> str:
    text = json.dumps(x, sort_keys=True, default=str)
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


