"""Snapshots: a pickled, deep-copied or copied controller, RBF network,
reference model or vehicle steps exactly as the original, to the bit."""

from __future__ import annotations

import copy
import pickle
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import neurov

LAM = np.array([0.8, 0.8, 0.8, 0.6, 0.6, 0.6])
KD = np.array([200.0, 200.0, 200.0, 50.0, 50.0, 50.0])


def _network(n: int = 7) -> neurov.RbfNetwork:
    rng = np.random.default_rng(11)
    net = neurov.RbfNetwork(rng.normal(size=(n, 24)), rng.uniform(2.0, 4.0, size=n))
    net.weights = rng.normal(scale=3.0, size=(6, n))
    return net


def _nn() -> neurov.NNAdaptiveController:
    return neurov.NNAdaptiveController(
        _network(), LAM, KD, 0.5, 0.1, modification="e_modification", kappa=0.01,
        learning_rates=np.linspace(0.2, 0.9, 7),
    )


def _theta(vehicle: neurov.Vehicle) -> np.ndarray:
    return np.asarray(neurov.regressor_parameters(vehicle))


CONTROLLERS: dict[str, Callable[[neurov.Vehicle], Any]] = {
    "pd": lambda v: neurov.PDController(np.full(6, 300.0), np.full(6, 80.0)),
    "pid": lambda v: neurov.PIDController(np.full(6, 300.0), np.full(6, 40.0), np.full(6, 80.0),
                                          np.full(6, 50.0), 0.1),
    "sliding_mode": lambda v: neurov.SlidingModeController(LAM, KD, np.full(6, 20.0),
                                                           np.full(6, 0.2), _theta(v)),
    "linear_adaptive": lambda v: neurov.LinearAdaptiveController(LAM, KD, 0.05, 0.1, 0.9 * _theta(v)),
    "nn_adaptive": lambda v: _nn(),
    "computed_torque": lambda v: neurov.ComputedTorqueController(v, LAM, KD),
}

SNAPSHOTS: dict[str, Callable[[Any], Any]] = {
    "pickle": lambda obj: pickle.loads(pickle.dumps(obj)),
    "deepcopy": copy.deepcopy,
    "copy": copy.copy,
}


