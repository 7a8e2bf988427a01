"""Result.to_pandas: one row per control step, indexed by time, with named
columns that hold exactly the Result's arrays."""

from __future__ import annotations

import numpy as np

import neurov
import pandas as pd
import pytest

from neurov import THETA_NAMES, Status
from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario, SensorFault, ThrusterFailure
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate

SCENARIO = Scenario(
    name="pandas_square", duration=12.0, use_thrusters=True,
    command=CommandSpec(type="square", args={"side": 3.0, "start": 1.0}),
    controller=ControllerSpec(type="linear", theta0="true"),
    sensor_faults=[SensorFault(kind=neurov.SensorFaultKind.freeze, start=4.0, end=6.0)],
    thruster_failures=[ThrusterFailure(index=2, efficiency=0.0, time=8.0)],
)


@pytest.fixture(scope="module")
def run() -> Result:
    return simulate(SCENARIO)


def test_one_row_per_step_indexed_by_time(run: Result) -> None:
    df = run.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert len(df) == len(run.t) == round(SCENARIO.duration / SCENARIO.dt) + 1
    assert df.index.name == "t"
    np.testing.assert_array_equal(df.index.to_numpy(), run.t)


def test_columns_hold_the_result_arrays(run: Result) -> None:
    df = run.to_pandas()
    pose, body, force = ("x", "y", "z", "phi", "theta", "psi"), ("u", "v", "w", "p", "q", "r"), "XYZKMN"
    blocks = {
        tuple(f"eta_{n}" for n in pose): run.eta,
        tuple(f"nu_{n}" for n in body): run.nu,
        tuple(f"eta_d_{n}" for n in pose): run.eta_d,
        tuple(f"eta_d_dot_{n}" for n in pose): run.eta_d_dot,
        tuple(f"tau_demanded_{n}" for n in force): run.tau_demanded,
        tuple(f"tau_applied_{n}" for n in force): run.tau_applied,
        tuple(f"disturbance_{n}" for n in force): run.disturbance,
        tuple(f"s_{n}" for n in pose): run.s,
        tuple(f"eta_estimate_{n}" for n in pose): run.eta_estimate,
        tuple(f"nu_estimate_{n}" for n in body): run.nu_estimate,
        ("current_N", "current_E", "current_D"): run.current,
    }
    for names, arr in blocks.items():
        np.testing.assert_array_equal(df[list(names)].to_numpy(), arr)
    n = run.thrusts.shape[1]
    assert n == 6
    np.testing.assert_array_equal(df[[f"thrusts_{i}" for i in range(n)]].to_numpy(), run.thrusts)
    np.testing.assert_array_equal(df[[f"theta_{k}" for k in THETA_NAMES]].to_numpy(), run.theta)
    np.testing.assert_array_equal(df["adaptive_norm"].to_numpy(), run.adaptive_norm)


def test_statuses_are_names_and_faults_are_bits(run: Result) -> None:
    df = run.to_pandas()
    for col in ("controller_status", "plant_status"):
        assert [Status(int(c)).name for c in getattr(run, col)] == df[col].astype(str).tolist()
    assert set(df["plant_status"].astype(str)) == {"ok"}
    t = df.index.to_numpy()
    faults = df["faults"].to_numpy()
    assert faults.dtype == np.uint8
    np.testing.assert_array_equal(faults, run.faults)
    # The freeze (bit 1) covers [4, 6); the thruster (bit 8) is out from 8 s on.
    np.testing.assert_array_equal(faults & 1 != 0, (t >= 4.0 - 1e-9) & (t < 6.0 - 1e-9))
    np.testing.assert_array_equal(faults & 8 != 0, t >= 8.0 - 1e-9)
    assert not np.any(faults & (2 | 4))
