"""What a tuning leaves (:class:`TuneOutcome`, which :func:`neurov.tune`
returns) and what ``neurov tune`` prints last: every file it wrote, then the
verdict in words of the tuned controllers on the held-out plants
(:mod:`neurov.study.verdict`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from neurov.study.running import StudyOutcome, written_message
from neurov.study.verdict import vehicle_verdicts, verdict_text

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["TuneOutcome", "closing_message"]


@dataclass
class TuneOutcome:
    """What :func:`neurov.tune` returns: the folder, the trials run, the tuned
    gains and the files written, and the verdict study's outcome."""

    out_dir: Path
    ran: int
    """Trials this call ran (the others were in the storage, or run by other processes)."""
    seconds: float
    best: dict[str, dict[str, Any]]
    """Controller key -> its tuned table (as in best.toml)."""
    trials_path: Path
    best_path: Path
    figures: list[Path]
    verdict: StudyOutcome | None
    unusable: dict[str, str] = field(default_factory=dict)
    """Controller key -> why its best trial is no tuning at all (no trial
    feasible, every run failed): best.toml holds its least bad gains."""
    equal_effort: pd.DataFrame | None = None
    """Two objectives: the verdict among the controllers read at equal effort (equal_effort.csv)."""
    equal_effort_words: str = ""
    param_files: list[tuple[Path, bool]] = field(default_factory=list)
    """(path, feasible) of each ArduSub parameter file written beside best.toml."""


def closing_message(outcome: TuneOutcome, test_samples: int) -> str:
    """The files of the tuning and of its verdict study, then the verdict."""
    out = outcome.out_dir
    figures = ", ".join(p.name for p in outcome.figures) or "none (--no-plots)"
    lines = [f"wrote to {out}/:", f"  trials: {outcome.trials_path.name}", f"  tuned gains: {outcome.best_path.name}",
             "  storage: tuning.db (a rerun resumes from it), tuning.json", f"  figures: {figures}"]
    v = outcome.verdict
    if v is None:
        return "\n".join(lines)
    lines += ["", f"verdict study on {test_samples} held-out plants per scenario, in {v.out_dir}:",
              written_message(v)]
    text = verdict_text(vehicle_verdicts(v.study, v.table) if v.study else [], title="verdict of the tuning")
    if outcome.equal_effort_words:  # two objectives: the controllers compared where their efforts are equal
        text += ("\n" if text else "") + f"at equal effort: {outcome.equal_effort_words}"
    return "\n".join(lines + (["", text] if text else []))