def _inputs(rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    eta = rng.normal(scale=0.5, size=6)
    eta[4] = rng.uniform(-0.6, 0.6)  # away from the pitch singularity
    return eta, rng.normal(scale=0.3, size=6), rng.normal(scale=0.5, size=6), \
        rng.normal(scale=0.2, size=6), rng.normal(scale=0.1, size=6)


def _memory(ctl: Any) -> list[np.ndarray]:
    """Everything a controller exposes of its state."""
    out = [np.asarray(v) for v in ctl.tracking.values()]
    for name in ("weights", "basis", "network_output", "adapted", "weight_norm", "theta",
                 "model_output", "integral"):
        if hasattr(ctl, name):
            out.append(np.asarray(getattr(ctl, name)))
    return out


def _assert_identical(a: list[np.ndarray], b: list[np.ndarray]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.tobytes() == y.tobytes()


@pytest.mark.parametrize("snapshot", SNAPSHOTS)
@pytest.mark.parametrize("kind", CONTROLLERS)
def test_controller_snapshot_steps_as_the_original(kind: str, snapshot: str, nerov: neurov.Vehicle) -> None:
    rng = np.random.default_rng(5)
    ctl = CONTROLLERS[kind](nerov)
    for _ in range(15):
        ctl.step(*_inputs(rng))
    twin = SNAPSHOTS[snapshot](ctl)
    assert type(twin) is type(ctl) and twin is not ctl
    _assert_identical(_memory(twin), _memory(ctl))
    for _ in range(15):
        u = _inputs(rng)
        assert ctl.step(*u).tobytes() == twin.step(*u).tobytes()
    _assert_identical(_memory(twin), _memory(ctl))
    # The twin is independent of the original.
    ctl.reset()
    assert not np.array_equal(twin.s, ctl.s)


def test_nn_snapshot_keeps_initial_weights_and_rates() -> None:
    rng = np.random.default_rng(8)
    ctl = _nn()
    w0 = ctl.weights
    for _ in range(10):
        ctl.step(*_inputs(rng))
    assert not np.array_equal(ctl.weights, w0)
    twin = pickle.loads(pickle.dumps(ctl))
    assert twin.modification == "e_modification"
    twin.reset()
    assert twin.weights.tobytes() == w0.tobytes()


def test_a_snapshot_after_a_refused_step_keeps_the_status() -> None:
    """The last status is state too: the step after a refused one behaves
    the same in the original and the copy."""
    rng = np.random.default_rng(2)
    ctl = _nn()
    for _ in range(5):
        ctl.step(*_inputs(rng))
    bad = list(_inputs(rng))
    bad[0][4] = np.pi / 2  # the pitch singularity: refused in C++
    with pytest.raises(ValueError, match="singularity"):
        ctl.step(*bad)
    state = ctl.__getstate__()
    assert state["status"] == 1  # near_singularity
    twin = pickle.loads(pickle.dumps(ctl))
    assert twin.__getstate__()["status"] == 1
    u = _inputs(rng)
    assert ctl.step(*u).tobytes() == twin.step(*u).tobytes()


@pytest.mark.parametrize("field", ["weights", "basis", "network_output"])
def test_a_corrupt_snapshot_is_refused(field: str) -> None:
    state = _nn().__getstate__()
    state[field] = np.full_like(np.asarray(state[field]), np.nan)
    with pytest.raises(ValueError, match=f"argument '{field}' must be finite"):
        _restore(neurov.NNAdaptiveController, state)


def test_a_snapshot_of_the_wrong_size_is_refused() -> None:
    state = neurov.PIDController(np.ones(6), np.ones(6), np.ones(6), np.ones(6)).__getstate__()
    state["integral"] = np.zeros(5)
    with pytest.raises(ValueError, match="integral"):
        _restore(neurov.PIDController, state)
    del state["integral"]
    with pytest.raises(ValueError, match="field 'integral' is missing"):
        _restore(neurov.PIDController, state)


def _restore(cls: type, state: dict[str, Any]) -> Any:
    """What unpickling does with `state`: __setstate__ on a new object."""
    obj = cls.__new__(cls)
    obj.__setstate__(state)
    return obj


@pytest.mark.parametrize("snapshot", SNAPSHOTS)
def test_rbf_network_snapshot(snapshot: str) -> None:
    rng = np.random.default_rng(1)
    net = neurov.RbfNetwork(rng.normal(size=(9, 4)), rng.uniform(1, 2, 9), rng.normal(size=4),
                            rng.uniform(0.5, 2, 4))
    net.weights = rng.normal(size=(6, 9))
    twin = SNAPSHOTS[snapshot](net)
    for name in ("weights", "centres", "widths", "input_offset", "input_scale"):
        assert np.asarray(getattr(twin, name)).tobytes() == np.asarray(getattr(net, name)).tobytes()
    x = rng.normal(size=4)
    assert twin.output(x).tobytes() == net.output(x).tobytes()
    net.weights = np.zeros((6, 9))
    assert np.any(twin.weights != 0)


@pytest.mark.parametrize("snapshot", SNAPSHOTS)
def test_reference_model_snapshot_steps_as_the_original(snapshot: str) -> None:
    rng = np.random.default_rng(4)
    ref = neurov.ReferenceModel(np.full(6, 1.2), np.full(6, 0.4), rng.normal(scale=0.2, size=6))
    # A command past the pitch limit, so that pitch_limited is state worth keeping.
    for _ in range(8):
        ref.step([1, -1, 2, 0.3, 1.55, -0.4], 0.2)
    twin = SNAPSHOTS[snapshot](ref)
    assert twin.pitch_limited == ref.pitch_limited
    for _ in range(8):
        r = rng.normal(size=6)
        r[4] = 0.3
        a, b = ref.step(r, 0.2), twin.step(r, 0.2)
        assert all(x.tobytes() == y.tobytes() for x, y in zip(a, b))
    assert ref.nu_d.tobytes() == twin.nu_d.tobytes()


@pytest.mark.parametrize("snapshot", SNAPSHOTS)
def test_vehicle_snapshot(snapshot: str, nerov: neurov.Vehicle) -> None:
    twin = SNAPSHOTS[snapshot](nerov)
    eta, nu = np.full(6, 0.1), np.full(6, 0.2)
    tau = np.arange(6.0)
    a = neurov.rk4_step(vehicle=nerov, eta=eta, nu=nu, tau=tau, dt=0.1)
    b = neurov.rk4_step(vehicle=twin, eta=eta, nu=nu, tau=tau, dt=0.1)
    assert all(np.asarray(x).tobytes() == np.asarray(y).tobytes() for x, y in zip(a, b))
