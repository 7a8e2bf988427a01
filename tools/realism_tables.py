"""The realism study's tables for docs/studies.md ("Ideal and realistic"),
from its runs kept under docs/data/: ideal against realistic, the cost of
each part (the delay alone, the EKF alone) and the tethered square.

    python tools/realism_tables.py docs/data/realism docs/data/realism_parts --table medians
    python tools/realism_tables.py docs/data/realism docs/data/realism_parts --table cost|failed|versus
    python tools/realism_tables.py docs/data/realism --table tether

The first folder holds ``neurov study realism``'s runs, the second (for the
parts) those of ``python tools/realism_parts.py``: the same plants with each
disturbed scenario given only the delay (``*_delay_only``) and each
realistic one without it (``*_ekf_only``). A run's value is its RMS position
error, infinite when the run diverged; ratios are paired on the plant, as a
study's head to head pairs them (neurov.study.statistics.ratio). Failure
rates and counts follow the study's failure rule.
"""

from __future__ import annotations

import argparse
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pandas as pd

from neurov.study import load_study
from neurov.study.statistics import ratio
from neurov.study.tables import failed_runs, read_table

METRIC = "rmse_position_m"
VARIANTS = {"disturbed": "ideal", "realistic": "realistic", "delay_only": "delay", "ekf_only": "ekf"}
VEHICLES = {"nerov": "NEROV", "bluerov2": "BlueROV2 Heavy"}
PATHS = {"square": "square", "helix": "helix", "lawnmower": "lawnmower", "depth_step": "depth steps",
         "heading_step": "heading steps"}
#: The head-to-head comparisons of the page: A against B.
VERSUS = (("nn", "linear"), ("nn", "linear_nominal"), ("nn", "pid"), ("smc", "nn"), ("smc", "pid"),
          ("super_twisting", "smc"), ("super_twisting", "pid"))


@lru_cache(maxsize=1)
def _study():  # type: ignore[no-untyped-def]
    return load_study("realism")


def _runs(folders: list[Path]) -> pd.DataFrame:
    study = _study()
    frames = []
    for folder in folders:
        name = "runs.csv" if (folder / "runs.csv").is_file() else "runs.csv.gz"
        frames.append(read_table(folder / name))
    runs = pd.concat(frames, ignore_index=True)
    runs["failed"] = failed_runs(runs, study.failure).to_numpy()
    # A run stopped as diverged has no finite error: it counts as infinitely bad (as in a study's head to head).
    runs["value"] = runs[METRIC].astype(float).fillna(np.inf)
    parts = runs["scenario"].str.extract(r"^(nerov|bluerov2)_(.*?)_(disturbed|realistic|delay_only|ekf_only|tether)$")
    return runs.assign(veh=parts[0], path=parts[1], variant=parts[2].map(VARIANTS).fillna(parts[2]))


def _label(c: str) -> str:
    return _study().label(c)


def _controllers(runs: pd.DataFrame) -> list[str]:
    return [c for c in _study().controllers if c in set(runs["controller"])]


def _num(x: float) -> str:
    return "inf" if not np.isfinite(x) else f"{x:.3f}"


def _failed_pct(runs: pd.DataFrame) -> float:
    return 100.0 * float(runs["failed"].mean())


def medians(runs: pd.DataFrame) -> str:
    """Per vehicle: the median RMS position error per path, ideal -> realistic
    (failure rates where not 0 %), and the mean rank by median."""
    out = ["Median RMS position error [m] over the plants, ideal → realistic (the failure rate where it "
           "is not 0 % in either); mean rank by median among the controllers over the five paths.", ""]
    for veh, title in VEHICLES.items():
        sub = runs[(runs.veh == veh) & runs.variant.isin(["ideal", "realistic"])]
        paths = [p for p in PATHS if p in set(sub.path)]
        med = sub.groupby(["path", "variant", "controller"])["value"].median()
        fail = sub.groupby(["path", "variant", "controller"])["failed"].mean()
        rank = med.groupby(["path", "variant"]).rank(method="min")
        cs = _controllers(sub)
        out += [f"| {title} | " + " | ".join(PATHS[p] for p in paths) + " | mean rank ideal → realistic |",
                "|---|" + "---|" * (len(paths) + 1)]
        for c in cs:
            cells = []
            for p in paths:
                a, b = med[(p, "ideal", c)], med[(p, "realistic", c)]
                fa, fb = fail[(p, "ideal", c)], fail[(p, "realistic", c)]
                f = f" ({100 * fa:.0f} → {100 * fb:.0f} % fail)" if fa or fb else ""
                cells.append(f"{_num(a)} → {_num(b)}{f}")
            ri, rr = rank[:, "ideal", c].mean(), rank[:, "realistic", c].mean()
            out.append(f"| {_label(c)} | " + " | ".join(cells) + f" | {ri:.1f} → {rr:.1f} of {len(cs)} |")
        out.append("")
    return "\n".join(out)


def _paired(runs: pd.DataFrame, veh: str, c: str, variant: str, against: str = "ideal") -> np.ndarray:
    """Per plant and path of `veh`: `variant`'s value / `against`'s, paired."""
    sub = runs[(runs.veh == veh) & (runs.controller == c)]
    wide = sub.pivot_table(index=["path", "sample"], columns="variant", values="value", aggfunc="first")
    if variant not in wide or against not in wide:
        return np.array([])
    return np.array([ratio(x, y) for x, y in zip(wide[variant], wide[against], strict=True)])


