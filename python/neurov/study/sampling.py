"""The plant of one sample: the perturbation draws, fixed by the study's
seed and the sample index alone, applied to a scenario's vehicle, current,
noise and disturbances."""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from neurov import _core
from neurov.config.scenario import Scenario
from neurov.study.spec import Perturbation, Study

__all__ = ["draw_perturbations", "draw_sample", "nominal_parameters", "plant_changes", "sample_plant",
           "sample_seeds", "scaled"]

def nominal_parameters(scenario: Scenario) -> dict[str, Any]:
    params = dict(scenario.vehicle_data().parameters)
    params.update(scenario.vehicle_parameters or {})
    return params


def scaled(value: Any, factors: Any, per_element: bool) -> Any:
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
    """The drawn values of every perturbation and the noise seed of `sample`
    (:func:`draw_perturbations` from the sample's own generator)."""
    rng, noise_seed = sample_seeds(study.seed, sample)
    return draw_perturbations(study.perturbations, rng), noise_seed


def draw_perturbations(perturbations: Sequence[Perturbation], rng: np.random.Generator) -> dict[str, np.ndarray]:
    """The drawn values of every perturbation from `rng` (6 per vehicle
    vector, 3 for inertia, 1 otherwise). The same draws apply to every
    scenario; a vehicle's vector uses as many as it has entries."""
    draws: dict[str, np.ndarray] = {}
    for p in perturbations:
        n = {"inertia": 3, "added_mass": 6, "linear_damping": 6, "quadratic_damping": 6}.get(p.parameter, 1)
        values = p.draw(rng, n if p.per_element else 1)
        draws[p.parameter] = values if p.per_element else np.full(n, values[0])
    return draws


def sample_plant(study: Study, scenario: Scenario, sample: int) -> tuple[Scenario, dict[str, float]]:
    """The scenario as sample `sample` sees it (perturbed vehicle, current,
    noise, disturbances and noise seed) and the drawn values, flat, for the
    table."""
    draws, noise_seed = draw_sample(study, sample)
    changes, columns = plant_changes(scenario, study.perturbations, draws)
    return scenario.replace(seed=noise_seed, **changes), columns


def plant_changes(scenario: Scenario, perturbations: Sequence[Perturbation], draws: dict[str, np.ndarray]
                  ) -> tuple[dict[str, Any], dict[str, float]]:
    """The changes to the scenario (:meth:`Scenario.replace`'s arguments) that
    make the drawn plant, and the drawn values, flat, for a table."""
    changes: dict[str, Any] = {}
    params = nominal_parameters(scenario)
    columns: dict[str, float] = {}
    touched_vehicle = False
    for p in perturbations:
        values = draws[p.parameter]
        if p.is_vehicle:
            n = _length(params[p.parameter])
            params[p.parameter] = scaled(params[p.parameter], values[:n], True)
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
    if scenario.current_model == _core.CurrentModel.gauss_markov:
        # The Gauss-Markov current wanders about a mean: the draws move the mean.
        if "current_speed" in draws or "current_direction" in draws:
            gm = copy.copy(scenario.gauss_markov_current)
            if "current_speed" in draws:
                gm.speed = float(draws["current_speed"][0])
            if "current_direction" in draws:
                gm.direction = float(draws["current_direction"][0])
            changes["gauss_markov_current"] = gm
    elif "current_speed" in draws or "current_direction" in draws:
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
        changes["disturbances"] = [_scaled_amplitude(d, k) for d in scenario.disturbances]
    return changes, columns


def _scaled_amplitude(d: Any, k: float) -> Any:
    """A copy of a disturbance with its amplitude times k."""
    out = copy.copy(d)
    out.amplitude = d.amplitude * k
    return out
