"""ROS 1 and ROS 2 bags through ``rosbags`` (no ROS installation): the
pose and body velocity from a ``nav_msgs/msg/Odometry`` topic (its time
base: the messages' header stamps, integer nanoseconds), the force from a
``geometry_msgs/msg/WrenchStamped`` topic in the body frame, held from its
latest message (the zero-order hold of the command) and cut where older
than the mapping's ``max_age``. The mapping file (see
:mod:`neurov.identification.mapping`)::

    format = "rosbag"
    body_frame = "flu"          # REP 103: base_link forward-left-up
    world_frame = "enu"         # odom / map east-north-up
    [topics]
    odometry = "/rov/odometry"
    wrench = "/rov/thrust_wrench"
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov.identification.alignment import hold
from neurov.identification.errors import LogError
from neurov.identification.log import Log, make_log
from neurov.identification.mapping import Mapping, to_neurov_frames

__all__ = ["read_rosbag", "euler_from_quaternion", "stamp_ns", "topic_messages"]

Array = NDArray[np.float64]
_TOPICS = {"odometry": "nav_msgs/msg/Odometry", "wrench": "geometry_msgs/msg/WrenchStamped"}


def euler_from_quaternion(q: Array) -> Array:
    """(n, 3) roll, pitch, yaw (ZYX) of (n, 4) quaternions (x, y, z, w)."""
    x, y, z, w = q.T
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = np.arcsin(np.clip(2 * (w * y - z * x), -1.0, 1.0))
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return np.column_stack([roll, pitch, yaw])


def stamp_ns(msg: Any) -> int:
    """A stamped message's header stamp in integer nanoseconds."""
    return int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec)


def topic_messages(reader: Any, topic: str, msgtype: str | tuple[str, ...], where: str) -> list[Any]:
    """The messages of `topic` in an open ``rosbags`` reader, deserialised;
    LogError naming `where` for a topic missing or of a type not `msgtype`
    (one of them, for a tuple)."""
    wanted = (msgtype,) if isinstance(msgtype, str) else msgtype
    conns = [c for c in reader.connections if c.topic == topic]
    if not conns:
        raise LogError(f"{where}: no topic {topic!r} (the bag has "
                       f"{sorted({c.topic for c in reader.connections})})")
    if conns[0].msgtype not in wanted:
        raise LogError(f"{where}: topic {topic!r} is {conns[0].msgtype}, expected {' or '.join(wanted)}")
    return [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages(connections=conns)]


def read_rosbag(path: str | Path, mapping: Mapping) -> Log:
    from rosbags.highlevel import AnyReader

    path = Path(path)
    if not path.exists():
        raise LogError(f"{path}: no such bag")
    topics = mapping.data.get("topics")
    if not isinstance(topics, dict):
        raise LogError(f"{mapping.where}: topics: expected a table naming 'odometry' and 'wrench'")
    for key in _TOPICS:
        if not isinstance(topics.get(key), str):
            raise LogError(f"{mapping.where}: topics.{key}: expected a topic name")
    try:
        with AnyReader([path]) as reader:
            odom = topic_messages(reader, topics["odometry"], _TOPICS["odometry"], str(path))
            wrench = topic_messages(reader, topics["wrench"], _TOPICS["wrench"], str(path))
    except LogError:
        raise
    except Exception as e:  # rosbags' own errors for a file that is not a bag
        raise LogError(f"{path}: not a readable bag: {e}") from None
    if not odom or not wrench:
        raise LogError(f"{path}: topic {topics['odometry' if not odom else 'wrench']!r} has no message")
    t_ns = np.array([stamp_ns(m) for m in odom], dtype=np.int64)
    t = (t_ns - t_ns[0]) * 1e-9
    pos = np.array([[m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z]
                    for m in odom])
    quat = np.array([[m.pose.pose.orientation.x, m.pose.pose.orientation.y,
                      m.pose.pose.orientation.z, m.pose.pose.orientation.w] for m in odom])
    twist = np.array([[m.twist.twist.linear.x, m.twist.twist.linear.y, m.twist.twist.linear.z,
                       m.twist.twist.angular.x, m.twist.twist.angular.y, m.twist.twist.angular.z]
                      for m in odom])
    w_t = (np.array([stamp_ns(m) for m in wrench], dtype=np.int64) - t_ns[0]) * 1e-9
    w = np.array([[m.wrench.force.x, m.wrench.force.y, m.wrench.force.z,
                   m.wrench.torque.x, m.wrench.torque.y, m.wrench.torque.z] for m in wrench])
    tau = hold(t, w_t, w, mapping.max_age, f"{path}: {topics['wrench']}")
    eta = np.hstack([pos, euler_from_quaternion(quat)])
    eta, nu, tau = to_neurov_frames(eta, twist, tau, mapping.body_frame, mapping.world_frame)
    return make_log(str(path), t, eta, nu, tau)
