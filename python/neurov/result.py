"""The result of one closed-loop run: the time series as arrays, its
metrics, and its export (CSV, NPZ, pandas)."""

from __future__ import annotations

import csv
import json
import math
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.scenario import Scenario

__all__ = ["SERIES", "TRANSIENT_S", "Result", "metrics_start"]

Array = NDArray[np.float64]

TRANSIENT_S = 10.0
"""The start-up transient the metrics skip [s]: the weights start from zero
and the reference model catches up with the first command (the shipped
commands start moving within 5 s). A fixed time, so that a 24-hour run and a
1-minute run are judged on the same footing."""


CSV_BLOCK_ROWS = 20_000
"""Rows per block written by :meth:`Result.to_csv`."""


def metrics_start(duration: float) -> float:
    """Where the metrics window starts for a run of `duration` seconds:
    :data:`TRANSIENT_S`, or half the run if it is shorter than twice that.
    The one window of ``neurov run``, ``neurov paper``, :meth:`Result.metrics`
    and the run plots (studies set their own ``after``)."""
    return min(TRANSIENT_S, 0.5 * duration)


def _finite_or_inf(x: Any) -> float:
    """A metric as a float; NaN (from inf - inf in a diverged run) as inf."""
    x = float(x)
    return x if math.isfinite(x) else math.inf


