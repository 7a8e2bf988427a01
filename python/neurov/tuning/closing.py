"""What ``neurov tune`` prints last: every file it wrote, then the verdict in
words of the tuned controllers on the held-out plants
(:mod:`neurov.study.verdict`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from neurov.study.running import written_message
from neurov.study.verdict import vehicle_verdicts, verdict_text

if TYPE_CHECKING:
    from neurov.tuning.running import TuneOutcome

__all__ = ["closing_message"]


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
