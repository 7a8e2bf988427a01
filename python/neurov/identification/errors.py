"""The errors of identification: each names the file, the signal or the
parameter and says what was expected."""

from __future__ import annotations

from neurov.errors import NeurovError

__all__ = ["IdentificationError", "LogError"]


class IdentificationError(NeurovError):
    """Identification cannot go on: a free parameter the logs cannot reach,
    a template outside the regressor's structure, too few samples."""


class LogError(IdentificationError):
    """A log that cannot be read: a missing signal, time going backwards,
    units that do not match. Names the file and the signal."""