def cost(runs: pd.DataFrame) -> str:
    """The median over a vehicle's plants (all five paths) of the paired
    ratio variant / ideal, for each part and both together."""
    have = [v for v in ("delay", "ekf", "realistic") if v in set(runs.variant)]
    names = {"delay": "delay alone", "ekf": "EKF alone", "realistic": "both (realistic)"}
    head = [f"{VEHICLES[veh]}: {names[v]}" if i == 0 else names[v]
            for veh in VEHICLES for i, v in enumerate(have)]
    n = {veh: len(_paired(runs, veh, _controllers(runs)[0], "realistic")) for veh in VEHICLES}
    out = [f"Median over the plants of a vehicle ({', '.join(f'{k} on {VEHICLES[v]}' for v, k in n.items())}: "
           "the paths × the samples) of the paired ratio of RMS position errors, variant / ideal "
           "(a run that diverged counting as infinitely bad; more than 1.0 is worse):", "",
           "| controller | " + " | ".join(head) + " |", "|---|" + "---|" * len(head)]
    for c in _controllers(runs):
        cells = [f"{np.median(_paired(runs, veh, c, v)):.2f}" for veh in VEHICLES for v in have]
        out.append(f"| {_label(c)} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def failed(runs: pd.DataFrame) -> str:
    """Failed runs per vehicle, controller and variant."""
    have = [v for v in ("ideal", "delay", "ekf", "realistic") if v in set(runs.variant)]
    names = {"ideal": "ideal", "delay": "delay alone", "ekf": "EKF alone", "realistic": "realistic"}
    out = []
    for veh, title in VEHICLES.items():
        sub = runs[(runs.veh == veh) & runs.variant.isin(have)]
        count = sub.groupby(["controller", "variant"])["failed"].sum()
        n = int(sub.groupby(["controller", "variant"]).size().max())
        out += [f"| {title}: failed runs of {n} | " + " | ".join(names[v] for v in have) + " |",
                "|---|" + "---|" * len(have)]
        out += [f"| {_label(c)} | " + " | ".join(str(int(count.get((c, v), 0))) for v in have) + " |"
                for c in _controllers(sub)]
        out.append("")
    return "\n".join(out)


def versus(runs: pd.DataFrame) -> str:
    """A against B on the same plants over a vehicle's five paths, ideal ->
    realistic: in how many A's error is lower, and the median of A / B."""
    out = ["| A against B | " + " | ".join(VEHICLES.values()) + " |", "|---|" + "---|" * len(VEHICLES)]
    for a, b in VERSUS:
        cells = []
        for veh in VEHICLES:
            wins, meds, n = [], [], 0
            for v in ("ideal", "realistic"):
                sub = runs[(runs.veh == veh) & (runs.variant == v)]
                wide = sub.pivot_table(index=["path", "sample"], columns="controller", values="value", aggfunc="first")
                r = np.array([ratio(x, y) for x, y in zip(wide[a], wide[b], strict=True)])
                wins.append(int((r < 1).sum()))
                meds.append(f"{np.median(r):.2f}")
                n = len(r)
            cells.append(f"{wins[0]} → {wins[1]} of {n}; {meds[0]} → {meds[1]}")
        out.append(f"| {_label(a)} against {_label(b)} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def tether(runs: pd.DataFrame) -> str:
    """BlueROV2 Heavy's realistic square against the same on its tether."""
    sub = runs[(runs.veh == "bluerov2") & (runs.path == "square") & runs.variant.isin(["realistic", "tether"])]
    if "tether" not in set(sub.variant):
        raise SystemExit("--table tether: no bluerov2_square_tether runs in the folders given")
    out = ["| controller | median, realistic → tether [m] | paired ratio tether / realistic | failed, realistic → tether |",
           "|---|---|---|---|"]
    for c in _controllers(sub):
        one = sub[sub.controller == c]
        med = one.groupby("variant")["value"].median()
        fails = one.groupby("variant")["failed"].sum()
        n = int(one.groupby("variant").size().max())
        r = np.median(_paired(runs[runs.path == "square"], "bluerov2", c, "tether", "realistic"))
        out.append(f"| {_label(c)} | {_num(med['realistic'])} → {_num(med['tether'])} | {r:.3f} | "
                   f"{int(fails['realistic'])} → {int(fails['tether'])} of {n} |")
    return "\n".join(out) + "\n"


TABLES = {"medians": medians, "cost": cost, "failed": failed, "versus": versus, "tether": tether}


def main(args: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("folders", nargs="+", type=Path, help="the realism study's folder, then the parts' folder")
    p.add_argument("--table", choices=sorted(TABLES), required=True, help="which table")
    a = p.parse_args(args)
    for folder in a.folders:
        if not (folder / "runs.csv").is_file() and not (folder / "runs.csv.gz").is_file():
            p.error(f"{folder}: no runs.csv or runs.csv.gz")
    print(TABLES[a.table](_runs(a.folders)), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
