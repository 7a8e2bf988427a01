"""A tuning's rankings over several tuning seeds: the same file tuned once
per seed (``neurov tune FILE --seed N --out DIR/seedN``), each verdict's
ranks per scenario, how often each held, and whether the order is settled."""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from pathlib import Path

import pandas as pd

__all__ = ["rank_spread", "seed_ranks", "spread_words"]


def _verdict_ranks(folder: Path) -> pd.DataFrame:
    """One folder's ranks: equal_effort.csv (two objectives: the controllers
    read at equal effort), else the tuned rows of verdict/summary.csv."""
    folder = Path(folder)
    if (folder / "equal_effort.csv").exists():
        t = pd.read_csv(folder / "equal_effort.csv")
    else:
        t = pd.read_csv(folder / "verdict" / "summary.csv")
        t = t[~t["controller"].str.endswith("_hand_set")]
    return t[["scenario", "controller", "rank", "median"]]


def seed_ranks(folders: Sequence[str | Path]) -> pd.DataFrame:
    """Per seed (its folder's name), scenario and controller: the rank and median."""
    frames = []
    for f in folders:
        t = _verdict_ranks(Path(f))
        t.insert(0, "seed", Path(f).name)
        frames.append(t)
    if not frames:
        raise ValueError("argument 'folders': expected at least one tuning folder")
    return pd.concat(frames, ignore_index=True)


def rank_spread(folders: Sequence[str | Path]) -> pd.DataFrame:
    """Per scenario and controller: its rank in each seed (in the folders'
    order), the most frequent rank and in how many seeds it held."""
    ranks = seed_ranks(folders)
    seeds = list(dict.fromkeys(ranks["seed"]))
    rows = []
    for (scenario, controller), g in ranks.groupby(["scenario", "controller"], sort=False):
        by_seed = dict(zip(g["seed"], g["rank"].astype(int)))
        held = Counter(by_seed.values()).most_common()
        top = min(r for r, n in held if n == held[0][1])  # of equally frequent ranks, the best
        rows.append({"scenario": scenario, "controller": controller,
                     "ranks": " ".join(str(by_seed.get(s, "-")) for s in seeds), "modal_rank": top,
                     "held": sum(1 for r in by_seed.values() if r == top), "seeds": len(seeds)})
    return pd.DataFrame(rows)


def spread_words(spread: pd.DataFrame) -> str:
    """Per scenario: settled when every controller kept its rank in every
    seed, otherwise which controllers moved; then which held rank 1 throughout."""
    said = []
    unsettled = []
    for scenario, g in spread.groupby("scenario", sort=False):
        moved = g[g["held"] < g["seeds"]]
        if len(moved):
            unsettled.append(f"{scenario} ({', '.join(moved['controller'])} moved)")
    n = int(spread["seeds"].max())
    firsts = spread[(spread["modal_rank"] == 1) & (spread["held"] == spread["seeds"])]
    if unsettled:
        said.append(f"Over {n} tuning seeds the order is not settled on {len(unsettled)} of "
                    f"{spread['scenario'].nunique()} scenarios: " + "; ".join(unsettled) + ".")
    else:
        said.append(f"Over {n} tuning seeds every controller kept its rank on every scenario: the order is "
                    "settled.")
    kept = Counter(firsts["controller"])
    if kept:
        said.append("Rank 1 in every seed: " + ", ".join(f"{c} on {k} scenario(s)" for c, k in kept.items()) + ".")
    else:
        said.append("No controller held rank 1 in every seed on any scenario.")
    changed = []
    for scenario, g in spread.groupby("scenario", sort=False):
        if (g["modal_rank"].eq(1) & g["held"].eq(g["seeds"])).any():
            continue
        tops = [(c, sum(r == "1" for r in ranks.split())) for c, ranks in zip(g["controller"], g["ranks"])]
        tops = sorted((t for t in tops if t[1]), key=lambda t: -t[1])
        changed.append(f"{scenario}: " + ", ".join(f"{c} in {k} of {n} seeds" for c, k in tops))
    if changed:
        said.append("Rank 1 changed with the seed on " + "; ".join(changed) + ": not settled.")
    return " ".join(said)
