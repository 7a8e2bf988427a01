"""Argument checking of every public function that takes arrays or numbers:
a wrong shape, dtype or a non-finite value is an error that names the
argument; every reasonable array-like is accepted and gives the same result."""

from __future__ import annotations

import fractions
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


# ------------------------------------------------------------- array arguments


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_wrong_shape(site: Site, arg: str) -> None:
    for shape in wrong_shapes(np.asarray(GOOD[arg])):
        with pytest.raises(ValueError) as err:
            site.call(**{arg: np.ones(shape)})
        message = str(err.value)
        assert f"'{arg}'" in message, message
        assert EXPECTED_SHAPE[arg] in message, message
        assert f"got {shape}" in message, message


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_python_scalar_for_an_array_is_a_shape_error(site: Site, arg: str) -> None:
    if arg in NUMBER_ALSO_OK:
        np.testing.assert_array_equal(
            comparable(site.call(**{arg: 2.0})), comparable(site.call(**{arg: np.full(np.shape(GOOD[arg]), 2.0)}))
        )
        return
    with pytest.raises(ValueError, match=f"'{arg}'.*must have shape"):
        site.call(**{arg: 1.0})


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_wrong_dtype(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg])
    bad_values = {
        "str array": np.full(good.shape, "a"),
        "str list": np.full(good.shape, "1.0").tolist(),
        "str": "abcdef",
        "complex": good.astype(complex),
        "object": good.astype(object),
        "bool": np.ones(good.shape, dtype=bool),
        "dict": {"a": 1},
        "object()": object(),
        "bytes": b"\x00" * 48,
    }
    for what, bad in bad_values.items():
        with pytest.raises(TypeError) as err:
            site.call(**{arg: bad})
        assert f"'{arg}'" in str(err.value), (what, str(err.value))


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_none(site: Site, arg: str) -> None:
    if arg in site.optional:
        # None is the default: the same as leaving the argument out.
        kwargs = {k: GOOD[k] for k in site.args if k != arg}
        kwargs.update(site.fixed)
        np.testing.assert_array_equal(comparable(site.call(**{arg: None})), comparable(site.func(**kwargs)))
    else:
        with pytest.raises(TypeError, match=f"'{arg}'.*None"):
            site.call(**{arg: None})


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_non_finite(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg], dtype=float)
    for bad in (np.nan, np.inf, -np.inf):
        for index in (0, good.size - 1):
            value = good.copy()
            value.flat[index] = bad
            with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
                site.call(**{arg: value})
            with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
                site.call(**{arg: value.tolist()})


def accepted_forms(good: np.ndarray) -> dict[str, Any]:
    strided = np.zeros(good.shape[:-1] + (2 * good.shape[-1],))
    strided[..., ::2] = good
    view = strided[..., ::2]
    assert not view.flags.c_contiguous
    reversed_ = good[::-1].copy()[::-1]
    readonly = good.copy()
    readonly.flags.writeable = False
    forms = {
        "list": good.tolist(),
        "tuple": tuple(good.tolist()),
        "strided view": view,
        "negative strides": reversed_,
        "read-only": readonly,
        "read-only strided": np.lib.stride_tricks.as_strided(view, writeable=False),
        "big-endian": good.astype(">f8"),
    }
    if good.ndim == 2:
        forms["fortran order"] = np.asfortranarray(good)
        forms["transposed view"] = good.T.copy().T
    return forms


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_array_likes_are_accepted_and_agree(site: Site, arg: str) -> None:
    good = np.asarray(GOOD[arg], dtype=float)
    expected = comparable(site.call(**{arg: good}))
    for what, value in accepted_forms(good).items():
        before = np.array(value, copy=True)
        got = comparable(site.call(**{arg: value}))
        np.testing.assert_array_equal(got, expected, err_msg=what)
        np.testing.assert_array_equal(np.asarray(value), before, err_msg=f"{what} was modified")


@pytest.mark.parametrize(("site", "arg"), ARRAY_CASES)
def test_integer_and_float32_arrays_are_accepted(site: Site, arg: str) -> None:
    ints = INTEGER[arg]
    expected = comparable(site.call(**{arg: ints.astype(float)}))
    for dtype in (np.int64, np.int32, np.int16):
        got = comparable(site.call(**{arg: ints.astype(dtype)}))
        np.testing.assert_array_equal(got, expected, err_msg=str(dtype))
    np.testing.assert_array_equal(comparable(site.call(**{arg: ints.tolist()})), expected)
    good32 = np.asarray(GOOD[arg]).astype(np.float32)
    np.testing.assert_array_equal(
        comparable(site.call(**{arg: good32})), comparable(site.call(**{arg: good32.astype(np.float64)}))
    )


def test_array_results_are_fresh_writeable_float64() -> None:
    for site in SITES:
        result = site.call()
        arrays = result if isinstance(result, tuple) else (result,)
        for a in arrays:
            if isinstance(a, np.ndarray):
                assert a.dtype == np.float64 and a.flags.writeable, site.name
                assert not any(np.shares_memory(a, GOOD[k]) for k in site.args if isinstance(GOOD[k], np.ndarray))


# ------------------------------------------------------------ scalar arguments

