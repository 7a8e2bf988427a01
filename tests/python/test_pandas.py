"""Result.to_pandas: one row per control step, indexed by time, with named
columns that hold exactly the Result's arrays."""

from __future__ import annotations

import numpy as np

import neurov
import pandas as pd
import pytest

from neurov import THETA_NAMES, Status
from neurov.scenario import CommandSpec, ControllerSpec, Scenario, SensorFault, ThrusterFailure
from neurov.simulation import Result, simulate

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
    blocks = {
        ("x", "y", "z", "phi", "theta", "psi"): run.eta,
        ("u", "v", "w", "p", "q", "r"): run.nu,
        ("x_d", "y_d", "z_d", "phi_d", "theta_d", "psi_d"): run.eta_d,
        ("x_d_dot", "y_d_dot", "z_d_dot", "phi_d_dot", "theta_d_dot", "psi_d_dot"): run.eta_d_dot,
        ("tau_X", "tau_Y", "tau_Z", "tau_K", "tau_M", "tau_N"): run.tau_demanded,
        ("tau_applied_X", "tau_applied_Y", "tau_applied_Z", "tau_applied_K", "tau_applied_M",
         "tau_applied_N"): run.tau_applied,
        ("d_X", "d_Y", "d_Z", "d_K", "d_M", "d_N"): run.disturbance,
        ("s_x", "s_y", "s_z", "s_phi", "s_theta", "s_psi"): run.s,
    }
    for names, arr in blocks.items():
        np.testing.assert_array_equal(df[list(names)].to_numpy(), arr)
    n = run.thrusts.shape[1]
    assert n == 6
    np.testing.assert_array_equal(df[[f"thrust_{i}" for i in range(n)]].to_numpy(), run.thrusts)
    np.testing.assert_array_equal(df[[f"theta[{k}]" for k in THETA_NAMES]].to_numpy(), run.theta)
    np.testing.assert_array_equal(df["adaptive_norm"].to_numpy(), run.adaptive_norm)


def test_statuses_are_names_and_faults_are_flags(run: Result) -> None:
    df = run.to_pandas()
    for col in ("controller_status", "plant_status"):
        assert [Status(int(c)).name for c in getattr(run, col)] == df[col].astype(str).tolist()
    assert set(df["plant_status"].astype(str)) == {"ok"}
    t = df.index.to_numpy()
    # The freeze covers [4, 6); the thruster is out from 8 s on.
    np.testing.assert_array_equal(df["fault_freeze"].to_numpy(), (t >= 4.0 - 1e-9) & (t < 6.0 - 1e-9))
    np.testing.assert_array_equal(df["fault_thruster"].to_numpy(), t >= 8.0 - 1e-9)
    assert not df["fault_dropout"].any() and not df["fault_noise_burst"].any()
    for bit, col in enumerate(("fault_freeze", "fault_dropout", "fault_noise_burst", "fault_thruster",
                               "pitch_limited")):
        np.testing.assert_array_equal(df[col].to_numpy(), (run.faults >> bit) & 1 == 1)