SERIES = (
    "t", "eta", "nu", "eta_d", "eta_d_dot", "tau_demanded", "tau_applied", "disturbance", "s",
    "thrusts", "theta", "adaptive_norm", "controller_status", "plant_status", "faults",
    "current", "wave_velocity", "wave_elevation", "payload_mass", "eta_estimate", "nu_estimate",
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
    current: Array  #: (N, 3) NED current at the vehicle [m/s]
    wave_velocity: Array  #: (N, 3) NED orbital velocity at the vehicle [m/s]
    wave_elevation: Array  #: (N,) surface elevation above the vehicle [m]
    payload_mass: Array  #: (N,) payload mass in effect [kg]
    eta_estimate: Array  #: (N, 6) the pose the controller was given (measured or estimated)
    nu_estimate: Array  #: (N, 6) the body velocity the controller was given
    diverged: bool
    wall_time: float = 0.0
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def error(self) -> Array:
        """eta - eta_d, shape (K, 6)."""
        return self.eta - self.eta_d

    def metrics(self, after: float | None = None) -> dict[str, Any]:
        """Tracking and effort metrics over t >= `after` [s]: RMS error per DOF
        and of the 3-D position, maximum errors, mean and maximum ``|tau|`` per
        DOF, control energy integral ``||tau|| dt``, integral absolute error
        per DOF. `after` defaults to :func:`metrics_start` (the one window
        ``neurov run``, ``neurov paper`` and the run plots use).

        ``window_start_s`` and ``window_end_s`` say what the numbers cover.
        A diverged run (``diverged`` true, ``diverged_at_s`` its last row)
        gets its metrics over what was simulated: from `after` if rows exist
        there, else over every row; non-finite values give inf."""
        if after is None:
            after = metrics_start(self.scenario.duration)
        if not math.isfinite(after):
            raise ValueError(f"argument 'after' must be a finite time [s], got {after}")
        # t is increasing, so the window is a slice (views, no copies of a long run).
        first = int(np.searchsorted(self.t, after, side="left"))
        if first == len(self.t):
            if not (self.diverged and len(self.t)):
                raise ValueError(f"argument 'after' = {after} leaves no samples "
                                 f"(run ends at {self.t[-1] if len(self.t) else 0})")
            first = 0
        m = slice(first, None)
        e = self.eta[m] - self.eta_d[m]
        tau = self.tau_demanded[m]
        dt = self.scenario.dt
        names = ("x", "y", "z", "roll", "pitch", "yaw")
        with np.errstate(over="ignore", invalid="ignore"):
            pos = np.linalg.norm(e[:, :3], axis=1)
            out: dict[str, Any] = {
                "window_start_s": float(self.t[m][0]),
                "window_end_s": float(self.t[m][-1]),
                "rmse_position_m": _finite_or_inf(np.sqrt(np.mean(pos**2))),
                "max_position_error_m": _finite_or_inf(np.max(pos)),
                "rmse_yaw_rad": _finite_or_inf(np.sqrt(np.mean(e[:, 5] ** 2))),
                "max_yaw_error_rad": _finite_or_inf(np.max(np.abs(e[:, 5]))),
                "rmse": {n: _finite_or_inf(np.sqrt(np.mean(e[:, i] ** 2))) for i, n in enumerate(names)},
                "max_abs_error": {n: _finite_or_inf(np.max(np.abs(e[:, i]))) for i, n in enumerate(names)},
                "iae": {n: _finite_or_inf(np.sum(np.abs(e[:, i])) * dt) for i, n in enumerate(names)},
                "mean_abs_tau": _finite_or_inf(np.mean(np.abs(tau))),
                "max_abs_tau": _finite_or_inf(np.max(np.abs(tau))),
                "mean_abs_tau_dof": [_finite_or_inf(x) for x in np.mean(np.abs(tau), axis=0)],
                "max_abs_tau_dof": [_finite_or_inf(x) for x in np.max(np.abs(tau), axis=0)],
                "control_energy": _finite_or_inf(np.sum(np.linalg.norm(tau, axis=1)) * dt),
                "final_adaptive_norm": _finite_or_inf(self.adaptive_norm[-1]),
                "max_adaptive_norm": _finite_or_inf(np.max(self.adaptive_norm)),
                "refused_steps": int(np.count_nonzero(self.controller_status[m])),
                "diverged": bool(self.diverged),
                "diverged_at_s": float(self.t[-1]) if self.diverged and len(self.t) else None,
            }
        return out

    def divergence_message(self) -> str:
        """One line saying when and how the run diverged ('' if it did not)."""
        if not self.diverged:
            return ""
        if not len(self.t):
            return "diverged before the first step"
        plant, ctrl = (_core.Status(int(a[-1])).name for a in (self.plant_status, self.controller_status))
        return (f"diverged at t = {self.t[-1]:g} s: plant status {plant}, controller status {ctrl}; "
                f"{len(self.t)} of {round(self.scenario.duration / self.scenario.dt) + 1} rows simulated")

    def columns(self) -> dict[str, Array]:
        """Flat named columns (one per DOF, thruster and parameter)."""
        cols: dict[str, Array] = {"t": self.t}
        dof = ("x", "y", "z", "phi", "theta", "psi")
        body = ("u", "v", "w", "p", "q", "r")
        for name, arr, labels in (
            ("eta", self.eta, dof), ("nu", self.nu, body), ("eta_d", self.eta_d, dof),
            ("eta_d_dot", self.eta_d_dot, dof), ("tau_demanded", self.tau_demanded, body),
            ("tau_applied", self.tau_applied, body), ("disturbance", self.disturbance, body),
            ("s", self.s, dof), ("eta_estimate", self.eta_estimate, dof),
            ("nu_estimate", self.nu_estimate, body),
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
        for name, arr in (("current", self.current), ("wave_velocity", self.wave_velocity)):
            cols.update((f"{name}_{n}", arr[:, i]) for i, n in enumerate("NED"))
        cols["wave_elevation"] = self.wave_elevation
        cols["payload_mass"] = self.payload_mass
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
        ``pitch_limited`` and ``shallow`` (bits 1, 2, 4, 8, 16, 32 of :attr:`faults`);
        the sea at the vehicle ``current_N, current_E, current_D``,
        ``wave_velocity_N`` ... [m/s], ``wave_elevation`` [m], the
        ``payload_mass`` in effect [kg], and what the controller was given
        (the measurement or the estimate) ``x_est`` ... ``psi_est``,
        ``u_est`` ... ``r_est``."""
        import pandas as pd

        pose, body = ("x", "y", "z", "phi", "theta", "psi"), ("u", "v", "w", "p", "q", "r")
        force = ("X", "Y", "Z", "K", "M", "N")
        cols: dict[str, Any] = {}
        for arr, names in ((self.eta, pose), (self.nu, body), (self.eta_d, [f"{n}_d" for n in pose]),
                           (self.eta_d_dot, [f"{n}_d_dot" for n in pose]),
                           (self.tau_demanded, [f"tau_{n}" for n in force]),
                           (self.tau_applied, [f"tau_applied_{n}" for n in force]),
                           (self.disturbance, [f"d_{n}" for n in force]),
                           (self.s, [f"s_{n}" for n in pose]),
                           (self.eta_estimate, [f"{n}_est" for n in pose]),
                           (self.nu_estimate, [f"{n}_est" for n in body])):
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
                                    "pitch_limited", "shallow")):
            cols[name] = (self.faults & (1 << bit)) != 0
        for name, arr in (("current", self.current), ("wave_velocity", self.wave_velocity)):
            cols.update((f"{name}_{n}", arr[:, i]) for i, n in enumerate("NED"))
        cols["wave_elevation"] = self.wave_elevation
        cols["payload_mass"] = self.payload_mass
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def to_csv(self, path: str | Path, quiet: bool = True) -> Path:
        """Writes every column of :meth:`columns` to a CSV file with a header
        row, each number as the shortest text that reads back to the same
        float64. Written in blocks of :data:`CSV_BLOCK_ROWS` rows (a 24-hour
        run does not need its whole text in memory), through pyarrow's C++
        writer when pyarrow is installed (``neurov[parquet]``; about four times
        faster), else Python's csv module; unless `quiet`, a progress bar."""
        from neurov.progress import progress_bar

        path = Path(path)
        cols = self.columns()
        rows = len(self.t)
        with progress_bar(rows, path.name, unit="row", quiet=quiet) as bar:
            try:
                import pyarrow as pa
                import pyarrow.csv as pacsv
            except ImportError:
                with path.open("w", newline="") as f:
                    w = csv.writer(f)
                    w.writerow(cols.keys())
                    for start in range(0, rows, CSV_BLOCK_ROWS):
                        block = slice(start, start + CSV_BLOCK_ROWS)
                        w.writerows(zip(*(c[block].tolist() for c in cols.values())))
                        bar.update(len(self.t[block]))
                return path
            schema = pa.schema([(name, pa.float64()) for name in cols])
            options = pacsv.WriteOptions(quoting_style="none")
            with pacsv.CSVWriter(str(path), schema, write_options=options) as writer:
                for start in range(0, rows, CSV_BLOCK_ROWS):
                    block = slice(start, start + CSV_BLOCK_ROWS)
                    writer.write_batch(pa.record_batch([c[block] for c in cols.values()], schema=schema))
                    bar.update(len(self.t[block]))
        return path

    def to_npz(self, path: str | Path, quiet: bool = True) -> Path:
        """Writes the arrays (and the scenario name, the controller and
        whether it diverged) to a compressed .npz, array by array (no copy of
        the run in memory); unless `quiet`, a progress bar."""
        from neurov.progress import progress_bar

        path = Path(path)
        arrays: dict[str, Any] = {"scenario": np.array(self.scenario.name),
                                  "controller": np.array(self.controller),
                                  "diverged": np.array(self.diverged)}
        arrays.update((k, getattr(self, k)) for k in SERIES)
        # Level 1: the float series barely compress more at numpy's level 6,
        # which takes several times longer.
        with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, compresslevel=1,
                             allowZip64=True) as zf, \
                progress_bar(len(arrays), path.name, unit="array", quiet=quiet) as bar:
            for name, value in arrays.items():
                with zf.open(f"{name}.npy", "w", force_zip64=True) as f:
                    np.lib.format.write_array(f, np.asanyarray(value), allow_pickle=False)
                bar.update(1)
        return path

    def to_time_response(self) -> Any:
        """This run as ``control.TimeResponseData`` (needs ``neurov[control]``);
        see :func:`neurov.control.to_time_response`."""
        from neurov.control import to_time_response

        return to_time_response(self)

    def summary_json(self, after: float | None = None) -> str:
        return json.dumps({"scenario": self.scenario.name, "controller": self.controller,
                           **self.metrics(after)}, indent=2)
