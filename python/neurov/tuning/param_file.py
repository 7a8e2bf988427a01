"""ArduSub's tuned parameters written back as ArduSub reads them: for each
tuned ``ardusub`` controller, a QGroundControl parameter file beside
``best.toml`` (``best.param``; ``best_<controller>.param`` when several are
tuned) with only the parameters the tuning set, and a header saying what
they were tuned on. Written also when no trial was feasible (the least bad
trial), and the header says so. A two-objective tuning (error and effort)
writes the trial its front is read at, as best.toml holds it: the one of
least error within the stated effort (picks.csv), and the header says which."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from neurov.laws.ardusub_params import PARAMETERS, format_param_file
from neurov.tuning.equal_effort import Fronts
from neurov.tuning.outputs import best_tables, best_trial
from neurov.tuning.spec import Tuning

__all__ = ["write_best_params"]


def write_best_params(tuning: Tuning, studies: dict[str, Any], folder: Path,
                      fronts: Fronts | None = None) -> list[tuple[Path, bool]]:
    """(path, feasible) of each parameter file written: of the best trial,
    or with `fronts` (two objectives) of the trial read at equal effort."""
    tables = best_tables(tuning, studies) if fronts is None else fronts.tables
    tuned = [c for c, t in tables.items() if t.get("type") == "ardusub"]
    written = []
    s = tuning.settings
    scenarios = ", ".join(str(x) for x in tuning.study_table.get("scenarios", []))
    objective = (f"objective the {s.aggregate} of {s.objective}" if fronts is None else
                 f"two objectives, the {s.aggregate} of {s.objective} and of {s.effort}")
    for controller in tuned:
        table = tables[controller]
        feasible, picked = _picked(studies[controller], controller, fronts)
        params = {k: float(v) for k, v in table.items() if k in PARAMETERS}
        header = [
            f"ArduSub parameters tuned by `neurov tune {Path(tuning.source).name}` (controller {controller!r}):",
            f"{s.trials} trials, sampler {s.sampler} (seed {s.seed}); {objective}",
            f"over {s.train_samples} training plants per scenario of: {scenarios or 'the study file'}.",
            f"Mode {table.get('mode', 'depth_hold')}; on top of {table.get('params') or 'ArduSub defaults'}.",
            *picked[:-1],
            picked[-1] + ("." if feasible else ": NO TRIAL WAS FEASIBLE, these are the least bad values."),
            "Only the parameters the tuning set; load with QGroundControl's Parameters > Tools > Load from file."]
        name = "best.param" if len(tuned) == 1 else f"best_{controller}.param"
        path = folder / name
        path.write_text(format_param_file(params, header))
        written.append((path, feasible))
    return written


def _picked(study: Any, controller: str, fronts: Fronts | None) -> tuple[bool, list[str]]:
    """Whether the trial written was feasible, and the header's lines saying
    which trial it is (the last without its full stop)."""
    if fronts is None:
        best = best_trial(study)
        return bool(best.user_attrs.get("feasible", True)), [f"Best trial {best.number}, objective {best.value:.6g}"]
    rows = fronts.picks[fronts.picks["controller"] == controller]
    numbers = sorted({int(n) for n in rows["trial"]})
    trials = {t.number: t for t in study.trials if t.number in numbers}
    feasible = all(bool(trials[n].user_attrs.get("feasible", True)) for n in numbers)
    lines = [f"Read at equal effort ({fronts.source}; picks.csv): the trial of least error whose effort is",
             "at most that level, else the one over it least."]
    for r in rows.itertuples():
        reach = "within it" if r.within else "OVER IT: the front does not reach that effort"
        lines.append(f"On {r.vehicle}: trial {int(r.trial)}, error {r.error:.6g}, effort {r.effort:.6g} "
                     f"at the level {r.effort_at:.6g} ({reach})")
    return feasible, lines
