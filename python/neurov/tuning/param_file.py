"""ArduSub's tuned parameters written back as ArduSub reads them: for each
tuned ``ardusub`` controller, a QGroundControl parameter file beside
``best.toml`` (``best.param``; ``best_<controller>.param`` when several are
tuned) with only the parameters the tuning set, and a header saying what
they were tuned on. Written also when no trial was feasible (the least bad
trial), and the header says so."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from neurov.laws.ardusub_params import PARAMETERS, format_param_file
from neurov.tuning.outputs import best_tables, best_trial
from neurov.tuning.spec import Tuning

__all__ = ["write_best_params"]


def write_best_params(tuning: Tuning, studies: dict[str, Any], folder: Path) -> list[tuple[Path, bool]]:
    """(path, feasible) of each parameter file written."""
    tables = best_tables(tuning, studies)
    tuned = [c for c, t in tables.items() if t.get("type") == "ardusub"]
    written = []
    s = tuning.settings
    scenarios = ", ".join(str(x) for x in tuning.study_table.get("scenarios", []))
    for controller in tuned:
        table = tables[controller]
        best = best_trial(studies[controller])
        feasible = bool(best.user_attrs.get("feasible", True))
        params = {k: float(v) for k, v in table.items() if k in PARAMETERS}
        header = [
            f"ArduSub parameters tuned by `neurov tune {Path(tuning.source).name}` (controller {controller!r}):",
            f"{s.trials} trials, sampler {s.sampler} (seed {s.seed}); objective the {s.aggregate} of {s.objective}",
            f"over {s.train_samples} training plants per scenario of: {scenarios or 'the study file'}.",
            f"Mode {table.get('mode', 'depth_hold')}; on top of {table.get('params') or 'ArduSub defaults'}.",
            f"Best trial {best.number}, objective {best.value:.6g}"
            + ("." if feasible else ": NO TRIAL WAS FEASIBLE, these are the least bad values."),
            "Only the parameters the tuning set; load with QGroundControl's Parameters > Tools > Load from file."]
        name = "best.param" if len(tuned) == 1 else f"best_{controller}.param"
        path = folder / name
        path.write_text(format_param_file(params, header))
        written.append((path, feasible))
    return written
