"""NN controller step time against the number of centres N, log-log, from a
Google Benchmark JSON file of neurov_bench:

    build/bench/neurov_bench --benchmark_filter='BM_NNStep<' \\
        --benchmark_repetitions=5 --benchmark_out=nn_step.json --benchmark_out_format=json
    python bench/plot_scaling.py nn_step.json --out docs/images/nn_step_scaling.png

Plots the median CPU time per step for double and float with a line of
slope 1 (time proportional to N) through the double point at N = 256.
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

_NAME = re.compile(r"BM_NNStep<(double|float)>/(\d+)")
_TO_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def load(path: Path) -> dict[str, dict[int, float]]:
    """Median CPU ns per step by scalar and N (the aggregate 'median' rows if
    the run had repetitions, else the single rows)."""
    data = json.loads(path.read_text())
    rows: dict[str, dict[int, list[float]]] = defaultdict(lambda: defaultdict(list))
    have_median = any(b.get("aggregate_name") == "median" for b in data["benchmarks"])
    for b in data["benchmarks"]:
        m = _NAME.match(b.get("run_name", b["name"]))
        if not m:
            continue
        if have_median and b.get("aggregate_name") != "median":
            continue
        if not have_median and b.get("run_type") == "aggregate":
            continue
        rows[m.group(1)][int(m.group(2))].append(b["cpu_time"] * _TO_NS[b.get("time_unit", "ns")])
    return {s: {n: statistics.median(v) for n, v in sorted(d.items())} for s, d in rows.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("json", type=Path)
    ap.add_argument("--out", type=Path, default=Path("nn_step_scaling.png"))
    args = ap.parse_args()
    series = load(args.json)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for scalar, marker in (("double", "o"), ("float", "s")):
        if scalar in series:
            ns, ts = zip(*series[scalar].items())
            ax.loglog(ns, ts, marker=marker, label=f"{scalar}")
            for n, t in zip(ns, ts):
                print(f"{scalar:6s} N = {n:5d}: {t:9.1f} ns  ({t / n:.2f} ns per centre)")
    if "double" in series and 256 in series["double"]:
        ns = sorted(series["double"])
        t256 = series["double"][256]
        ax.loglog(ns, [t256 * n / 256 for n in ns], "k:", lw=1, label="slope 1 (time ~ N)")
    ax.axhline(1000, color="grey", lw=0.8, ls="--")
    ax.text(16, 1080, "1 us", color="grey", fontsize=8)
    ax.set_xlabel("centres N")
    ax.set_ylabel("CPU time per step [ns]")
    ax.set_title("NN controller step (24 inputs, 6 outputs), neurov_bench")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
