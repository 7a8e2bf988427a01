"""The result of one closed-loop run: the time series as arrays, its
metrics, and its export (CSV, NPZ, pandas, MCAP)."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.metrics import TRANSIENT_S, MetricsWindow, metrics_start
from neurov.scenario import Scenario

__all__ = ["SERIES", "TRANSIENT_S", "Result", "metrics_start"]

Array = NDArray[np.float64]

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

    @property
    def met_sea(self) -> bool:
        """True if the run met a current, waves or a payload change."""
        return bool(np.any(self.current) or np.any(self.wave_elevation) or np.any(self.payload_mass))

    def metrics(self, after: float | None = None) -> dict[str, Any]:
        """Tracking and effort metrics over t >= `after` [s]: RMS error per DOF
        and of the 3-D position, maximum errors, mean and maximum ``|tau|`` per
        DOF, control energy integral ``||tau|| dt``, integral absolute error
        per DOF. `after` defaults to :func:`metrics_start` (the one window
        ``neurov run``, ``neurov paper`` and the run plots use).

        ``window_start_s`` and ``window_end_s`` say what the numbers cover;
        ``refused_steps`` counts the refused controller steps of the whole
        run, ``refused_steps_in_window`` those in the window.
        A diverged run (``diverged`` true, ``diverged_at_s`` its last row)
        gets its metrics over what was simulated: from `after` if rows exist
        there, else over every row; non-finite values give inf."""
        window = MetricsWindow(self.scenario.duration, self.scenario.dt, after)
        window.add(self)
        return window.value()

    @property
    def first_refusal(self) -> str | None:
        """The first refused controller step, ``"t = 5 s, invalid_argument:
        step raised TypeError: ..."`` (a Python controller's message; a
        compiled controller's status only), or None if no step was refused."""
        errors = self.extra.get("controller_errors") or {}
        if errors:
            status, first = min(errors.items(), key=lambda kv: kv[1]["first_t"])
            return f"t = {first['first_t']:g} s, {status}: {first['first']}"
        # A streamed run's drawn rows are thinned: its first refused row is kept in extra.
        first = self.extra.get("first_refused")
        if first is None:
            bad = np.flatnonzero(self.controller_status)
            if not len(bad):
                return None
            first = (float(self.t[bad[0]]), int(self.controller_status[bad[0]]))
        return f"t = {first[0]:g} s, {_core.Status(first[1]).name}"

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
        float64, in blocks (see :class:`neurov.export.CsvWriter`: pyarrow's
        C++ writer when installed, about four times faster); unless `quiet`,
        a progress bar."""
        from neurov.export import CsvWriter
        from neurov.progress import progress_bar

        cols = self.columns()
        with progress_bar(len(self.t), Path(path).name, unit="row", quiet=quiet) as bar, \
                CsvWriter(path, list(cols)) as writer:
            writer.write(cols, progress=bar)
        return Path(path)

    def npz_arrays(self) -> dict[str, Any]:
        """What :meth:`to_npz` writes besides the series: the scenario's name,
        the controller and whether the run diverged."""
        return {"scenario": np.array(self.scenario.name), "controller": np.array(self.controller),
                "diverged": np.array(self.diverged)}

    def to_npz(self, path: str | Path, quiet: bool = True) -> Path:
        """Writes the arrays of :data:`SERIES` (and :meth:`npz_arrays`) to a
        compressed .npz, array by array (see :class:`neurov.export.NpzWriter`);
        unless `quiet`, a progress bar."""
        from neurov.export import NpzWriter
        from neurov.progress import progress_bar

        writer = NpzWriter(path)
        try:
            for name, value in self.npz_arrays().items():
                writer.set(name, value)
            writer.append({k: getattr(self, k) for k in SERIES})
        except BaseException:
            writer.discard()
            raise
        with progress_bar(writer.count, Path(path).name, unit="array", quiet=quiet) as bar:
            return writer.close(progress=bar)

    def to_mcap(self, path: str | Path) -> Path:
        """Writes this run as a ROS 2 recording (MCAP, for Foxglove,
        PlotJuggler, ``ros2 bag``; needs ``neurov[ros]``): odometry, desired
        pose, wrenches and /tf in the ENU/FLU frames of REP 103 (docs/recordings.md),
        and the whole run, which :func:`neurov.recording.mcap_reader.read_mcap`
        reads back; see :func:`neurov.recording.mcap_writer.write_mcap`."""
        from neurov.recording.mcap_writer import write_mcap

        return write_mcap(self, path)

    def to_time_response(self) -> Any:
        """This run as ``control.TimeResponseData`` (needs ``neurov[control]``);
        see :func:`neurov.control.to_time_response`."""
        from neurov.control import to_time_response

        return to_time_response(self)

    def view(self, *others: Result, **options: Any) -> Any:
        """The 3-D replay of this run, and of `others` on the same path to
        compare them (needs ``neurov[view]``: plotly): a
        :class:`neurov.replay.Replay`, which Jupyter shows inline and
        ``.write_html(path)`` writes as one file that opens offline.
        `options`: those of :func:`neurov.replay.replay` (``labels``,
        ``title``, ``max_frames``)."""
        from neurov.replay import replay

        return replay([self, *others], **options)

    def summary_json(self, after: float | None = None) -> str:
        return json.dumps({"scenario": self.scenario.name, "controller": self.controller,
                           **self.metrics(after)}, indent=2)
