"""neurov's errors, in one family: every error neurov raises for bad input
derives from :class:`NeurovError`, itself a ``ValueError``, so one ``except
neurov.errors.NeurovError`` (or the familiar ``except ValueError``) catches
them all, and a caller can tell neurov's refusals from a bug's.

``NeurovError`` and ``ValidationError`` are made by the compiled core (it
raises ``ValidationError`` when a C++ validator refuses a configuration and
never imports this package); the others say which kind of input was refused.
A ``ValidationError`` carries what the validator found as attributes, so no
caller reads its message to learn the field: ``field`` (the C++ name),
``index`` (the element, row-major for a matrix; -1 for the whole field),
``value`` (None for a whole matrix) and ``expected``.

A run that finished but should not be trusted as it stands is told by a
warning, not an error: :class:`RefusedStepsWarning`.
"""

from __future__ import annotations

from neurov._core import NeurovError, ValidationError

__all__ = [
    "ControllerError",
    "FactoryError",
    "NeurovError",
    "RecordedPathError",
    "RecordingError",
    "RefusedStepsWarning",
    "ResultFileError",
    "ScenarioError",
    "SchemaError",
    "StudyError",
    "ValidationError",
    "VehicleFileError",
    "WeightsFileError",
]


class SchemaError(NeurovError):
    """A value that does not fit its field; the message names file and key."""


class ScenarioError(NeurovError):
    """A scenario that cannot be used: names the file, the field and what was expected."""


class VehicleFileError(NeurovError):
    """A vehicle file that cannot be read: names the file and the field."""


class WeightsFileError(NeurovError):
    """A weights file that cannot be read, or does not fit the network."""


class RecordingError(NeurovError):
    """A recording (MCAP, ROS 2 bag) that cannot be read: names the file, the topic or the field."""


class RecordedPathError(RecordingError):
    """A recorded path that cannot be read; `field` is the argument at
    fault (``file``, ``topic`` or ``start``)."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(message)
        self.field = field


class ResultFileError(NeurovError):
    """A run's file (result.npz, .csv, .parquet or its folder) that cannot be
    loaded back: names the file (or the command-line argument) and what was
    expected of it."""


class StudyError(NeurovError):
    """A study that cannot be run: names the file and the field."""


class FactoryError(NeurovError):
    """A factory that cannot be imported, is not callable, or does not return a controller."""


class ControllerError(NeurovError):
    """A controller written in Python failed in a study's run (it raised, or
    returned something that is not six finite real numbers): the study
    records the run as failed, with the first failure's message."""


class RefusedStepsWarning(RuntimeWarning):
    """A controller written in Python had steps refused (it raised, or
    returned something that is not six finite real numbers): the run went
    on under the scenario's ``refused_step_policy``, so its numbers are not
    the controller's. ``result.first_refusal`` gives the first error."""
