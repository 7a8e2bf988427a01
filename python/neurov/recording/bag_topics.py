"""A bag's topics through ``rosbags`` (no ROS installation): the messages of
one topic, and a message's header stamp. Shared by the recorded path
(:mod:`neurov.recording.recorded_path`) and identification's bag reader
(:mod:`neurov.identification.rosbag_log`), which sits above this layer."""

from __future__ import annotations

from typing import Any

from neurov.errors import RecordingError

__all__ = ["stamp_ns", "topic_messages"]


def stamp_ns(msg: Any) -> int:
    """A stamped message's header stamp in integer nanoseconds."""
    return int(msg.header.stamp.sec) * 1_000_000_000 + int(msg.header.stamp.nanosec)


def topic_messages(reader: Any, topic: str, msgtype: str | tuple[str, ...], where: str) -> list[Any]:
    """The messages of `topic` in an open ``rosbags`` reader, deserialised;
    :class:`neurov.errors.RecordingError` naming `where` for a topic missing
    or of a type not `msgtype` (one of them, for a tuple)."""
    wanted = (msgtype,) if isinstance(msgtype, str) else msgtype
    conns = [c for c in reader.connections if c.topic == topic]
    if not conns:
        raise RecordingError(f"{where}: no topic {topic!r} (the bag has "
                             f"{sorted({c.topic for c in reader.connections})})")
    if conns[0].msgtype not in wanted:
        raise RecordingError(f"{where}: topic {topic!r} is {conns[0].msgtype}, expected {' or '.join(wanted)}")
    return [reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages(connections=conns)]
