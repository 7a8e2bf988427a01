"""Drawing a study's figures, and only those whose data changed: each
figure's inputs are hashed into figures.json next to it, so a rerun that
adds no run redraws nothing."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Mapping
from pathlib import Path
from types import ModuleType

import pandas as pd

from neurov.progress import progress_bar
from neurov.config.scenario import Scenario
from neurov.study.log import Record
from neurov.study.spec import Study
from neurov._core import __version__

__all__ = ["FIGURE_STATE", "draw_figures"]

FIGURE_STATE = "figures.json"
#: Part of every figure's digest: raised when the drawing changes within a
#: release, so that a study folder drawn by the old code is redrawn.
#: 2: few samples as points, metric labels in words, fixed layouts.
#: 3: one colour per controller, horizontal boxes named on every row, titles that wrap.
#: 4: one scale for every box panel, angles in degrees, one-run studies drawn and titled as such.
FIGURE_STYLE = 4


def _digest(*parts: object) -> str:
    text = json.dumps([__version__, FIGURE_STYLE, *parts], sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _plots() -> ModuleType:
    # matplotlib takes a second to import; a rerun with nothing to draw skips it.
    from neurov.plotting import study

    return study


def _figures(study: Study, table: pd.DataFrame, records: Mapping[tuple[str, str, int], Record]
             ) -> list[tuple[str, str, Callable[[Path], Path]]]:
    """(file name, digest of what it shows, how to draw it) for every figure."""
    labels = [(c, study.label(c)) for c in study.controllers]
    metric = study.ranking_metric
    shown = table[["scenario", "controller", "sample", metric]]
    out = [(f"boxplot_{metric}.png",
            _digest("boxes", study.name, study.samples, labels, [s.name for s in study.scenarios],
                    shown.to_csv(index=False)),
            lambda path: _plots().plot_boxes(study, table, path))]
    bands: list = []  # one figure object for every band plot, built at the first one drawn

    def draw_bands(path: Path, scenario: Scenario) -> Path:
        if not bands:
            bands.append(_plots().BandPlotter(study))
        return bands[0].draw(records, scenario, path)

    for s in study.scenarios:
        series = [records[(s.name, c, k)]["series"] for c in study.controllers for k in range(study.samples)
                  if (s.name, c, k) in records]
        out.append((f"error_bands_{s.name}.png",
                    _digest("bands", s.name, study.samples, study.after, labels, series),
                    lambda path, s=s: draw_bands(path, s)))
    return out


def draw_figures(study: Study, table: pd.DataFrame, records: Mapping[tuple[str, str, int], Record],
                 out: Path, quiet: bool = False) -> list[Path]:
    """Draws the box plot and the error bands into `out` where missing or
    stale, with a progress bar; returns the paths drawn."""
    state_path = out / FIGURE_STATE
    try:
        state = json.loads(state_path.read_text())
        if not isinstance(state, dict):
            state = {}
    except (OSError, json.JSONDecodeError):
        state = {}
    # A run without a result (it raised, or its worker died) has no error series to draw.
    records = {k: r for k, r in records.items() if r.get("series") is not None}
    stale = [(name, digest, draw) for name, digest, draw in _figures(study, table, records)
             if state.get(name) != digest or not (out / name).is_file()]
    drawn = []
    with progress_bar(len(stale), f"{study.name}: plots", unit="plot", quiet=quiet) as bar:
        for name, digest, draw in stale:
            drawn.append(draw(out / name))
            # Saved after each figure: an interrupted plotting phase keeps what it drew.
            state[name] = digest
            state_path.write_text(json.dumps(state, indent=2, sort_keys=True) + "\n")
            bar.update(1)
    return drawn
