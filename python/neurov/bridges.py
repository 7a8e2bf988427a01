"""The bridges' (and the figures') functions registered for the layers beneath them
(:mod:`neurov.hooks`), run by ``import neurov``.

Each function imports its bridge only when it is called: the bridges load
optional libraries (mcap, SciPy, python-control, plotly, Matplotlib) that
``import neurov`` must not (tests/python/test_import_cost.py).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from neurov import hooks

__all__: list[str] = []


def _read_mcap(path: Path, scenario: Any) -> Any:
    from neurov.recording.mcap_reader import read_mcap  # deferred: mcap

    return read_mcap(path, scenario)


def _write_mcap(result: Any, path: str | Path) -> Path:
    from neurov.recording.mcap_writer import write_mcap  # deferred: mcap, SciPy

    return write_mcap(result, path)


def _mcap_recorder(path: Path, scenario: Any, thrusters: int) -> Any:
    from neurov.recording.mcap_writer import McapRecorder  # deferred: mcap, SciPy

    return McapRecorder(path, scenario, thrusters)


def _recorded_path(file: str | Path, topic: str, start: float = 0.0) -> Any:
    from neurov.recording.recorded_path import recorded_path  # deferred: rosbags or mcap, SciPy

    return recorded_path(file, topic, start)


def _to_time_response(result: Any) -> Any:
    from neurov.control import to_time_response  # deferred: python-control

    return to_time_response(result)


def _replay(results: Any, **options: Any) -> Any:
    from neurov.replay import replay  # deferred: plotly, at the replay's first call

    return replay(results, **options)


def _run_figures(drawn: Any, **options: Any) -> Any:
    from neurov.plotting.run_figures import run_figures  # deferred: Matplotlib

    return run_figures(drawn, **options)


for _name, _function in (("read_mcap", _read_mcap), ("write_mcap", _write_mcap),
                         ("mcap_recorder", _mcap_recorder), ("recorded_path", _recorded_path),
                         ("to_time_response", _to_time_response), ("replay", _replay),
                         ("run_figures", _run_figures)):
    hooks.provide(_name, _function)
