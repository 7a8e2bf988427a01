"""Markdown tables of a tuning folder's small CSVs (budget.csv, picks.csv,
pareto.csv, equal_effort.csv) and of several seeds' folders, for the docs:
``neurov tune-table DIR [DIR ...] --table NAME``. They read the files only,
so a table of a long tuning is printed in a second from its kept outputs."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import pandas as pd

from neurov.tuning.seeds import rank_spread, spread_words

__all__ = ["TABLES", "main_table", "markdown_table"]


def _g(x: float | str) -> str:
    try:
        v = float(x)
    except ValueError:
        return str(x)
    return "n/a" if math.isnan(v) else "inf" if math.isinf(v) else f"{v:.3g}"


def _md(head: Sequence[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def budget_markdown(folder: Path) -> str:
    t = pd.read_csv(folder / "budget.csv")
    unit = str(t["budget"].iloc[0]).replace("_", " ")
    rows = [[r.controller, str(r.trials_started), str(r.trials_pruned), str(r.trials_completed),
             str(r.runs_finished), f"{r.budget_spent} of {r.budget_limit}"] for r in t.itertuples()]
    return _md(["controller", "trials started", "pruned", "completed", "runs finished", f"budget used ({unit})"],
               rows)


def fronts_markdown(folder: Path) -> str:
    """Per controller and vehicle: the front's size, its least-effort and
    least-error ends, and the trial read at the stated effort."""
    fronts = pd.read_csv(folder / "pareto.csv")
    picks = pd.read_csv(folder / "picks.csv")
    fronts = fronts[fronts["front"] != "all"]
    rows = []
    for r in picks.itertuples():
        f = fronts[(fronts["front"] == r.vehicle) & (fronts["controller"] == r.controller)].sort_values("effort")
        low, high = f.iloc[0], f.iloc[-1]
        rows.append([r.controller, r.vehicle, str(len(f)), f"{_g(low.error)} at {_g(low.effort)}",
                     f"{_g(high.error)} at {_g(high.effort)}",
                     f"{_g(r.error)} at {_g(r.effort)}" + ("" if r.within else " (above it: the front's least effort)"),
                     _g(r.effort_at)])
    return _md(["controller", "vehicle", "trials on the front", "least effort: error at effort",
                "least error: error at effort", "read at the stated effort: error at effort", "stated effort"],
               rows)


def equal_effort_markdown(folder: Path) -> str:
    """The verdict among the controllers read at equal effort: per scenario,
    the median error, its 95 % interval, the rank and the median effort;
    then the verdict's sentences."""
    t = pd.read_csv(folder / "equal_effort.csv")
    effort = "median_" + str(pd.read_csv(folder / "pareto.csv")["effort_metric"].iloc[0])
    scenarios = list(dict.fromkeys(t["scenario"]))
    order = t.groupby("controller", sort=False)["rank"].mean().sort_values(kind="stable").index
    rows = []
    for c in order:
        cells = [c]
        for s in scenarios:
            r = t[(t["scenario"] == s) & (t["controller"] == c)].iloc[0]
            rank = "**1**" if r["rank"] == 1 else str(int(r["rank"]))
            fail = f", fails {100 * r.failure_rate:.0f} %" if r.failure_rate > 0 else ""
            cells.append(f"{_g(r['median'])} ({_g(r.median_ci_low)}–{_g(r.median_ci_high)}), {rank}{fail}; "
                         f"effort {_g(r[effort])}")
        rows.append(cells)
    words = folder / "equal_effort.md"
    text = _md(["controller", *scenarios], rows)
    return text + ("\n\n" + words.read_text().strip() if words.exists() else "")


def spread_markdown(folders: Sequence[Path]) -> str:
    """Per controller and scenario: its rank in each seed and how often the
    most frequent one held; then whether the order is settled."""
    spread = rank_spread(folders)
    scenarios = list(dict.fromkeys(spread["scenario"]))
    controllers = list(spread.groupby("controller", sort=False)["modal_rank"].mean()
                       .sort_values(kind="stable").index)
    rows = []
    for c in controllers:
        cells = [c]
        for s in scenarios:
            r = spread[(spread["scenario"] == s) & (spread["controller"] == c)].iloc[0]
            cells.append(f"{r.ranks} ({r.modal_rank}: {r.held} of {r.seeds})")
        rows.append(cells)
    seeds = ", ".join(Path(f).name for f in folders)
    return (f"Ranks in the seeds {seeds}, in that order (the most frequent rank: in how many seeds it held).\n\n"
            + _md(["controller", *scenarios], rows) + "\n\n" + spread_words(spread))


TABLES = {"budget": budget_markdown, "fronts": fronts_markdown, "equal-effort": equal_effort_markdown}


def markdown_table(folders: Sequence[str | Path], table: str) -> str:
    paths = [Path(f) for f in folders]
    for p in paths:
        if not p.is_dir():
            raise ValueError(f"argument 'folders': {p} is not a tuning folder")
    if table == "spread":
        if len({p.name for p in paths}) != len(paths):
            raise ValueError("argument 'folders': a seed spread names each seed by its folder's name; "
                             f"these repeat one: {', '.join(map(str, paths))}")
        return spread_markdown(paths)
    if table not in TABLES:
        raise ValueError(f"argument 'table': expected one of {', '.join([*TABLES, 'spread'])}, got {table!r}")
    if len(paths) != 1:
        raise ValueError(f"argument 'folders': the {table!r} table reads one tuning folder, got {len(paths)}")
    return TABLES[table](paths[0])


def main_table(folders: Sequence[str], table: str) -> int:
    print(markdown_table(folders, table))
    return 0
