"""ROS 1 and ROS 2 bags through ``rosbags`` (no ROS installation), from
the topics the mapping file names:

- ``odometry`` (``nav_msgs/msg/Odometry``, required): the time base (its
  header stamps, integer nanoseconds), the position and the body twist (a
  DVL's velocity, as a vehicle's odometry gives it);
- ``imu`` (``sensor_msgs/msg/Imu``, optional): the attitude (its orientation)
  and the body rates (its angular velocity) instead of the odometry's;
- ``pressure`` (``sensor_msgs/msg/FluidPressure``, optional): the depth
  instead of the odometry's z, depth = (p - surface_pressure) / (rho g) with
  the mapping's ``water_density`` (required with it) and ``surface_pressure``
  (default 101325 Pa), g = 9.80665 m/s^2;
- the force, one of: ``wrench`` (``geometry_msgs/msg/WrenchStamped``, the
  body wrench) or ``thrusters`` (``std_msgs/msg/Float64MultiArray``, or an
  integer array such as ``UInt16MultiArray`` for PWM; one command per
  thruster, stamped by the bag's receive time as it has no header): ``thruster_command = "N"`` (thrusts, through the template's
  configuration matrix) or ``"pwm"`` (through its thruster curves, as a
  tlog's PWM).

Every signal but the odometry is held from its latest message onto the time
base (the zero-order hold of a command) and cut where older than the
mapping's ``max_age``. An irregular time base (an unstamped array topic's
receive times) is resampled by the CSV reader's rule (the mapping's
``resample``, :func:`neurov.identification.csv_mapping.resample_by_mapping`).
The mapping file (see
:mod:`neurov.identification.mapping`)::

    format = "rosbag"
    body_frame = "flu"          # REP 103: base_link forward-left-up
    world_frame = "enu"         # odom / map east-north-up
    water_density = 997.0       # kg/m^3, with a pressure topic
    thruster_command = "N"      # N or pwm, with a thrusters topic
    [topics]
    odometry = "/rov/odometry"
    imu = "/rov/imu"
    pressure = "/rov/pressure"
    thrusters = "/rov/thruster_commands"   # or wrench = "/rov/thrust_wrench"
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.alignment import hold
from neurov.identification.csv_mapping import resample_by_mapping
from neurov.identification.errors import LogError
from neurov.identification.log import Log, fill_absent, make_log
from neurov.identification.mapping import Mapping, to_neurov_frames
from neurov.identification.ros_arrays import ARRAY_TYPES, array_rows, array_specs
from neurov.identification.tlog_log import pwm_force
from neurov.errors import RecordingError
from neurov.recording.bag_topics import stamp_ns, topic_messages

__all__ = ["read_rosbag", "euler_from_quaternion", "stamp_ns", "topic_messages"]

Array = NDArray[np.float64]
# PWM in microseconds is often published as integers (a PCA9685 driver's
# UInt16MultiArray): accepted for thruster commands, not for [[arrays]].
INTEGER_ARRAY_TYPES = tuple(f"std_msgs/msg/{k}MultiArray" for k in
                            ("UInt16", "Int16", "UInt32", "Int32", "UInt64", "Int64"))
_TOPICS: dict[str, str | tuple[str, ...]] = {"odometry": "nav_msgs/msg/Odometry", "wrench": "geometry_msgs/msg/WrenchStamped",
           "imu": "sensor_msgs/msg/Imu", "pressure": "sensor_msgs/msg/FluidPressure",
           "thrusters": ARRAY_TYPES + INTEGER_ARRAY_TYPES}
G = 9.80665  # m/s^2, standard gravity (as pressure sensors' depth uses)
SURFACE_PRESSURE = 101325.0  # Pa, the standard atmosphere


def euler_from_quaternion(q: Array) -> Array:
    """(n, 3) roll, pitch, yaw (ZYX) of (n, 4) quaternions (x, y, z, w)."""
    x, y, z, w = q.T
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.column_stack([roll, pitch, yaw])


def _received(reader: Any, topic: str) -> list[int]:
    """The bag's receive times [ns] of `topic`'s messages (for unstamped ones)."""
    conns = [c for c in reader.connections if c.topic == topic]
    return [int(ns) for _, ns, _ in reader.messages(connections=conns)]


def _topics(mapping: Mapping) -> dict[str, str]:
    topics = mapping.data.get("topics")
    where = mapping.where
    if not isinstance(topics, dict):
        raise LogError(f"{where}: topics: expected a table naming 'odometry' and 'wrench' or 'thrusters'")
    for key, name in topics.items():
        if key not in _TOPICS:
            raise LogError(f"{where}: topics.{key}: unknown (expected some of {sorted(_TOPICS)})")
        if not isinstance(name, str):
            raise LogError(f"{where}: topics.{key}: expected a topic name, got {name!r}")
    if "odometry" not in topics and not mapping.data.get("arrays"):
        raise LogError(f"{where}: topics.odometry: expected a topic name (the time base and velocity), "
                       "or [[arrays]] giving the pose and velocity")
    if ("wrench" in topics) == ("thrusters" in topics):
        raise LogError(f"{where}: topics: expected one of 'wrench' and 'thrusters' for the force")
    return topics


def _positive(mapping: Mapping, key: str, default: float | None) -> float:
    v = mapping.data.get(key, default)
    if v is None:
        raise LogError(f"{mapping.where}: {key}: expected a number > 0 (needed with a pressure topic)")
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0:
        raise LogError(f"{mapping.where}: {key}: expected a number > 0, got {v!r}")
    return float(v)


def _thrust(mapping: Mapping, commands: Array, thrusters: dict[str, Any] | None, where: str) -> Array:
    """The body wrench of per-thruster commands."""
    unit = mapping.data.get("thruster_command", "N")
    if unit not in ("N", "pwm"):
        raise LogError(f"{mapping.where}: thruster_command: expected 'N' or 'pwm', got {unit!r}")
    if thrusters is None:
        raise LogError(f"{where}: thruster commands need the template's [thrusters] to become a force")
    n = thrusters["matrix"].shape[1]
    if commands.shape[1] != n:
        raise LogError(f"{where}: {commands.shape[1]} values per message, expected {n} (the "
                       "template's thrusters)")
    if unit == "N":
        return commands @ np.asarray(thrusters["matrix"]).T
    if thrusters.get("curves") is None:
        raise LogError(f"{where}: PWM commands need the template's [thrusters.curve] to become thrust")
    return pwm_force(commands, thrusters)


def read_rosbag(path: str | Path, mapping: Mapping, thrusters: dict[str, Any] | None = None) -> Log:
    from rosbags.highlevel import AnyReader

    path = Path(path)
    if not path.exists():
        raise LogError(f"{path}: no such bag")
    topics = _topics(mapping)
    density = _positive(mapping, "water_density", None) if "pressure" in topics else 0.0
    p0 = _positive(mapping, "surface_pressure", SURFACE_PRESSURE) if "pressure" in topics else 0.0
    msgs: dict[str, list[Any]] = {}
    arrays = []
    try:
        with AnyReader([path]) as reader:
            for key, topic in topics.items():
                msgs[key] = topic_messages(reader, topic, _TOPICS[key], str(path))
            received = _received(reader, topics["thrusters"]) if "thrusters" in topics else []
            for topic, cols in array_specs(mapping):
                found = topic_messages(reader, topic, ARRAY_TYPES, str(path))
                arrays.append((topic, np.array(_received(reader, topic), dtype=np.int64),
                               array_rows(found, cols, f"{path}: {topic}")))
    except LogError:
        raise
    except RecordingError as e:  # a topic missing or of another type
        raise LogError(str(e)) from None
    except Exception as e:  # rosbags' own errors for a file that is not a bag
        raise LogError(f"{path}: not a readable bag: {e}") from None
    for key, found in msgs.items():
        if not found:
            raise LogError(f"{path}: topic {topics[key]!r} has no message")
    odom = msgs.get("odometry", [])
    t_ns = np.array([stamp_ns(m) for m in odom], dtype=np.int64) if odom else arrays[0][1]
    t = (t_ns - t_ns[0]) * 1e-9

    def held(key: str, values: Array, stamps: Any = None) -> Array:
        ns = np.array([stamp_ns(m) for m in msgs[key]] if stamps is None else stamps, dtype=np.int64)
        return hold(t, (ns - t_ns[0]) * 1e-9, values, mapping.max_age, f"{path}: {topics[key]}")

    pos, angles, twist = np.full((len(t), 3), np.nan), np.full((len(t), 3), np.nan), np.full((len(t), 6), np.nan)
    if odom:
        pos = np.array([[m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z]
                        for m in odom])
        quat = np.array([[m.pose.pose.orientation.x, m.pose.pose.orientation.y,
                          m.pose.pose.orientation.z, m.pose.pose.orientation.w] for m in odom])
        twist = np.array([[m.twist.twist.linear.x, m.twist.twist.linear.y, m.twist.twist.linear.z,
                           m.twist.twist.angular.x, m.twist.twist.angular.y, m.twist.twist.angular.z]
                          for m in odom])
        angles = euler_from_quaternion(quat)
    if "imu" in msgs:
        imu = msgs["imu"]
        q = np.array([[m.orientation.x, m.orientation.y, m.orientation.z, m.orientation.w] for m in imu])
        w = np.array([[m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z] for m in imu])
        both = held("imu", np.hstack([q, w]))
        ok = np.all(np.isfinite(both), axis=1)
        angles = np.full_like(angles, np.nan)
        angles[ok] = euler_from_quaternion(both[ok, :4])
        twist[:, 3:] = both[:, 4:]
    if "pressure" in msgs:
        depth = held("pressure", np.array([[(m.fluid_pressure - p0) / (density * G)]
                                           for m in msgs["pressure"]]))[:, 0]
        pos[:, 2] = -depth if mapping.world_frame == "enu" else depth
    eta = np.hstack([pos, angles])
    for topic, ns, values in arrays:
        got = hold(t, (ns - t_ns[0]) * 1e-9, values, mapping.max_age, f"{path}: {topic}")
        for col in np.flatnonzero(np.any(np.isfinite(values), axis=0)):
            (eta if col < 6 else twist)[:, col % 6] = got[:, col]
    # What the log lacks is said before the force is read (a thruster
    # mismatch is the lesser problem of a log with no attitude); a log with
    # no linear velocity or position is read, those columns held at zero
    # and named (its DOFs are left out of the fit, the log report says so).
    absent = fill_absent(str(path), eta, twist, mapping.where)
    if "wrench" in msgs:
        w = np.array([[m.wrench.force.x, m.wrench.force.y, m.wrench.force.z,
                       m.wrench.torque.x, m.wrench.torque.y, m.wrench.torque.z] for m in msgs["wrench"]])
        tau = held("wrench", w)
    else:
        where = f"{path}: {topics['thrusters']}"
        rows = [np.asarray(m.data, dtype=np.float64) for m in msgs["thrusters"]]
        if len({r.size for r in rows}) != 1:
            raise LogError(f"{where}: the messages hold different numbers of commands")
        commands = held("thrusters", np.vstack(rows), received)
        # The configuration matrix acts in neurov's body frame: the force it
        # gives is turned back into the log's frame with the rest below.
        tau = _thrust(mapping, commands, thrusters, where)
        if mapping.body_frame == "flu":
            tau = tau * np.array([1, -1, -1, 1, -1, -1.0])
    eta, nu, tau = to_neurov_frames(eta, twist, tau, mapping.body_frame, mapping.world_frame)
    t, eta, nu, tau, notes = resample_by_mapping(t, eta, nu, tau, mapping)
    log = make_log(str(path), t, eta, nu, tau, absent=absent)
    return replace(log, notes=(*notes, *log.notes)) if notes else log
