"""A run as a ROS 2 recording (MCAP, ``profile = ros2``) through the
official ``mcap`` and ``mcap-ros2-support`` packages, so that Foxglove,
PlotJuggler and ``ros2 bag`` open it.

The topics and frames are in docs/recordings.md; each message is stamped
(header and log time) with the row's ``t`` in integer nanoseconds. Besides
the messages the file holds the whole run, so that
:func:`neurov.recording.mcap_reader.read_mcap` gives it back exactly: the
attachment ``result.npz`` (the bytes of :meth:`neurov.Result.to_npz`), the
attachment ``scenario.toml`` (the scenario file's text, when the scenario
came from a file), and the metadata ``neurov`` (scenario name, controller,
source file, wall time, extra), ``scenario`` (its ``describe()``) and
``metrics``, each value a JSON text.
"""

from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurov.errors import RecordingError
from neurov.recording.frames import (BODY_FLU_FROM_FRD, WORLD_ENU_FROM_NED, body_to_flu, enu_quaternions,
                                     position_to_enu)
from neurov.recording.msgdefs import msgdef
from neurov.config.scenario import Scenario
from neurov import _core
from neurov._core import __version__

if TYPE_CHECKING:
    from neurov.results.timeseries import Result

__all__ = ["FRAMES", "TOPICS", "McapRecorder", "plain", "stamps", "write_mcap"]

FRAMES = {"world": "map", "world_ned": "map_ned", "body": "base_link", "body_frd": "base_link_frd"}
"""The frame ids: ENU world and FLU body (REP 103/105), and neurov's own
NED world and FRD body, fixed to them in /tf_static."""

TOPICS = {
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/odometry": "nav_msgs/msg/Odometry",
    "/odometry/estimate": "nav_msgs/msg/Odometry",
    "/desired_pose": "geometry_msgs/msg/PoseStamped",
    "/command_pose": "geometry_msgs/msg/PoseStamped",
    "/wrench/demanded": "geometry_msgs/msg/WrenchStamped",
    "/wrench/applied": "geometry_msgs/msg/WrenchStamped",
    "/imu": "sensor_msgs/msg/Imu",
    "/thrusts": "std_msgs/msg/Float64MultiArray",
}
"""Every topic a recording may hold and its type; ``/imu`` only for a run
whose scenario has an IMU and no estimator (then the attitude and rates the
controller was given are the IMU's latest readings), ``/thrusts`` only for
a run with thrusters."""

_ZEROS_36 = [0.0] * 36
_ZEROS_9 = [0.0] * 9
_NOT_GIVEN_9 = [-1.0] + [0.0] * 8  # sensor_msgs/Imu: element 0 = -1, no estimate of this quantity


def _vec(v: np.ndarray) -> dict[str, float]:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _quat(q: np.ndarray) -> dict[str, float]:
    return {"x": float(q[0]), "y": float(q[1]), "z": float(q[2]), "w": float(q[3])}


def _header(ns: int, frame: str) -> dict[str, Any]:
    return {"stamp": {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}, "frame_id": frame}


def stamps(t: np.ndarray) -> np.ndarray:
    """Each row's stamp: its ``t`` [s] in integer nanoseconds."""
    return np.rint(np.asarray(t, dtype=np.float64) * 1e9).astype(np.int64)


