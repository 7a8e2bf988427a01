"""The result of one closed-loop run: the time series as arrays, its
metrics, and its export (CSV, NPZ, pandas)."""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.scenario import Scenario

__all__ = ["Result"]

Array = NDArray[np.float64]

_SERIES = (
    "t", "eta", "nu", "eta_d", "eta_d_dot", "tau_demanded", "tau_applied", "disturbance", "s",
    "thrusts", "theta", "adaptive_norm", "controller_status", "plant_status", "faults",
)



@dataclass
class Result:
    """Time series of one closed-loop run; rows at t_k = k dt."""

    scenario: Scenario
    controller: str
    t: Array
    eta: Array
    nu: Array
    eta_d: Array
    eta_d_dot: Array
    tau_demanded: Array
    tau_applied: Array
    disturbance: Array
    s: Array
    thrusts: Array
    theta: Array
    adaptive_norm: Array
    controller_status: NDArray[np.uint8]
    plant_status: NDArray[np.uint8]
    faults: NDArray[np.uint8]
    diverged: bool
    wall_time: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def error(self) -> Array:
        """eta - eta_d, shape (K, 6)."""
        return self.eta - self.eta_d

    def metrics(self, after: float = 0.0) -> dict[str, Any]:
        """Tracking and effort metrics over t >= after (a transient to skip):
        RMS error per DOF and of the 3-D position, maximum errors, mean and
        maximum ``|tau|`` per DOF, control energy integral ``||tau|| dt``, integral
        absolute error per DOF. Non-finite or diverged runs give inf errors."""
        m = self.t >= after
        if not np.any(m):
            raise ValueError(f"argument 'after' = {after} leaves no samples (run ends at {self.t[-1] if len(self.t) else 0})")
        e = self.error[m]
        tau = self.tau_demanded[m]
        dt = self.scenario.dt
        pos = np.linalg.norm(e[:, :3], axis=1)
        names = ("x", "y", "z", "roll", "pitch", "yaw")
        out: dict[str, Any] = {
            "rmse_position_m": float(np.sqrt(np.mean(pos**2))),
            "max_position_error_m": float(np.max(pos)),
            "rmse_yaw_rad": float(np.sqrt(np.mean(e[:, 5] ** 2))),
            "max_yaw_error_rad": float(np.max(np.abs(e[:, 5]))),
            "rmse": {n: float(np.sqrt(np.mean(e[:, i] ** 2))) for i, n in enumerate(names)},
            "max_abs_error": {n: float(np.max(np.abs(e[:, i]))) for i, n in enumerate(names)},
            "iae": {n: float(np.sum(np.abs(e[:, i])) * dt) for i, n in enumerate(names)},
            "mean_abs_tau": float(np.mean(np.abs(tau))),
            "max_abs_tau": float(np.max(np.abs(tau))),
            "mean_abs_tau_dof": [float(x) for x in np.mean(np.abs(tau), axis=0)],
            "max_abs_tau_dof": [float(x) for x in np.max(np.abs(tau), axis=0)],
            "control_energy": float(np.sum(np.linalg.norm(tau, axis=1)) * dt),
            "final_adaptive_norm": float(self.adaptive_norm[-1]),
            "max_adaptive_norm": float(np.max(self.adaptive_norm)),
            "refused_steps": int(np.count_nonzero(self.controller_status[m])),
            "diverged": bool(self.diverged),
        }
        if self.diverged or not np.all(np.isfinite(e)):
            for k in ("rmse_position_m", "max_position_error_m", "rmse_yaw_rad", "max_yaw_error_rad"):
                out[k] = float("inf")
        return out

    def columns(self) -> dict[str, Array]:
        """Flat named columns (one per DOF, thruster and parameter)."""
        cols: dict[str, Array] = {"t": self.t}
        dof = ("x", "y", "z", "phi", "theta", "psi")
        body = ("u", "v", "w", "p", "q", "r")
        for name, arr, labels in (
            ("eta", self.eta, dof), ("nu", self.nu, body), ("eta_d", self.eta_d, dof),
            ("eta_d_dot", self.eta_d_dot, dof), ("tau_demanded", self.tau_demanded, body),
            ("tau_applied", self.tau_applied, body), ("disturbance", self.disturbance, body),
            ("s", self.s, dof),
        ):
            for i, lab in enumerate(labels):
                cols[f"{name}_{lab}"] = arr[:, i]
        for i in range(self.thrusts.shape[1]):
            cols[f"thrust_{i}"] = self.thrusts[:, i]
        for i, n in enumerate(_core.THETA_NAMES[: self.theta.shape[1]]):
            cols[f"theta[{n}]"] = self.theta[:, i]
        cols["adaptive_norm"] = self.adaptive_norm
        cols["controller_status"] = self.controller_status.astype(np.float64)
        cols["plant_status"] = self.plant_status.astype(np.float64)
        cols["faults"] = self.faults.astype(np.float64)
        return cols

    def to_pandas(self) -> Any:
        """The run as a tidy :class:`pandas.DataFrame`: one row per control
        step, indexed by time ``t`` [s]. Columns: the pose ``x, y, z, phi,
        theta, psi`` [m, rad]; the body velocities ``u, v, w, p, q, r``; the
        desired pose ``x_d`` ... ``psi_d`` and its rate ``x_d_dot`` ...;
        the demanded generalised force ``tau_X`` ... ``tau_N`` [N, N m] and the
        applied one ``tau_applied_X`` ...; the disturbance ``d_X`` ...; the
        sliding variable ``s_x`` ... ``s_psi``; the thrusts ``thrust_0`` ... [N]; the
        adapted parameters ``theta[m]`` ... (linear adaptive only); the
        ``adaptive_norm``; ``controller_status`` and ``plant_status`` as
        :class:`neurov.Status` names; and the fault flags ``fault_freeze``,
        ``fault_dropout``, ``fault_noise_burst``, ``fault_thruster`` and
        ``pitch_limited`` (bits 1, 2, 4, 8, 16 of :attr:`faults`)."""
        import pandas as pd

        pose, body = ("x", "y", "z", "phi", "theta", "psi"), ("u", "v", "w", "p", "q", "r")
        force = ("X", "Y", "Z", "K", "M", "N")
        cols: dict[str, Any] = {}
        for arr, names in ((self.eta, pose), (self.nu, body), (self.eta_d, [f"{n}_d" for n in pose]),
                           (self.eta_d_dot, [f"{n}_d_dot" for n in pose]),
                           (self.tau_demanded, [f"tau_{n}" for n in force]),
                           (self.tau_applied, [f"tau_applied_{n}" for n in force]),
                           (self.disturbance, [f"d_{n}" for n in force]),
                           (self.s, [f"s_{n}" for n in pose])):
            cols.update((n, arr[:, i]) for i, n in enumerate(names))
        cols.update((f"thrust_{i}", self.thrusts[:, i]) for i in range(self.thrusts.shape[1]))
        cols.update((f"theta[{n}]", self.theta[:, i])
                    for i, n in enumerate(_core.THETA_NAMES[: self.theta.shape[1]]))
        cols["adaptive_norm"] = self.adaptive_norm
        statuses = [s.name for s in sorted(_core.Status.__members__.values(), key=int)]
        for name in ("controller_status", "plant_status"):
            codes = getattr(self, name).astype(np.int64)
            cols[name] = pd.Categorical.from_codes(codes, categories=statuses)
        for bit, name in enumerate(("fault_freeze", "fault_dropout", "fault_noise_burst", "fault_thruster",
                                    "pitch_limited")):
            cols[name] = (self.faults & (1 << bit)) != 0
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def to_csv(self, path: str | Path) -> Path:
        """Writes every column to a CSV file with a header row."""
        path = Path(path)
        cols = self.columns()
        with path.open("w", newline="") as f:
            w = csv.writer(f)
            w.writerow(cols.keys())
            w.writerows(zip(*(c.tolist() for c in cols.values())))
        return path

    def to_npz(self, path: str | Path) -> Path:
        """Writes the arrays (and the scenario name and controller) to .npz."""
        path = Path(path)
        arrays = {k: getattr(self, k) for k in _SERIES}
        np.savez_compressed(path, scenario=self.scenario.name, controller=self.controller,
                            diverged=self.diverged, **arrays)
        return path

    def to_time_response(self) -> Any:
        """This run as ``control.TimeResponseData`` (needs ``neurov[control]``);
        see :func:`neurov.control.to_time_response`."""
        from neurov.control import to_time_response

        return to_time_response(self)

    def summary_json(self, after: float = 0.0) -> str:
        return json.dumps({"scenario": self.scenario.name, "controller": self.controller,
                           **self.metrics(after)}, indent=2)
