"""A recorded path as a commanded trajectory: the poses of a
``geometry_msgs/msg/PoseStamped`` or ``nav_msgs/msg/Odometry`` topic of a
ROS 2 bag or an MCAP file (read with ``rosbags``, as ``neurov identify``
reads bags), in ROS's ENU world and FLU body (REP 103), as neurov's timed
NED poses. A scenario names it::

    [command]
    type = "recorded"
    file = "survey.mcap"        # beside the scenario file, or an absolute path
    topic = "/command_pose"
    start = 0.0                 # s: when the first pose is commanded

The times are the header stamps less the first one, plus `start`; the
heading is unwrapped (a continuous angle, as the generators of
:mod:`neurov.config.trajectories` give it).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from neurov.errors import RecordedPathError, RecordingError
from neurov.recording.frames import euler_from_enu_quaternions, position_to_enu
from neurov.recording.bag_topics import stamp_ns, topic_messages

__all__ = ["POSE_TYPES", "RecordedPathError", "recorded_path"]

POSE_TYPES = ("geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Odometry")
"""The message types a recorded path is read from."""


def recorded_path(file: str | Path, topic: str, start: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """``(times, poses)`` of the poses on `topic` of the bag or MCAP `file`
    (see the module): times (K,) strictly increasing from `start`, poses
    (K, 6) NED [x, y, z, phi, theta, psi]. Raises :class:`RecordedPathError`
    for a file missing or unreadable, a topic missing or of another type,
    fewer than two poses, repeated stamps or stamps going backwards in the
    order logged, or non-finite values."""
    path = Path(file)
    if not isinstance(topic, str) or not topic:
        raise RecordedPathError("topic", f"expected a topic name, got {topic!r}")
    if isinstance(start, bool) or not isinstance(start, (int, float)) or not np.isfinite(start):
        raise RecordedPathError("start", f"expected a finite number of seconds, got {start!r}")
    if not path.exists():
        raise RecordedPathError("file", f"no such bag or MCAP file: {path}")
    try:
        from rosbags.highlevel import AnyReader
    except ImportError:
        raise RecordedPathError("file", "reading a recorded path needs rosbags: pip install 'neurov[ros]'") from None

    try:
        with AnyReader([path]) as reader:
            messages = topic_messages(reader, topic, POSE_TYPES, str(path))
    except RecordedPathError:
        raise
    except RecordingError as e:  # the topic missing or of another type
        raise RecordedPathError("topic", str(e)) from None
    except Exception as e:  # rosbags' own errors for a file that is not a bag
        raise RecordedPathError("file", f"{path}: not a readable ROS 2 bag or MCAP file "
                                        f"({type(e).__name__}: {e})") from None
    if len(messages) < 2:
        raise RecordedPathError("topic", f"{path}: topic {topic!r} has {len(messages)} pose(s); a path "
                                         "needs at least 2")
    poses = [m.pose.pose if hasattr(m, "child_frame_id") else m.pose for m in messages]
    xyz = np.array([[p.position.x, p.position.y, p.position.z] for p in poses])
    q = np.array([[p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w] for p in poses])
    if not (np.all(np.isfinite(xyz)) and np.all(np.isfinite(q))):
        raise RecordedPathError("topic", f"{path}: topic {topic!r} has non-finite positions or orientations")
    if np.any(np.linalg.norm(q, axis=1) < 1e-9):
        raise RecordedPathError("topic", f"{path}: topic {topic!r} has a zero quaternion (no orientation)")
    # In the order logged: a header stamp going backwards is refused, as
    # ``neurov identify`` refuses time going backwards (not re-sorted into
    # another path).
    ns = np.array([stamp_ns(m) for m in messages], dtype=np.int64)
    steps = np.diff(ns)
    if np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0])
        if steps[k] == 0:
            raise RecordedPathError("topic", f"{path}: topic {topic!r}: two poses stamped {ns[k]} ns; "
                                             "a path needs strictly increasing stamps")
        raise RecordedPathError("topic", f"{path}: topic {topic!r}: header stamps must not go backwards; pose "
                                         f"{k + 1} (in the order logged) is stamped {(ns[k + 1] - ns[0]) * 1e-9:.9g} "
                                         f"s after the first, before pose {k} at {(ns[k] - ns[0]) * 1e-9:.9g} s")
    euler = euler_from_enu_quaternions(q)
    euler[:, 2] = np.unwrap(euler[:, 2])
    times = float(start) + (ns - ns[0]) * 1e-9
    return times, np.hstack([position_to_enu(xyz), euler])
