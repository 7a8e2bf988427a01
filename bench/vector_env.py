"""Env-steps per second of neurov.gym.TrackingVectorEnv (one batch of K runs,
random actions drawn beforehand, autoresets included) against gymnasium's
SyncVectorEnv over K single TrackingEnvs, in the same run; with --scaling,
the vector env's rate from 1 to 4096 envs and a log-log plot.

    python bench/vector_env.py [--scenario paper_fig3] [--envs 256] [--steps 400]
        [--sync-steps 40 (0: none)] [--scaling] [--plot docs/images/vector_env_scaling.png] [--json out.json]

Prints env-steps per second (K times vector steps per second), the median
of --repeats timings, and the ratio to SyncVectorEnv. --table prints the
scaling of runs written with --json as a Markdown table (env-steps per
second and, in brackets, the time of one vector step).
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
from neurov.gym import TrackingEnv, TrackingVectorEnv

SCALING = (1, 4, 16, 64, 256, 1024, 4096)


def rate(envs: Any, steps: int, repeats: int) -> float:
    """Median env-steps per second over `repeats` runs of `steps` vector steps."""
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, *envs.action_space.shape)).astype(np.float32)
    rates = []
    for _ in range(repeats):
        envs.reset(seed=0)
        t0 = time.perf_counter()
        for a in actions:
            envs.step(a)
        rates.append(envs.num_envs * steps / (time.perf_counter() - t0))
    return float(np.median(rates))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="paper_fig3")
    p.add_argument("--envs", type=int, default=256)
    p.add_argument("--steps", type=int, default=400, help="vector steps per timing")
    p.add_argument("--sync-steps", type=int, default=40,
                   help="SyncVectorEnv steps per timing (0: no SyncVectorEnv)")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--scaling", action="store_true", help=f"also time K = {', '.join(map(str, SCALING))}")
    p.add_argument("--plot", type=Path, help="the scaling plot (PNG), with --scaling or --table")
    p.add_argument("--json", type=Path, help="also write the figures to this file")
    p.add_argument("--table", type=Path, nargs="+", metavar="JSON",
                   help="print the scaling of these --json files (each with --scaling) as a Markdown table, "
                        "one column a file (with --plot: plot the last file's), and exit")
    args = p.parse_args()
    if args.table:
        print(table(args.table))
        if args.plot:  # the last file's scaling
            last = json.loads(args.table[-1].read_text())
            plot({int(n): v for n, v in last["scaling"].items()}, last.get("sync_vector_env_steps_per_s", 0.0),
                 last["envs"], args.plot)
        return

    k = args.envs
    vec = TrackingVectorEnv(k, args.scenario)
    vector_rate = rate(vec, args.steps, args.repeats)
    out: dict[str, Any] = {
        "scenario": args.scenario, "envs": k, "batch": type(vec._batch).__name__,
        "vector_env_steps_per_s": vector_rate, "python": platform.python_version(), "numpy": np.__version__,
        "gymnasium": gymnasium.__version__,
    }
    said = (f"TrackingVectorEnv ({args.scenario}, {k} envs, batch {out['batch']}): {vector_rate:,.0f} env-steps/s "
            f"({1e6 * k / vector_rate:.2f} us a vector step)")
    sync_rate = 0.0
    if args.sync_steps > 0:
        sync = gymnasium.vector.SyncVectorEnv([lambda: TrackingEnv(args.scenario) for _ in range(k)])
        sync_rate = rate(sync, args.sync_steps, args.repeats)
        out.update(sync_vector_env_steps_per_s=sync_rate, ratio=vector_rate / sync_rate)
        said += f"; SyncVectorEnv over {k} TrackingEnv: {sync_rate:,.0f} env-steps/s; ratio {out['ratio']:.1f}x"
    print(said)
    if args.scaling:
        out["scaling"] = {}
        for n in SCALING:
            # About the same work per timing at every K (at least 20 vector steps).
            steps = max(20, args.steps * k // n)
            out["scaling"][n] = rate(TrackingVectorEnv(n, args.scenario), steps, args.repeats)
            print(f"  K = {n:5d}: {out['scaling'][n]:12,.0f} env-steps/s")
        if args.plot:
            plot(out["scaling"], sync_rate, k, args.plot)
    if args.json:
        args.json.write_text(json.dumps(out, indent=2))


def table(paths: list[Path]) -> str:
    """The env-steps per second of each file's scaling, by K, and what one
    vector step takes [us] (Markdown)."""
    runs = [json.loads(p.read_text()) for p in paths]
    names = [p.stem for p in paths]
    lines = ["| K | " + " | ".join(names) + " |", "|---:|" + "---:|" * len(runs)]
    for k in sorted({int(n) for r in runs for n in r["scaling"]}):
        cells = []
        for r in runs:
            v = r["scaling"].get(str(k))
            cells.append("" if v is None else f"{v:,.0f} ({1e6 * k / v:,.1f} µs)")
        lines.append(f"| {k:,} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(scaling: dict[int, float], sync_rate: float, k: int, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    ns, rates = zip(*sorted(scaling.items()))
    ax.loglog(ns, rates, marker="o", label="TrackingVectorEnv")
    if sync_rate > 0:
        ax.loglog([k], [sync_rate], marker="s", linestyle="none", label=f"SyncVectorEnv over {k} TrackingEnv")
    ax.axhline(1e6, color="grey", linestyle=":", label="target: 10^6 env-steps/s")
    ax.set_xlabel("envs K")
    ax.set_ylabel("env-steps per second")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
