"""The call sites and the good arguments the bad-input tests
(test_bad_input.py) vary one at a time: every public function that takes
arrays or numbers, with a good call of each."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import pytest

import neurov
import reference_model as ref

VEHICLE = neurov.Vehicle(**ref.general_parameters())

GOOD: dict[str, Any] = {
    "eta": np.array([1.0, -2.0, 3.0, 0.3, -0.4, 0.5]),
    "nu": np.array([0.5, -0.3, 0.2, 0.1, -0.2, 0.3]),
    "tau": np.array([10.0, -20.0, 30.0, -4.0, 5.0, -6.0]),
    "current": np.array([0.3, -0.2, 0.1]),
    **{k: np.asarray(v) if not isinstance(v, (str, float)) else v for k, v in ref.general_parameters().items()},
    # controllers and reference model
    "eta_d": np.array([1.5, -1.0, 2.0, 0.1, -0.1, 0.8]),
    "eta_d_dot": np.array([0.1, 0.2, -0.1, 0.01, 0.02, -0.03]),
    "eta_d_ddot": np.array([0.01, -0.02, 0.03, 0.001, -0.002, 0.003]),
    "lambda_": np.array([0.5, 0.5, 0.5, 0.8, 0.8, 0.8]),
    "kd": np.array([200.0, 200.0, 200.0, 50.0, 50.0, 50.0]),
    "kp": np.array([100.0, 100.0, 100.0, 20.0, 20.0, 20.0]),
    "lambda_d": np.array([1.0, 1.0, 1.0, 1.5, 1.5, 1.5]),
    "omega": np.array([0.25, 0.25, 0.25, 0.5, 0.5, 0.5]),
    "eta0": np.array([0.5, -0.5, 1.0, 0.0, 0.1, -0.2]),
    "r": np.array([10.0, 5.0, 2.0, 0.0, 0.0, 1.0]),
    "nu_r_dot": np.array([0.01, -0.02, 0.03, 0.001, -0.002, 0.003]),
    "nu_r": np.array([0.4, -0.2, 0.1, 0.05, -0.1, 0.2]),
    "gamma": np.linspace(0.1, 2.4, 24),
    "theta0": np.linspace(-5.0, 5.0, 24),
    "x": np.linspace(-1.0, 1.0, 24),
    "ki": np.array([10.0, 10.0, 10.0, 2.0, 2.0, 2.0]),
    "integral_limit": np.array([50.0, 50.0, 50.0, 10.0, 10.0, 10.0]),
    "k": np.array([20.0, 20.0, 20.0, 5.0, 5.0, 5.0]),
    "phi": np.array([0.1, 0.1, 0.1, 0.05, 0.05, 0.05]),
    "theta": np.linspace(-5.0, 5.0, 24),
}
# Integer-valued stand-ins (a valid vehicle and a regular pose).
INTEGER: dict[str, Any] = {
    "eta": np.array([1, -2, 3, 0, 1, -1]),
    "nu": np.array([1, 0, -1, 0, 1, 0]),
    "tau": np.array([10, -20, 30, -4, 5, -6]),
    "current": np.array([1, -1, 0]),
    "inertia": np.array([[25, -1, 1], [-1, 50, 2], [1, 2, 45]]),
    "added_mass": np.diag([30, 80, 80, 15, 30, 30]) + np.eye(6, k=3, dtype=int) + np.eye(6, k=-3, dtype=int),
    "linear_damping": np.array([70, 100, 100, 30, 50, 50]),
    "quadratic_damping": np.array([100, 200, 200, 50, 100, 100]),
    "centre_of_gravity": np.array([0, 0, 0]),
    "centre_of_buoyancy": np.array([0, 0, -1]),
    "eta_d": np.array([2, -1, 2, 0, 0, 1]),
    "eta_d_dot": np.array([1, 0, -1, 0, 0, 0]),
    "eta_d_ddot": np.array([0, 1, 0, 0, 0, 0]),
    "lambda_": np.array([1, 1, 1, 2, 2, 2]),
    "kd": np.array([200, 200, 200, 50, 50, 50]),
    "kp": np.array([100, 100, 100, 20, 20, 20]),
    "lambda_d": np.array([1, 1, 1, 2, 2, 2]),
    "omega": np.array([1, 1, 1, 2, 2, 2]),
    "eta0": np.array([1, -1, 1, 0, 0, 0]),
    "r": np.array([10, 5, 2, 0, 0, 1]),
    "nu_r_dot": np.array([1, -1, 0, 0, 0, 1]),
    "nu_r": np.array([0, 1, 0, 1, 0, 0]),
    "gamma": np.arange(1, 25),
    "theta0": np.arange(-12, 12),
    "x": np.arange(-12, 12),
    "ki": np.array([10, 10, 10, 2, 2, 2]),
    "integral_limit": np.array([50, 50, 50, 10, 10, 10]),
    "k": np.array([20, 20, 20, 5, 5, 5]),
    "phi": np.array([1, 1, 1, 2, 2, 2]),
    "theta": np.arange(-12, 12),
}
EXPECTED_SHAPE = {
    "eta": "(6,)",
    "nu": "(6,)",
    "tau": "(6,)",
    "current": "(3,)",
    "inertia": "(3, 3) or its diagonal (3,)",
    "added_mass": "(6, 6) or its diagonal (6,)",
    "linear_damping": "(6,)",
    "quadratic_damping": "(6,)",
    "centre_of_gravity": "(3,)",
    "centre_of_buoyancy": "(3,)",
    **{k: "(6,)" for k in ("eta_d", "eta_d_dot", "eta_d_ddot", "lambda_", "kd", "kp", "lambda_d", "omega")},
    **{k: "(6,)" for k in ("eta0", "r", "nu_r_dot", "nu_r")},
    **{k: "(24,)" for k in ("gamma", "theta0", "x", "theta")},
    **{k: "(6,)" for k in ("ki", "integral_limit", "k", "phi")},
}
# Array arguments that also take a plain number (the same value for every entry).
NUMBER_ALSO_OK = {"gamma"}
VEHICLE_KEYS = list(ref.general_parameters())


@dataclass(frozen=True)
class Site:
    """A public callable, the keyword arguments of a valid call, which of them
    are arrays (by default all) and which accept None."""

    name: str
    func: Callable[..., Any]
    args: tuple[str, ...]
    arrays: tuple[str, ...] | None = None
    optional: tuple[str, ...] = ()
    fixed: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.arrays is None:
            object.__setattr__(self, "arrays", self.args)

    def call(self, **changes: Any) -> Any:
        kwargs = {k: GOOD[k] for k in self.args}
        kwargs.update(self.fixed)
        kwargs.update(changes)
        return self.func(**kwargs)


# The arguments of the plant: Vehicle.acceleration and rk4_step.
PLANT_ARGS = ("eta", "nu", "tau", "current")

SITES = [
    Site("is_near_singularity", neurov.is_near_singularity, ("eta",)),
    Site("jacobian", neurov.jacobian, ("eta",)),
    Site("jacobian_inverse", neurov.jacobian_inverse, ("eta",)),
    Site("jacobian_dot", neurov.jacobian_dot, ("eta", "nu")),
    Site("Vehicle.coriolis", VEHICLE.coriolis, ("nu",)),
    Site("Vehicle.damping", VEHICLE.damping, ("nu",)),
    Site("Vehicle.restoring", VEHICLE.restoring, ("eta",)),
    Site("Vehicle.acceleration", VEHICLE.acceleration, PLANT_ARGS, optional=("current",)),
    Site("rk4_step", neurov.rk4_step, PLANT_ARGS, optional=("current",),
         fixed={"vehicle": VEHICLE, "dt": 0.1}),
    Site(
        "Vehicle",
        neurov.Vehicle,
        tuple(VEHICLE_KEYS),
        ("inertia", "added_mass", "linear_damping", "quadratic_damping", "centre_of_gravity", "centre_of_buoyancy"),
        optional=("centre_of_gravity", "centre_of_buoyancy"),
    ),
]
STEP_ARGS = ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot")
NETWORK = neurov.RbfNetwork(np.random.default_rng(3).normal(size=(5, 24)), 30.0)
NETWORK.weights = np.random.default_rng(4).normal(scale=10.0, size=(6, 5))


def new_nn() -> neurov.NNAdaptiveController:
    return neurov.NNAdaptiveController(NETWORK, GOOD["lambda_"], GOOD["kd"])


def new_linear() -> neurov.LinearAdaptiveController:
    return neurov.LinearAdaptiveController(GOOD["lambda_"], GOOD["kd"], GOOD["gamma"], theta0=GOOD["theta0"])


def new_pd() -> neurov.PDController:
    return neurov.PDController(GOOD["kp"], GOOD["kd"])


def new_pid() -> neurov.PIDController:
    return neurov.PIDController(GOOD["kp"], GOOD["ki"], GOOD["kd"], GOOD["integral_limit"])


def new_smc() -> neurov.SlidingModeController:
    return neurov.SlidingModeController(GOOD["lambda_"], GOOD["kd"], GOOD["k"], GOOD["phi"], GOOD["theta"])


def new_reference() -> neurov.ReferenceModel:
    return neurov.ReferenceModel(GOOD["lambda_d"], GOOD["omega"], GOOD["eta0"])


def reset_reference(**kwargs: Any) -> neurov.ReferenceModel:
    model = new_reference()
    model.step(GOOD["r"], 0.2)
    model.reset(**kwargs)
    return model


SITES += [
    Site("tracking_error", neurov.tracking_error, (*STEP_ARGS, "lambda_")),
    Site("regressor", neurov.regressor, ("nu_r_dot", "nu_r", "nu", "eta")),
    Site("ReferenceModel", neurov.ReferenceModel, ("lambda_d", "omega", "eta0"), optional=("eta0",)),
    Site("ReferenceModel.step", lambda **kw: new_reference().step(**kw), ("r",), fixed={"dt": 0.2}),
    Site("ReferenceModel.reset", reset_reference, ("eta0",)),
    Site("RbfNetwork.basis", NETWORK.basis, ("x",)),
    Site("RbfNetwork.output", NETWORK.output, ("x",)),
    Site("PDController", neurov.PDController, ("kp", "kd")),
    Site("PDController.step", lambda **kw: new_pd().step(**kw), STEP_ARGS),
    Site("NNAdaptiveController", neurov.NNAdaptiveController, ("lambda_", "kd"), fixed={"network": NETWORK}),
    Site("NNAdaptiveController.step", lambda **kw: new_nn().step(**kw), STEP_ARGS),
    Site("LinearAdaptiveController", neurov.LinearAdaptiveController, ("lambda_", "kd", "gamma", "theta0"),
         optional=("theta0",)),
    Site("LinearAdaptiveController.step", lambda **kw: new_linear().step(**kw), STEP_ARGS),
    Site("PIDController", neurov.PIDController, ("kp", "ki", "kd", "integral_limit")),
    Site("PIDController.step", lambda **kw: new_pid().step(**kw), STEP_ARGS),
    Site("SlidingModeController", neurov.SlidingModeController, ("lambda_", "kd", "k", "phi", "theta")),
    Site("SlidingModeController.step", lambda **kw: new_smc().step(**kw), STEP_ARGS),
    Site(
        "allocate_thrust",
        neurov._core.allocate_thrust,
        ("tau",),
        fixed={"matrix": np.vstack([np.eye(6), np.ones((2, 6))]).T, "max_thrust": np.full(8, 100.0)},
    ),
]
SITE = {site.name: site for site in SITES}
ARRAY_CASES = [pytest.param(site, arg, id=f"{site.name}-{arg}") for site in SITES for arg in site.arrays]


CONTROLLERS = (
    neurov.PDController,
    neurov.PIDController,
    neurov.SlidingModeController,
    neurov.NNAdaptiveController,
    neurov.LinearAdaptiveController,
)


def comparable(result: Any) -> np.ndarray:
    """Any result as one flat float array, for exact comparison."""
    if isinstance(result, neurov.Vehicle):
        p = result.parameters()
        return np.concatenate(
            [np.ravel(np.asarray(v, dtype=float)) for k, v in p.items() if k != "coriolis_form"]
            + [result.mass_matrix().ravel()]
        )
    if isinstance(result, neurov.ReferenceModel):
        result.step(GOOD["r"], 0.2)
        return np.concatenate([result.eta_d, result.nu_d, result.lambda_d, result.omega])
    if isinstance(result, CONTROLLERS):
        tau = result.step(*(GOOD[k] for k in STEP_ARGS))
        extra = [result.weights.ravel()] if isinstance(result, neurov.NNAdaptiveController) else []
        if isinstance(result, neurov.LinearAdaptiveController):
            extra = [result.theta]
        return np.concatenate([tau, result.s, *extra])
    if isinstance(result, dict):
        return np.concatenate([np.ravel(result[k]) for k in sorted(result)])
    if result is None:
        return np.zeros(0)
    if isinstance(result, tuple):
        return np.concatenate([np.ravel(x) for x in result])
    if isinstance(result, bool):
        return np.array([float(result)])
    assert isinstance(result, np.ndarray)
    assert result.dtype == np.float64
    return result.ravel()


def wrong_shapes(good: np.ndarray) -> list[tuple[int, ...]]:
    if good.ndim == 1:
        (n,) = good.shape
        return [(n - 1,), (n + 1,), (n, 1), (1, n), (), (0,), (2, n)]
    n = good.shape[0]
    return [(n, n - 1), (n - 1, n), (n * n,), (n + 1, n + 1), (n, n, 1), (), (0, 0), (n - 1,)]
