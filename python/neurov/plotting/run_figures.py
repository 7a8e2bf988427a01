"""The figures ``neurov run --plot`` writes (:data:`neurov.running.command.FIGURES`
and, for a run that met a sea, :data:`~neurov.running.command.SEA_FIGURES`),
each as a function that draws it into a file; lent to the running layer
through :mod:`neurov.hooks` as ``"run_figures"``."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from neurov.plotting import runs, sea as sea_plots
from neurov.results.timeseries import Result
from neurov.running.command import FIGURES, SEA_FIGURES

__all__ = ["run_figures"]


def run_figures(drawn: Result, *, sea: bool | None = None,
                elevation: Result | None = None) -> dict[str, Callable[[Path], Path]]:
    """File name -> a function that draws that figure of the run `drawn`
    into the path it is given and returns it: :data:`FIGURES`, and those of
    :data:`SEA_FIGURES` that apply (`sea`: the run met a current, waves or a
    payload change, default from its rows; the wave spectrum of a run with
    waves, from `elevation`, default `drawn`)."""
    draws = dict(zip(FIGURES, (runs.xy_path, runs.dof_time, runs.errors, runs.control_inputs,
                               runs.adaptive_norm)))
    if sea_plots.has_sea(drawn) if sea is None else sea:
        draws[SEA_FIGURES[0]] = sea_plots.sea_flow
    if drawn.scenario.waves is not None:
        draws[SEA_FIGURES[1]] = lambda _: sea_plots.wave_spectrum(elevation or drawn)
    return {name: (lambda path, draw=draw: runs.save(draw(drawn), path)) for name, draw in draws.items()}
