"""Faults during a run: one scenario file per fault in examples/scenarios/faults/,
each run whole through neurov.simulate.

For every fault the closed loop must keep tau finite and the produced wrench
within what the thrusters can give, report the fault while it lasts (the
`faults` bit column, `controller_status`), keep the weights bounded (the
scenarios run the NN controller with sigma-modification) and recover: the
tracking error back under the fault-free run's own bound a stated time after
the fault clears. Each fault must also visibly hurt while it lasts, or the
recovery check would be vacuous.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

import neurov
from neurov.results.timeseries import Result
from neurov.config.vehicle_file import load_thrusters, preset_path

ROOT = Path(__file__).resolve().parents[2]
FAULTS = ROOT / "examples" / "scenarios" / "faults"

# The fault-free square (any of the scenarios with its faults removed) stays
# within 0.17 m and 0.15 rad of the reference after its 10 s start-up
# transient (measured: 0.168 m, 0.141 rad); these bounds leave a margin for
# the noise of a different seed and are what "recovered" means below.
POSITION_BOUND_M = 0.25
YAW_BOUND_RAD = 0.2
TRANSIENT_S = 10.0

# (file, fault bit, fault interval [s), seconds after the fault clears by
# which the error must be back under the bounds).
CASES = {
    "thruster_failure": (8, (60.0, 100.0), 30.0),
    "sensor_freeze": (1, (80.0, 83.0), 20.0),
    "sensor_dropout": (2, (80.0, 82.0), 20.0),
    "noise_burst": (4, (80.0, 90.0), 20.0),
    "current_step": (0, (60.0, 130.0), 30.0),
}


@lru_cache(maxsize=None)
def run(name: str) -> Result:
    return neurov.simulate(neurov.load_scenario(FAULTS / f"{name}.toml"))


@lru_cache(maxsize=None)
def run_fault_free(name: str) -> Result:
    s = neurov.load_scenario(FAULTS / f"{name}.toml")
    return neurov.simulate(s.replace(thruster_failures=[], sensor_faults=[], current_steps=[]))


def position_error(r: Result) -> np.ndarray:
    return np.linalg.norm(r.error[:, :3], axis=1)


def yaw_error(r: Result) -> np.ndarray:
    return np.abs(r.error[:, 5])


def wrench_limit() -> np.ndarray:
    """Largest |wrench| per DOF the NEROV thrusters can produce: |B| @ max(|min|, |max|)."""
    t = load_thrusters(preset_path("nerov"))
    assert t is not None
    reach = np.maximum(np.abs(t["min_thrust"]), np.abs(t["max_thrust"]))
    return np.abs(t["matrix"]) @ reach


def test_every_fault_has_a_scenario_file() -> None:
    assert sorted(p.stem for p in FAULTS.glob("*.toml")) == sorted(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_scenario_declares_its_fault(name: str) -> None:
    s = neurov.load_scenario(FAULTS / f"{name}.toml")
    bit, (start, end), _ = CASES[name]
    assert s.use_thrusters and s.controller.type == "nn" and s.controller.modification.name == "sigma"
    if bit in (1, 2, 4):
        kind = {1: "freeze", 2: "dropout", 4: "noise_burst"}[bit]
        assert [(f.kind.name, f.start, f.end) for f in s.sensor_faults] == [(kind, start, end)]
    elif bit == 8:
        assert [(f.time, f.efficiency) for f in s.thruster_failures] == [(start, 0.0), (end, 1.0)]
    else:
        assert [c.time for c in s.current_steps] == [start, end]


@pytest.mark.parametrize("name", sorted(CASES))
def test_tau_stays_finite_and_within_the_thrusters(name: str) -> None:
    r = run(name)
    assert not r.diverged
    assert len(r.t) == round(r.scenario.duration / r.scenario.dt) + 1
    for series in (r.tau_demanded, r.tau_applied, r.thrusts, r.eta, r.nu, r.s, r.adaptive_norm):
        assert np.all(np.isfinite(series))
    assert np.all(r.plant_status == 0)
    limit = wrench_limit()
    assert np.all(np.abs(r.tau_applied) <= limit * (1 + 1e-9)), np.abs(r.tau_applied).max(axis=0)
    t = load_thrusters(preset_path("nerov"))
    assert t is not None
    assert np.all(r.thrusts <= t["max_thrust"] + 1e-9) and np.all(r.thrusts >= t["min_thrust"] - 1e-9)


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_fault_is_reported_while_it_lasts(name: str) -> None:
    r = run(name)
    bit, (start, end), _ = CASES[name]
    during = (r.t >= start - 1e-9) & (r.t < end - 1e-9)
    if bit == 0:
        # A change in the sea is not a fault of the vehicle: nothing to report.
        assert np.all(r.faults == 0) and np.all(r.controller_status == 0)
        return
    expected = np.where(during, bit, 0)
    np.testing.assert_array_equal(r.faults, expected, err_msg=f"fault bits of {name}")
    ok = neurov.Status.ok.value
    if bit == 2:
        # A dropout is NaN: the controller refuses every step of it, and only those.
        refused = neurov.Status.non_finite_input.value
        np.testing.assert_array_equal(r.controller_status, np.where(during, refused, ok))
    else:
        assert np.all(r.controller_status == ok)


def test_dropout_holds_the_last_force_and_freezes_the_weights() -> None:
    r = run("sensor_dropout")
    assert r.scenario.refused_step_policy.name == "hold"
    _, (start, end), _ = CASES["sensor_dropout"]
    k = np.flatnonzero((r.t >= start - 1e-9) & (r.t < end - 1e-9))
    assert len(k) == 10
    last_good = k[0] - 1
    np.testing.assert_array_equal(r.tau_demanded[k], np.repeat(r.tau_demanded[[last_good]], len(k), axis=0))
    np.testing.assert_array_equal(r.adaptive_norm[k], np.full(len(k), r.adaptive_norm[last_good]))
    # The first step after the dropout is accepted and adapts again.
    assert r.controller_status[k[-1] + 1] == 0
    assert r.adaptive_norm[k[-1] + 1] != r.adaptive_norm[last_good]


@pytest.mark.parametrize("name", sorted(CASES))
def test_recovers_after_the_fault_clears(name: str) -> None:
    r, nominal = run(name), run_fault_free(name)
    _, (start, end), settle = CASES[name]
    # The fault-free run itself respects the bounds (else they mean nothing).
    quiet = nominal.t >= TRANSIENT_S
    assert position_error(nominal)[quiet].max() < POSITION_BOUND_M
    assert yaw_error(nominal)[quiet].max() < YAW_BOUND_RAD
    # Up to the fault the faulty run is the fault-free one.
    before = (r.t >= TRANSIENT_S) & (r.t < start)
    np.testing.assert_allclose(r.eta[r.t < start], nominal.eta[nominal.t < start], atol=1e-12)
    assert position_error(r)[before].max() < POSITION_BOUND_M
    # Recovered: from `settle` seconds after the fault to the end of the run.
    after = r.t >= end + settle
    assert np.count_nonzero(after) >= 50
    assert position_error(r)[after].max() < POSITION_BOUND_M, position_error(r)[after].max()
    assert yaw_error(r)[after].max() < YAW_BOUND_RAD, yaw_error(r)[after].max()


@pytest.mark.parametrize("name", ["thruster_failure", "sensor_freeze", "noise_burst", "current_step"])
def test_the_fault_really_hurts_while_it_lasts(name: str) -> None:
    r, nominal = run(name), run_fault_free(name)
    _, (start, end), settle = CASES[name]
    window = (r.t >= start) & (r.t < end + settle)
    worst, worst_nominal = position_error(r)[window].max(), position_error(nominal)[window].max()
    assert worst > 2.0 * worst_nominal, (worst, worst_nominal)


@pytest.mark.parametrize("name", sorted(CASES))
def test_weights_stay_within_the_sigma_modification_bound(name: str) -> None:
    """With W(0) = 0 the leaky update W+ = (1 - dt sigma gamma) W - dt gamma a g^T
    keeps ||W|| <= max_k ||a_k|| ||g_k|| / sigma, a = J^-1(eta) s and ||g|| <=
    sqrt(N) (each basis value is at most 1), checked with the run's own s and
    pose, so a leak that stopped working fails it."""
    r = run(name)
    spec = r.scenario.controller
    n_centres = spec.centres["n"]
    a = np.array([neurov.jacobian_inverse(eta) @ s for eta, s in zip(r.eta, r.s)])
    bound = np.linalg.norm(a, axis=1).max() * np.sqrt(n_centres) / spec.sigma_m
    assert r.adaptive_norm.max() <= bound
    # And in practice far below it: the fault-free run's ||W|| times a small factor.
    assert r.adaptive_norm.max() < 10.0 * run_fault_free(name).adaptive_norm.max()


def test_sigma_modification_bounds_the_weights_where_the_gradient_law_drifts() -> None:
    """A thruster that never comes back: the pure gradient law (the paper's)
    winds ||W|| up for as long as the fault lasts; sigma-modification and
    projection level off."""
    s = neurov.load_scenario(FAULTS / "thruster_failure.toml")
    permanent = s.replace(thruster_failures=s.thruster_failures[:1], duration=600.0)
    runs = {}
    for mod, extra in (("none", {}), ("sigma", {"sigma_m": 0.05}), ("projection", {"w_max": 10.0})):
        spec = s.controller.replace(modification=mod, sigma_m=extra.get("sigma_m", 0.0),
                                   w_max=extra.get("w_max", 0.0))
        r = neurov.simulate(permanent, spec)
        assert not r.diverged and np.all(np.isfinite(r.tau_applied))
        runs[mod] = r.adaptive_norm
    third = len(runs["none"]) // 3
    growth = {mod: w[-1] / w[2 * third] for mod, w in runs.items()}
    # Measured: none 874 at 600 s and still growing by 75 % over the last
    # 200 s; sigma 121, growing by 2.5 %; projection pinned at w_max.
    assert growth["none"] > 1.3
    assert growth["sigma"] < 1.1
    assert runs["projection"].max() <= 10.0 * (1 + 1e-12)
    assert runs["none"].max() > 5.0 * runs["sigma"].max()
