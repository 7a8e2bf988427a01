"""A controller written in Python, run beside neurov's own.

An integral sliding-mode law on the nominal model, in numpy: with the earth-
frame error e = eta - eta_d and its integral z, the sliding variable

    s = e_dot + 2 Lambda e + Lambda^2 z

is driven to zero by the computed torque on the reference velocity nu_r
(J nu_r = eta_d_dot - 2 Lambda e - Lambda^2 z) plus a smoothed switching term,

    tau = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) - J^T (K_d s + K tanh(s / phi)).

M, C, D, g are the vehicle file's (not the perturbed plant's); the integral
takes up what the model gets wrong (a current, a heavier vehicle).

Run it:

    python examples/custom_controller.py            # one run and a small league table
    python examples/custom_controller.py --out league

The study names this file's ``make_controller`` by import path
(``custom_controller:make_controller``): every worker imports this module,
so this folder must be on PYTHONPATH (the script sets it for its workers).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import numpy as np

import neurov
from neurov.study import load_study, run_study
from neurov.study.spec import SCENARIO_DIR

HERE = Path(__file__).resolve().parent


class IntegralSlidingMode:
    """Integral sliding-mode control on a nominal vehicle model (see the module docstring)."""

    def __init__(self, vehicle: neurov.Vehicle, dt: float, lambda_: float = 0.5,
                 kd: Any = (200, 200, 200, 50, 50, 50), k: Any = (20, 20, 20, 5, 5, 5),
                 phi: float = 0.1, integral_limit: float = 2.0) -> None:
        self.vehicle, self.dt = vehicle, dt
        self.lam = np.full(6, lambda_)
        self.kd, self.k, self.phi = np.asarray(kd, float), np.asarray(k, float), phi
        self.integral_limit = integral_limit
        self.reset()

    def reset(self) -> None:
        self.z = np.zeros(6)
        self.s = np.zeros(6)

    def step(self, eta: Any, nu: Any, eta_d: Any, eta_d_dot: Any, eta_d_ddot: Any) -> Any:
        if not (np.isfinite(eta).all() and np.isfinite(nu).all()):
            # A dropout: refuse the step (the scenario's policy holds or zeroes the force).
            raise ValueError("measurement is not finite")
        lam, v = self.lam, self.vehicle
        J = neurov.jacobian(eta)
        e = eta - eta_d
        e_dot = J @ nu - eta_d_dot
        z = np.clip(self.z + e * self.dt, -self.integral_limit, self.integral_limit)
        s = e_dot + 2 * lam * e + lam**2 * z
        eta_r_dot = eta_d_dot - 2 * lam * e - lam**2 * z
        eta_r_ddot = eta_d_ddot - 2 * lam * e_dot - lam**2 * e
        nu_r = np.linalg.solve(J, eta_r_dot)
        nu_r_dot = np.linalg.solve(J, eta_r_ddot - neurov.jacobian_dot(eta, nu) @ nu_r)
        tau = (v.mass_matrix() @ nu_r_dot + (v.coriolis(nu) + v.damping(nu)) @ nu_r + v.restoring(eta)
               - J.T @ (self.kd * s + self.k * np.tanh(s / self.phi)))
        self.z, self.s = z, s  # only an accepted step moves the integrator
        return tau


def make_controller(scenario: neurov.Scenario) -> IntegralSlidingMode:
    """The study's factory: the controller for `scenario`'s nominal vehicle and control period."""
    return IntegralSlidingMode(neurov.Vehicle.from_file(scenario.vehicle_path()), scenario.dt)


STUDY = """
name = "custom_controller"
description = "An integral sliding-mode law written in Python beside the built-in controllers"
seed = 11
samples = 4
after = 10.0
scenarios = ["nerov_depth_step", "nerov_heading_step_disturbed", "nerov_square_disturbed"]

[ranking]
metric = "rmse_position_m"
also_show = ["rmse_yaw_rad", "mean_abs_tau"]

[controllers.mine]
factory = "custom_controller:make_controller"
label = "integral sliding mode (Python)"

[controllers.smc]
type = "smc"
label = "sliding mode (built in)"
lambda = 0.5
kd = [200, 200, 200, 50, 50, 50]
k = [50, 50, 50, 10, 10, 10]
phi = 0.1

[controllers.pd]
type = "pd"
label = "PD"
kp = [100, 100, 100, 25, 25, 25]
kd = [200, 200, 200, 50, 50, 50]

[[perturbations]]
parameter = "mass"
relative = 0.2

[[perturbations]]
parameter = "linear_damping"
relative = 0.3
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, help="folder for the study's table (default: a temporary one)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()

    scenario = neurov.load_scenario(SCENARIO_DIR / "nerov_square_disturbed.toml")
    result = neurov.simulate(scenario, make_controller(scenario), label="integral sliding mode")
    m = result.metrics()
    print(f"{scenario.name}: RMS position error {m['rmse_position_m']:.3f} m, "
          f"RMS yaw error {math.degrees(m['rmse_yaw_rad']):.3f} deg, refused steps {m['refused_steps']}, "
          f"{result.wall_time * 1e3:.0f} ms for {len(result.t)} steps")

    # The workers import this module by name: put its folder on their path.
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(HERE), os.environ.get("PYTHONPATH")]))
    sys.path.insert(0, str(HERE))
    with tempfile.TemporaryDirectory() as tmp:
        study_file = Path(tmp) / "custom_controller.toml"
        study_file.write_text(STUDY)
        out = run_study(load_study(study_file), args.out or Path(tmp) / "out", workers=args.workers,
                        executor="processes", plots=False, progress=False)
        print(out.league.read_text())


if __name__ == "__main__":
    main()
