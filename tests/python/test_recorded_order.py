"""A recorded command whose header stamps go backwards in the order the
messages were logged is refused, as ``neurov identify`` refuses time going
backwards: before, the poses were re-sorted by stamp into another path
without a word."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("rosbags")

from neurov.recording.recorded_path import RecordedPathError, recorded_path  # noqa: E402


def _bag(folder: Path, stamps_s: list[float]) -> Path:
    """A rosbag2 folder of PoseStamped on /path logged at 0, 1, 2, ... s,
    their header stamps `stamps_s`."""
    from rosbags.rosbag2 import Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    T = store.types
    epoch = 1_700_000_000 * 10**9
    with Writer(folder, version=8) as writer:
        conn = writer.add_connection("/path", "geometry_msgs/msg/PoseStamped", typestore=store)
        for k, stamp in enumerate(stamps_s):
            ns = epoch + round(stamp * 1e9)
            msg = T["geometry_msgs/msg/PoseStamped"](
                header=T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](
                    sec=ns // 10**9, nanosec=ns % 10**9), frame_id="map"),
                pose=T["geometry_msgs/msg/Pose"](
                    position=T["geometry_msgs/msg/Point"](x=float(k), y=0.0, z=0.0),
                    orientation=T["geometry_msgs/msg/Quaternion"](x=0.0, y=0.0, z=0.0, w=1.0)))
            writer.write(conn, epoch + k * 10**9, store.serialize_cdr(msg, "geometry_msgs/msg/PoseStamped"))
    return folder


def test_stamps_going_backwards_in_the_order_logged_are_refused(tmp_path: Path) -> None:
    bag = _bag(tmp_path / "bag", [0.0, 2.0, 1.0, 3.0])
    with pytest.raises(RecordedPathError, match=r"bag: topic '/path': header stamps must not go backwards; "
                                                r"pose 2 \(in the order logged\) is stamped 1 s after the first, "
                                                r"before pose 1 at 2 s") as err:
        recorded_path(bag, "/path")
    assert err.value.field == "topic"


def test_increasing_stamps_read_in_their_order(tmp_path: Path) -> None:
    times, poses = recorded_path(_bag(tmp_path / "bag", [0.0, 0.5, 2.0, 3.0]), "/path", start=1.0)
    assert list(times) == [1.0, 1.5, 3.0, 4.0]
    assert list(poses[:, 1]) == [0.0, 1.0, 2.0, 3.0]  # ENU x is NED y