SCALAR_CASES = [
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "phi", id="rotation-phi"),
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "theta", id="rotation-theta"),
    pytest.param(lambda **kw: neurov.rotation(**{"phi": 0.1, "theta": -0.2, "psi": 0.3, **kw}), "psi", id="rotation-psi"),
    pytest.param(lambda **kw: SITE["rk4_step"].call(**{"dt": 0.1, **kw}), "dt", id="rk4_step-dt"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "mass", id="Vehicle-mass"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "weight", id="Vehicle-weight"),
    pytest.param(lambda **kw: SITE["Vehicle"].call(**kw), "buoyancy", id="Vehicle-buoyancy"),
]


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_wrong_type(call: Callable[..., Any], arg: str) -> None:
    for bad in (None, "1.0", True, False, 1j, [1.0], (1.0,), {"x": 1.0}, object()):
        with pytest.raises(TypeError, match=f"'{arg}'"):
            call(**{arg: bad})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_given_a_one_element_array(call: Callable[..., Any], arg: str) -> None:
    with pytest.raises(TypeError, match=f"'{arg}'"):
        call(**{arg: np.array([1.0])})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_non_finite(call: Callable[..., Any], arg: str) -> None:
    for bad in (np.nan, np.inf, -np.inf, float("nan"), np.float32("nan")):
        with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
            call(**{arg: bad})


@pytest.mark.parametrize(("call", "arg"), SCALAR_CASES)
def test_scalar_number_types_are_accepted(call: Callable[..., Any], arg: str) -> None:
    value = {"phi": 1, "theta": -1, "psi": 2, "dt": 1, "mass": 185, "weight": 1815, "buoyancy": 1790}[arg]
    expected = comparable(call(**{arg: float(value)}))
    for form in (
        value,
        np.int64(value),
        np.int32(value),
        np.float64(value),
        np.float32(value),
        np.array(float(value)),
        fractions.Fraction(value),
    ):
        np.testing.assert_array_equal(comparable(call(**{arg: form})), expected, err_msg=repr(form))


@pytest.mark.parametrize("dt", [0, 0.0, -0.0, -0.1, -np.inf, np.inf, np.nan])
def test_rk4_step_bad_dt(dt: float) -> None:
    with pytest.raises(ValueError, match="'dt'"):
        neurov.rk4_step(VEHICLE, GOOD["eta"], GOOD["nu"], GOOD["tau"], dt)


@pytest.mark.parametrize("dt", [True, False, None, "0.1", 0.1j])
def test_rk4_step_dt_of_wrong_type(dt: Any) -> None:
    with pytest.raises(TypeError, match="'dt'"):
        neurov.rk4_step(VEHICLE, GOOD["eta"], GOOD["nu"], GOOD["tau"], dt)


def test_rk4_step_needs_a_vehicle() -> None:
    for bad in (None, neurov.Vehicle.nerov().parameters(), "nerov"):
        with pytest.raises(TypeError, match="vehicle"):
            neurov.rk4_step(bad, GOOD["eta"], GOOD["nu"], GOOD["tau"], 0.1)  # type: ignore[arg-type]


# ---------------------------------------------------- Vehicle(...) parameters

BAD_VEHICLE_VALUES = {
    "zero mass": ("mass", 0.0),
    "negative mass": ("mass", -1.0),
    "negative weight": ("weight", -1.0),
    "negative buoyancy": ("buoyancy", -0.5),
    "non-symmetric inertia": ("inertia", [[25.0, 1.0, 0.0], [0.0, 50.0, 0.0], [0.0, 0.0, 50.0]]),
    "indefinite inertia": ("inertia", [-100.0, 50.0, 50.0]),
    "non-symmetric added_mass": ("added_mass", np.triu(np.full((6, 6), 5.0)) + np.eye(6) * 30),
    "indefinite added_mass": ("added_mass", np.full(6, -1000.0)),
    "negative linear_damping": ("linear_damping", [70.0, 100.0, -1.0, 30.0, 50.0, 50.0]),
    "negative quadratic_damping": ("quadratic_damping", [-100.0, 200.0, 200.0, 50.0, 100.0, 100.0]),
    "off-centre gravity": ("centre_of_gravity", [0.0, 0.0, 5.0]),  # M_RB indefinite
    "unknown coriolis_form": ("coriolis_form", "m2c"),
    "empty coriolis_form": ("coriolis_form", ""),
}


@pytest.mark.parametrize("case", list(BAD_VEHICLE_VALUES))
def test_vehicle_bad_parameter(case: str) -> None:
    key, value = BAD_VEHICLE_VALUES[case]
    p = ref.general_parameters()
    p[key] = value
    with pytest.raises(ValueError) as err:
        neurov.Vehicle(**p)
    assert key in str(err.value), str(err.value)


def test_vehicle_negative_inertia_is_refused() -> None:
    p = dict(ref.NEROV, inertia=[-1.0, 50.0, 50.0])  # M[3, 3] = -1 + 15 > 0
    with pytest.raises(ValueError, match="inertia"):
        neurov.Vehicle(**p)


def test_vehicle_coriolis_form_must_be_a_string() -> None:
    with pytest.raises(TypeError, match="'coriolis_form'"):
        neurov.Vehicle(**dict(ref.NEROV, coriolis_form=1))


def test_vehicle_unknown_or_missing_keyword() -> None:
    with pytest.raises(TypeError, match="masss"):
        neurov.Vehicle(**dict(ref.NEROV, masss=1.0))
    p = dict(ref.NEROV)
    del p["mass"]
    with pytest.raises(TypeError):
        neurov.Vehicle(**p)
    with pytest.raises(TypeError):
        neurov.Vehicle(185.0)  # type: ignore[call-arg]


def test_vehicle_error_leaves_nothing_half_built() -> None:
    """A failed build raises; the presets are unaffected."""
    with pytest.raises(ValueError):
        neurov.Vehicle(**dict(ref.NEROV, mass=-1.0))
    assert neurov.Vehicle.nerov().mass == 185.0