def _pose(eta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return position_to_enu(eta[:, :3]), enu_quaternions(eta[:, 3:])


def _has_imu(scenario: Scenario) -> bool:
    sim = scenario.simulation
    return sim.sensors.imu is not None and sim.estimator.type == _core.EstimatorType.none


class McapRecorder:
    """Writes a run's rows to an MCAP file as they come (:meth:`add`, a
    :class:`neurov.Result` of some rows at a time), then the whole run
    (:meth:`close`). :meth:`discard` closes what was written (a valid MCAP
    of the rows so far, without the run's attachments)."""

    def __init__(self, path: str | Path, scenario: Scenario, thrusters: int) -> None:
        try:  # here, not at the top: the API pages build without neurov[ros]
            from mcap_ros2.writer import Writer
        except ImportError:
            raise RecordingError("writing an MCAP recording needs mcap and mcap-ros2-support: "
                                 "pip install 'neurov[ros]' (or write CSV: --format csv)") from None

        self.path = Path(path)
        self.scenario = scenario
        self._file = self.path.open("wb")
        try:
            self._writer = Writer(self._file)
            self._schemas = {name: self._writer.register_msgdef(name, msgdef(name))
                             for name in sorted(set(TOPICS.values()))}
        except BaseException:
            self._file.close()
            raise
        self._imu = _has_imu(scenario)
        self._thrusters = thrusters
        self._static_written = False

    def _write(self, topic: str, message: dict[str, Any], ns: int) -> None:
        self._writer.write_message(topic, self._schemas[TOPICS[topic]], message, log_time=ns, publish_time=ns)

    def _transform(self, ns: int, parent: str, child: str, xyz: Any, q: Any) -> dict[str, Any]:
        return {"header": _header(ns, parent), "child_frame_id": child,
                "transform": {"translation": _vec(xyz), "rotation": _quat(q)}}

    def add(self, rows: Result) -> None:
        """Writes the messages of `rows`."""
        ns_all = stamps(rows.t)
        if not len(ns_all):
            return
        world, body = FRAMES["world"], FRAMES["body"]
        if not self._static_written:
            ns0 = int(ns_all[0])
            self._write("/tf_static", {"transforms": [
                self._transform(ns0, world, FRAMES["world_ned"], np.zeros(3), WORLD_ENU_FROM_NED),
                self._transform(ns0, body, FRAMES["body_frd"], np.zeros(3), BODY_FLU_FROM_FRD)]}, ns0)
            self._static_written = True
        p, q = _pose(rows.eta)
        p_est, q_est = _pose(rows.eta_estimate)
        p_d, q_d = _pose(rows.eta_d)
        # The command at each row, as the reference model was given it (the core's interpolation).
        command = self.scenario.simulation.command
        p_c, q_c = _pose(np.array([command.at(t) for t in rows.t.tolist()]).reshape(-1, 6))
        nu, nu_est = body_to_flu(rows.nu), body_to_flu(rows.nu_estimate)
        tau_d, tau_a = body_to_flu(rows.tau_demanded), body_to_flu(rows.tau_applied)
        for k, ns in enumerate(ns_all.tolist()):
            self._write("/tf", {"transforms": [self._transform(ns, world, body, p[k], q[k])]}, ns)
            for topic, pk, qk, vk in (("/odometry", p[k], q[k], nu[k]),
                                      ("/odometry/estimate", p_est[k], q_est[k], nu_est[k])):
                self._write(topic, {
                    "header": _header(ns, world), "child_frame_id": body,
                    "pose": {"pose": {"position": _vec(pk), "orientation": _quat(qk)}, "covariance": _ZEROS_36},
                    "twist": {"twist": {"linear": _vec(vk[:3]), "angular": _vec(vk[3:])},
                              "covariance": _ZEROS_36}}, ns)
            for topic, pk, qk in (("/desired_pose", p_d[k], q_d[k]), ("/command_pose", p_c[k], q_c[k])):
                self._write(topic, {"header": _header(ns, world),
                                    "pose": {"position": _vec(pk), "orientation": _quat(qk)}}, ns)
            for topic, wk in (("/wrench/demanded", tau_d[k]), ("/wrench/applied", tau_a[k])):
                self._write(topic, {"header": _header(ns, body),
                                    "wrench": {"force": _vec(wk[:3]), "torque": _vec(wk[3:])}}, ns)
            if self._imu:
                self._write("/imu", {
                    "header": _header(ns, body), "orientation": _quat(q_est[k]),
                    "orientation_covariance": _ZEROS_9, "angular_velocity": _vec(nu_est[k, 3:]),
                    "angular_velocity_covariance": _ZEROS_9, "linear_acceleration": _vec(np.zeros(3)),
                    "linear_acceleration_covariance": _NOT_GIVEN_9}, ns)
            if self._thrusters:
                self._write("/thrusts", {
                    "layout": {"dim": [{"label": "thruster", "size": self._thrusters, "stride": self._thrusters}],
                               "data_offset": 0},
                    "data": rows.thrusts[k].tolist()}, ns)

    def close(self, npz: bytes, metrics: dict[str, Any], result: Result) -> Path:
        """Writes the run (`npz`: the bytes of its result.npz), its scenario
        and `metrics`, and closes the file."""
        # A streamed run's drawn rows are thinned; result.npz holds every row.
        extra = {k: v for k, v in result.extra.items() if k != "plotted_rows_of"}
        try:
            self._writer.add_attachment(0, 0, "result.npz", "application/x-npz", npz)
            source = Path(self.scenario.source) if self.scenario.source else None
            if source is not None and source.is_file():
                self._writer.add_attachment(0, 0, "scenario.toml", "application/toml", source.read_bytes())
            self._writer.add_metadata("neurov", {
                "version": __version__, "scenario": self.scenario.name, "controller": result.controller,
                "source": str(source) if source is not None else "",
                "diverged": json.dumps(result.diverged), "wall_time": json.dumps(result.wall_time),
                "extra": json.dumps(plain(extra)), "frames": json.dumps(FRAMES)})
            self._writer.add_metadata("scenario", {"describe": json.dumps(plain(self.scenario.describe()))})
            self._writer.add_metadata("metrics", {k: json.dumps(plain(v)) for k, v in metrics.items()})
            self._writer.finish()
        finally:
            self._file.close()
        return self.path

    def discard(self) -> None:
        """Ends the file with the messages written so far."""
        try:
            self._writer.finish()
        finally:
            self._file.close()


def plain(value: Any) -> Any:
    """`value` as JSON can hold it: arrays as lists, tuples as lists, enums
    by name, inf and NaN as null (as metrics.json writes them)."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, np.generic):
        return plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return getattr(value, "name", str(value))


def write_mcap(result: Result, path: str | Path, metrics: dict[str, Any] | None = None) -> Path:
    """Writes `result` to the MCAP file `path` (see the module); `metrics`
    default to ``result.metrics()``. What :meth:`neurov.Result.to_mcap` does."""
    path = Path(path)
    metrics = result.metrics() if metrics is None else metrics
    recorder = McapRecorder(path, result.scenario, result.thrusts.shape[1])
    try:
        recorder.add(result)
        with tempfile.TemporaryDirectory(prefix=f".{path.name}.", dir=path.parent) as spool:
            npz = result.to_npz(Path(spool) / "result.npz").read_bytes()
    except BaseException:
        recorder.discard()
        path.unlink(missing_ok=True)
        raise
    return recorder.close(npz, metrics, result)
