"""Bad arguments to the controllers: a non-finite or malformed step argument
raises naming it and changes nothing; a bad configuration names the
parameter."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import neurov
from controller_reference import make_nn, random_case

Array = np.ndarray


# ---------------------------------------------------------------- bad input

ARG_NAMES = ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot")


def controllers(rng: np.random.Generator) -> list[tuple[Any, Any]]:
    """Each controller with a function returning the state a refused step must not touch."""
    c = random_case(rng)
    nn = make_nn(c)
    lin = neurov.LinearAdaptiveController(np.ones(6), np.full(6, 30.0), 2.0, 0.05, rng.uniform(0, 100, 24))
    pd = neurov.PDController(np.full(6, 50.0), np.full(6, 20.0))

    def nn_state(x: neurov.NNAdaptiveController) -> bytes:
        return x.weights.tobytes() + x.s.tobytes() + x.network_output.tobytes() + x.basis.tobytes() + bytes([x.adapted])

    def lin_state(x: neurov.LinearAdaptiveController) -> bytes:
        return x.theta.tobytes() + x.s.tobytes() + x.model_output.tobytes()

    def pd_state(x: neurov.PDController) -> bytes:
        return x.s.tobytes() + x.tracking["eta_tilde"].tobytes()

    return [(nn, nn_state), (lin, lin_state), (pd, pd_state)]


@pytest.mark.parametrize("which", [0, 1, 2], ids=["nn", "linear", "pd"])
def test_non_finite_argument_raises_naming_it_and_changes_nothing(which: int) -> None:
    ctl, state = controllers(np.random.default_rng(7))[which]
    twin, _ = controllers(np.random.default_rng(7))[which]
    args = list(random_case(np.random.default_rng(8)).args())
    for c in (ctl, twin):  # a history, so "unchanged" means something
        c.step(*args)
        c.step(*args)
    before = state(ctl)
    for i, name in enumerate(ARG_NAMES):
        for bad in (np.nan, np.inf, -np.inf):
            for index in (0, 4):
                broken = [a.copy() for a in args]
                broken[i][index] = bad
                with pytest.raises(ValueError, match=f"'{name}'"):
                    ctl.step(*broken)
                assert state(ctl) == before, name
    for pitch in (np.pi / 2, -np.pi / 2):
        singular = [a.copy() for a in args]
        singular[0][4] = pitch
        with pytest.raises(ValueError, match="'eta'.*singularity"):
            ctl.step(*singular)
        assert state(ctl) == before
    # Afterwards it steps exactly as the twin that never saw the bad calls.
    np.testing.assert_array_equal(ctl.step(*args), twin.step(*args))
    assert state(ctl) == state(twin)


@pytest.mark.parametrize(
    ("arg", "value", "error", "match"),
    [
        ("eta", np.zeros(5), ValueError, r"'eta' must have shape \(6,\)"),
        ("nu", None, TypeError, "'nu'"),
        ("eta_d_dot", np.zeros((6, 1)), ValueError, "'eta_d_dot'"),
        ("eta_d_ddot", ["a"] * 6, TypeError, "'eta_d_ddot'"),
    ],
)
def test_malformed_argument_names_it(rng: np.random.Generator, arg: str, value: object, error: type, match: str) -> None:
    for ctl, state in controllers(rng):
        args = dict(zip(ARG_NAMES, random_case(rng).args()))
        before = state(ctl)
        args[arg] = value  # type: ignore[assignment]
        with pytest.raises(error, match=match):
            ctl.step(**args)
        assert state(ctl) == before


# ------------------------------------------------------------ configuration


def nn_kwargs(**change: Any) -> dict[str, Any]:
    net = neurov.RbfNetwork(np.zeros((3, 24)), 1.0)
    return {"network": net, "lambda_": np.ones(6), "kd": np.full(6, 10.0), "gamma": 0.3, "dt": 0.2} | change


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"lambda_": [1, 1, 0, 1, 1, 1]}, r"lambda_?\[2\] = 0"),
        ({"lambda_": [-1, 1, 1, 1, 1, 1]}, r"lambda_?\[0\] = -1"),
        ({"kd": [0, -1, 0, 0, 0, 0]}, r"kd\[1\] = -1"),
        ({"gamma": -0.1}, r"gamma = -0.1"),
        ({"dt": 0.0}, r"dt = 0"),
        ({"dt": -0.2}, r"dt = -0.2"),
        ({"dt": np.nan}, r"'dt' must be finite"),
        ({"modification": "sigma", "sigma_m": 0.0}, r"sigma_m = 0.*sigma"),
        ({"modification": "e_modification"}, r"kappa = 0"),
        ({"modification": "projection"}, r"w_max = 0"),
        ({"modification": "leaky"}, r"'modification' must be.*got 'leaky'"),
        ({"dead_zone": -0.1}, r"dead_zone = -0.1"),
        ({"learning_rates": [0.3, -0.1, 0.3]}, r"'learning_rates'"),
        ({"learning_rates": [0.3, 0.3]}, r"'learning_rates' must have shape \(3,\)"),
        ({"network": neurov.RbfNetwork(np.zeros((3, 23)), 1.0)}, r"'network' must have 24 inputs"),
    ],
)
def test_nn_configuration_errors_name_the_parameter(change: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        neurov.NNAdaptiveController(**nn_kwargs(**change))


def test_nn_modification_must_be_a_string() -> None:
    with pytest.raises(TypeError, match="'modification' must be a str"):
        neurov.NNAdaptiveController(**nn_kwargs(modification=1))


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"lambda_": [1, 0, 1, 1, 1, 1]}, r"lambda_?\[1\] = 0"),
        ({"kd": [0, 0, 0, -2, 0, 0]}, r"kd\[3\] = -2"),
        ({"gamma": -1.0}, r"gamma(\[0\])? = -1"),
        ({"gamma": np.r_[np.ones(23), -1.0]}, r"gamma\[23\] = -1"),
        ({"dt": 0.0}, r"dt = 0"),
        ({"theta0": np.r_[np.nan, np.zeros(23)]}, r"'theta0' must be finite"),
        ({"theta0": np.zeros(23)}, r"'theta0' must have shape \(24,\)"),
    ],
)
def test_linear_configuration_errors_name_the_parameter(change: dict, match: str) -> None:
    kwargs = {"lambda_": np.ones(6), "kd": np.full(6, 10.0), "gamma": 1.0, "dt": 0.1} | change
    with pytest.raises(ValueError, match=match):
        neurov.LinearAdaptiveController(**kwargs)


@pytest.mark.parametrize(("kp", "kd", "match"), [([-1, 0, 0, 0, 0, 0], np.zeros(6), r"kp\[0\] = -1"), (np.zeros(6), [0, 0, 0, 0, 0, -3], r"kd\[5\] = -3")])
def test_pd_configuration_errors_name_the_parameter(kp: Any, kd: Any, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        neurov.PDController(kp, kd)
