"""One colour per controller in every figure a study draws: no two
controllers share a colour, none is the grey that marks "the other
controllers", and the shipped controllers keep theirs from study to study."""

from __future__ import annotations

import dataclasses
from collections import defaultdict
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib.colors import to_hex, to_rgb
from matplotlib.figure import Figure

from neurov.plotting.colours import OTHERS_GREY, PALETTE, controller_colours
from neurov.plotting.study import FEW_SAMPLES, BandPlotter, box_figure
from neurov.study import load_study


def _colours_by_controller(fig: Figure) -> dict[str, set[str]]:
    """Every colour each controller's artists (gid "controller:NAME") are drawn in."""
    out: dict[str, set[str]] = defaultdict(set)
    for artist in fig.findobj(lambda a: str(a.get_gid() or "").startswith("controller:")):
        name = artist.get_gid().split(":", 1)[1]
        if hasattr(artist, "get_facecolor") and not hasattr(artist, "get_xdata"):
            colours = np.atleast_2d(artist.get_facecolor())
        else:
            colours = np.atleast_2d(to_rgb(artist.get_color()))
        out[name].update(to_hex(c[:3]) for c in colours)
    return out


def _assert_one_colour_each(fig: Figure, controllers: list[str]) -> None:
    seen = _colours_by_controller(fig)
    assert set(seen) == set(controllers)
    for name, colours in seen.items():
        assert len(colours) == 1, (name, colours)
    owners: dict[str, str] = {}
    for name, (colour,) in seen.items():
        assert colour not in owners, f"{name} and {owners.get(colour)} share {colour}"
        owners[colour] = name
        r, g, b = to_rgb(colour)
        assert not (r == g == b), f"{name} is drawn in a grey ({colour})"
    assert to_hex(OTHERS_GREY) not in owners


def _table(study: object, samples: int) -> pd.DataFrame:
    rng = np.random.default_rng(5)
    return pd.DataFrame([{"scenario": s.name, "controller": c, "sample": k,
                          study.ranking_metric: rng.uniform(0.05, 1.0)}  # type: ignore[attr-defined]
                         for s in study.scenarios for c in study.controllers  # type: ignore[attr-defined]
                         for k in range(samples)])


def _robustness(samples: int) -> object:
    # Eleven controllers, one past matplotlib's ten-colour cycle.
    study = load_study("robustness")
    study = dataclasses.replace(study, scenarios=study.scenarios[:2], samples=samples)
    assert len(study.controllers) > 10
    return study


@pytest.mark.parametrize("samples", [3, FEW_SAMPLES])  # points, then boxes
def test_no_two_controllers_share_a_colour_in_a_box_plot(samples: int) -> None:
    study = _robustness(samples)
    _assert_one_colour_each(box_figure(study, _table(study, samples)), study.controllers)  # type: ignore[attr-defined]


def test_no_two_controllers_share_a_colour_in_an_error_band_figure(tmp_path: Path) -> None:
    study = _robustness(3)
    scenario = study.scenarios[0]  # type: ignore[attr-defined]
    rng = np.random.default_rng(1)
    records = {(scenario.name, c, k): {"series": {"t0": 0.0, "dt": 0.5,
                                                  "position_error": list(rng.uniform(0.01, 1.0, 30))}}
               for c in study.controllers for k in range(3)}  # type: ignore[attr-defined]
    bands = BandPlotter(study)
    bands.draw(records, scenario, tmp_path / "bands.png", dpi=20)
    _assert_one_colour_each(bands.fig, study.controllers)  # type: ignore[attr-defined]


def test_a_controller_has_the_same_colour_in_every_shipped_study() -> None:
    seen: dict[str, str] = {}
    for name in ("league", "robustness", "realism", "sea_state"):
        study = load_study(name)
        for c, colour in controller_colours(study.controllers).items():
            assert seen.setdefault(c, colour) == colour, (name, c)


def test_colours_stay_distinct_past_the_palette() -> None:
    names = ["nn", "pd"] + [f"mine_{i}" for i in range(len(PALETTE) + 5)]
    colours = controller_colours(names)
    assert len(set(colours.values())) == len(names)
    assert colours["nn"] == controller_colours(["nn"])["nn"]
    with pytest.raises(ValueError, match="names"):
        controller_colours(["pd", "pd"])
