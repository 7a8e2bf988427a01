"""Warnings neurov gives about a run that finished but should not be trusted
as it stands."""

from __future__ import annotations

__all__ = ["RefusedStepsWarning"]


class RefusedStepsWarning(RuntimeWarning):
    """A controller written in Python had steps refused (it raised, or
    returned something that is not six finite real numbers): the run went
    on under the scenario's ``refused_step_policy``, so its numbers are not
    the controller's. ``result.first_refusal`` gives the first error."""
