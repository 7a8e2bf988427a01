"""Soak: 24 simulated hours at 5 Hz (432,000 control steps) of the NN
controller with sigma-modification, through NEROV's thrusters, under a yaw
disturbance, a slowly turning current and measurement noise.

The loop runs in C++, an hour per call, the controller carried from one hour
to the next (its weights are the thing that could drift): so the process holds
one hour of results at a time and its resident set size must not grow from the
first hour to the last. Asserted: nothing non-finite, no refused step, ||W||
and the tracking error bounded and not creeping up from the first half of the
day to the second, the RSS flat. The figures are printed (pytest -s);
docs/reliability.md quotes them.

    pytest -m slow tests/python/test_soak.py -s
"""

from __future__ import annotations

import os
import resource
import time

import numpy as np
import pytest

import neurov
from neurov import _core
from neurov.config.scenario import Disturbance, Scenario
from neurov.laws.registry import build_controller
from neurov.running.plant import build_vehicle, simulation_config

HOURS = 24
HOUR_S = 3600.0
DT = 0.2


def soak_scenario() -> Scenario:
    """A 5 m circle every 150 s (24 laps an hour, so every hour starts where
    the last ended) with the heading swinging +-0.5 rad, at 2 m depth."""
    times, poses = neurov.config.trajectories.circle(radius=5.0, period=150.0, depth=2.0, turns=HOUR_S / 150.0,
                                              start=0.0, points_per_turn=72, face_travel=False)
    poses[:, 5] = 0.5 * np.sin(2 * np.pi * times / 150.0)
    base = neurov.load_scenario(
        os.path.join(os.path.dirname(__file__), "..", "..", "examples", "scenarios", "faults",
                     "thruster_failure.toml"))
    return base.replace(
        name="soak",
        duration=HOUR_S,
        thruster_failures=[],
        command=neurov.CommandSpec(type="waypoints", times=times, poses=poses),
        # The paper's Fig. 5 disturbance: 10 N m in yaw at 0.05 Hz (180 periods an hour).
        disturbances=[Disturbance(dof=5, amplitude=10.0, frequency=0.05)],
        # 0.1 m/s north plus 0.1 m/s swinging east-west every 10 minutes.
        current=np.array([0.1, 0.0, 0.0]),
        current_amplitude=np.array([0.0, 0.1, 0.0]),
        current_period=600.0,
        noise_eta=np.array([0.02, 0.02, 0.02, 0.002, 0.002, 0.005]),
        noise_nu=np.array([0.01, 0.01, 0.01, 0.002, 0.002, 0.002]),
    )


def rss_bytes() -> int:
    """Resident set size now (not the peak): /proc/self/statm, field 2, in pages."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def hour_config(s: Scenario, eta0: np.ndarray, nu0: np.ndarray, seed: int) -> _core.SimulationConfig:
    config = simulation_config(s)
    config.eta0 = eta0
    config.nu0 = nu0
    config.seed = seed
    return config


@pytest.mark.slow
@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs Linux /proc for the RSS")
def test_24_hours_nn_sigma_modification() -> None:
    s = soak_scenario()
    assert s.controller.type == "nn" and s.controller.modification.name == "sigma"
    assert s.use_thrusters
    vehicle = build_vehicle(s)
    controller = build_controller(s.controller, s)
    eta, nu = s.eta0.copy(), s.nu0.copy()
    per_hour: list[dict[str, float]] = []
    rss: list[int] = []
    steps = 0
    start, cpu_start = time.perf_counter(), time.process_time()
    for hour in range(HOURS):
        r = _core.run_closed_loop(vehicle, controller, hour_config(s, eta, nu, seed=hour))
        assert not r["diverged"], f"hour {hour}"
        for key in ("eta", "nu", "tau_demanded", "tau_applied", "s", "adaptive_norm", "thrusts"):
            assert np.all(np.isfinite(r[key])), f"{key} non-finite in hour {hour}"
        assert np.all(r["controller_status"] == 0) and np.all(r["plant_status"] == 0), f"hour {hour}"
        # Row 0 of an hour is the last row of the one before (same instant,
        # same state), so the hour adds len - 1 control steps.
        steps += len(r["t"]) - 1
        error = r["eta"] - r["eta_d"]
        skip = r["t"] >= (60.0 if hour == 0 else 0.0)  # the very first start-up only
        per_hour.append({
            "max_weight_norm": float(r["adaptive_norm"].max()),
            "max_position_error_m": float(np.linalg.norm(error[skip, :3], axis=1).max()),
            "max_yaw_error_rad": float(np.abs(error[skip, 5]).max()),
            "rms_position_error_m": float(np.sqrt(np.mean(np.sum(error[skip, :3] ** 2, axis=1)))),
            "max_abs_tau_applied": float(np.abs(r["tau_applied"]).max()),
        })
        eta, nu = r["eta"][-1].copy(), r["nu"][-1].copy()
        del r, error
        rss.append(rss_bytes())
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu_start

    w = np.array([h["max_weight_norm"] for h in per_hour])
    pos = np.array([h["max_position_error_m"] for h in per_hour])
    yaw = np.array([h["max_yaw_error_rad"] for h in per_hour])
    figures = {
        "steps": steps,
        "wall_s": round(wall, 1),
        "cpu_s": round(cpu, 1),
        "max_weight_norm": round(float(w.max()), 3),
        "max_position_error_m": round(float(pos.max()), 3),
        "max_yaw_error_rad": round(float(yaw.max()), 3),
        "rms_position_error_m_last_hour": round(per_hour[-1]["rms_position_error_m"], 4),
        "rss_mib_after_hour_1": round(rss[0] / 2**20, 1),
        "rss_mib_after_hour_24": round(rss[-1] / 2**20, 1),
        "peak_rss_mib": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1),
    }
    print("\nsoak:", figures)
    print("per hour max ||W||:", np.round(w, 3).tolist())
    print("per hour max position error [m]:", np.round(pos, 3).tolist())

    assert steps == HOURS * round(HOUR_S / DT) == 432_000
    # ||W|| bounded and not drifting: the second half of the day never goes
    # beyond the first half's maximum by more than 5 %.
    half = HOURS // 2
    assert np.all(np.isfinite(w))
    assert w[half:].max() <= 1.05 * w[1:half].max(), w.tolist()
    # Tracking error bounded, and no worse in the second half than the first.
    assert pos.max() < 0.5 and yaw.max() < 0.5, (pos.tolist(), yaw.tolist())
    assert pos[half:].max() <= 1.2 * pos[:half].max()
    # Memory flat: one hour's results are freed before the next hour runs, so
    # the RSS after hour 24 is that after hour 1 give or take allocator noise;
    # a leak of even 32 bytes a step would add 13 MiB.
    assert rss[-1] - rss[0] < 8 * 2**20, [round(x / 2**20, 1) for x in rss]
