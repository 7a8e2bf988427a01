"""Runs as ROS 2 recordings (MCAP) and recorded paths read back.

:func:`neurov.recording.mcap_writer.write_mcap` (``Result.to_mcap``,
``neurov run --format mcap``) writes a run as ROS 2 messages in the frames
ROS tools expect (REP 103/105, see :mod:`neurov.recording.frames`);
:func:`neurov.recording.mcap_reader.read_mcap` reads it back into the
:class:`neurov.Result` it was; :mod:`neurov.recording.recorded_path` reads
the poses of a ROS 2 bag or MCAP as a scenario's commanded path. The
``mcap`` packages are imported by those modules only, so that
``import neurov`` stays cheap (frames docs: docs/recordings.md)."""
