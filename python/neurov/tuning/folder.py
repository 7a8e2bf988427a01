"""A tuning's folder read back: the study of its verdict rebuilt from the
tuning file and best.toml, so that ``neurov report`` prints the verdict's
tables from the folder (or from a copy of it kept under docs/data/)."""

from __future__ import annotations

import json
from pathlib import Path

from neurov.tuning.spec import TuneError
from neurov.files import read_toml
from neurov.study.spec import Study
from neurov.tuning.reading import load_tuning, verdict_study

__all__ = ["is_tuning_folder", "verdict_of_folder"]


def is_tuning_folder(folder: str | Path) -> bool:
    """Whether `folder` is a tuning's (tuning.json and best.toml, the verdict in verdict/)."""
    folder = Path(folder)
    return (folder / "tuning.json").is_file() and (folder / "best.toml").is_file()


def verdict_of_folder(folder: str | Path) -> tuple[Path, Study]:
    """The verdict's study folder of a tuning's folder and its study: the
    tuning (the shipped one of tuning.json's name, else its source) with the
    gains of best.toml."""
    folder = Path(folder)
    try:
        meta = json.loads((folder / "tuning.json").read_text())
    except (OSError, json.JSONDecodeError) as e:
        raise TuneError(f"{folder}/tuning.json: not readable ({e}); is it a tuning's folder?") from None
    name = meta.get("name", "")
    try:
        tuning = load_tuning(name)
    except (TuneError, OSError):
        tuning = load_tuning(meta.get("source", ""))
    best = read_toml(folder / "best.toml", TuneError, "tuned gains").get("controllers", {})
    return folder / "verdict", verdict_study(tuning, best)
