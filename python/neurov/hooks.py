"""What the bridges lend to the layers beneath them.

The configuration, running and results layers never import a bridge
(recording, python-control, the replay), not even inside a function: a
bridge sits above them. Where one of them offers what only a bridge can do
(:meth:`neurov.Result.to_mcap`, ``load_result("run.mcap")``, ``neurov run
--format mcap``, a recorded path as a scenario's command, ...), it asks
this registry for the function by name, and the bridge has put it here:
:mod:`neurov.bridges` registers every bridge's functions when ``import
neurov`` runs (as it does before any of neurov's modules is imported), each
deferring its bridge's import until it is called, so that ``import
neurov`` loads none of their libraries.

The names, and what each function is:

- ``"read_mcap"``: ``(path, scenario) -> Result``, a run read back from a
  ROS 2 recording (:func:`neurov.recording.mcap_reader.read_mcap`);
- ``"write_mcap"``: ``(result, path) -> Path``
  (:func:`neurov.recording.mcap_writer.write_mcap`);
- ``"mcap_recorder"``: ``(path, scenario, thrusters) -> recorder``, a run
  streamed into a recording chunk by chunk
  (:class:`neurov.recording.mcap_writer.McapRecorder`);
- ``"recorded_path"``: ``(file, topic, start) -> (times, poses)``
  (:func:`neurov.recording.recorded_path.recorded_path`);
- ``"to_time_response"``: ``(result) -> control.TimeResponseData``
  (:func:`neurov.control.to_time_response`);
- ``"replay"``: ``(results, **options) -> Replay`` (:func:`neurov.replay.replay`);
- ``"run_figures"``: ``(drawn, sea=, elevation=) -> {file name: draw(path) -> path}``,
  the figures of ``neurov run --plot`` (:func:`neurov.plotting.run_figures.run_figures`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from neurov.errors import NeurovError

__all__ = ["NAMES", "provide", "provided"]

NAMES = ("read_mcap", "write_mcap", "mcap_recorder", "recorded_path", "to_time_response", "replay",
         "run_figures")
"""Every name a bridge may provide (see the module)."""

_PROVIDED: dict[str, Callable[..., Any]] = {}


def provide(name: str, function: Callable[..., Any]) -> None:
    """Registers `function` as what `name` (one of :data:`NAMES`) does."""
    if name not in NAMES:
        raise ValueError(f"argument 'name': expected one of {', '.join(NAMES)}, got {name!r}")
    _PROVIDED[name] = function


def provided(name: str) -> Callable[..., Any]:
    """The function registered as `name`; a :class:`neurov.errors.NeurovError`
    if no bridge has registered it (only possible when a module of neurov is
    loaded without ``import neurov`` having run)."""
    try:
        return _PROVIDED[name]
    except KeyError:
        raise NeurovError(f"nothing provides {name!r}: its bridge registers it when `import neurov` "
                          "runs (neurov.bridges)") from None
