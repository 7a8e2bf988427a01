"""How the paper's NN controller depends on the settings the paper leaves open
or states: K_d, gamma, the width sigma, the number of centres N, and what the
network actually learns with sigma = 30. Prints Markdown tables; the tables of
docs/paper-reproduction.md are its output, one section each:

    python examples/paper_sensitivity.py                      # every section
    python examples/paper_sensitivity.py --section width      # one: kd_gamma, width or learns
    python examples/paper_sensitivity.py --out sensitivity.md # also write the tables to a file

Runs from anywhere (a copy of examples/ alone will do): it needs only the
installed neurov. The time it took goes to stderr, so that stdout is the same
on every run.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

import neurov
from neurov.laws.registry import build_controller
from neurov.paper.experiments import paper_scenario

HEAD = ("| setting | RMS position [m] | RMS yaw [deg] | max abs tau [N, N m] | max norm of W |\n"
        "|---|---|---|---|---|")


def row(label: str, result: neurov.Result) -> str:
    """One table row: the metrics over t >= 10 s (neurov's default window)."""
    m = result.metrics()
    status = "diverged" if m["diverged"] else f"{m['max_adaptive_norm']:.1f}"
    return (f"| {label} | {m['rmse_position_m']:.4f} | {math.degrees(m['rmse_yaw_rad']):.3f} | "
            f"{m['max_abs_tau']:.0f} | {status} |")


def kd_gamma(scenario: neurov.Scenario) -> list[str]:
    base = scenario.controller
    kd = np.array(base.kd)
    lines = [HEAD]
    for scale in (0.0, 0.25, 1.0, 2.0):
        for gamma in (0.3, 3.0, 30.0):
            spec = base.replace(kd=kd * scale, gamma=gamma)
            lines.append(row(f"K_d = {scale:g} x ours, gamma = {gamma:g}", neurov.simulate(scenario, spec)))
    return lines


def width(scenario: neurov.Scenario) -> list[str]:
    base = scenario.controller
    lines = [HEAD]
    for sigma in (1.0, 3.0, 10.0, 30.0, 100.0):
        lines.append(row(f"sigma = {sigma:g}", neurov.simulate(scenario, base.replace(width=sigma))))
    for n in (16, 64, 256, 1024):
        spec = base.replace(centres={"method": "sobol", "n": n, "seed": 1})
        lines.append(row(f"N = {n}", neurov.simulate(scenario, spec)))
    lines.append(row("gamma = 0 (no learning)", neurov.simulate(scenario, base.replace(gamma=0.0))))
    return lines


def learns(scenario: neurov.Scenario) -> list[str]:
    base = scenario.controller
    result = neurov.simulate(scenario, base)
    controller = build_controller(base, scenario)
    basis = []
    for k in range(len(result.t)):
        controller.step(result.eta[k], result.nu[k], result.eta_d[k], result.eta_d_dot[k], np.zeros(6))
        basis.append(np.array(controller.basis, copy=True))
    g = np.array(basis)
    gain = base.gamma * float(np.sum(g.mean(axis=0) ** 2))
    one = base.replace(centres=np.zeros((1, 24)), gamma=gain)
    return [f"Along the run every basis value g_j stays in [{g.min():.3f}, {g.max():.3f}]; "
            f"each centre's value moves by {np.mean(g.max(0) - g.min(0)):.3f} on average.", "",
            HEAD, row("N = 64 Sobol centres (the paper's set-up)", result),
            row(f"N = 1 centre at 0, gamma = {gain:.2f} (an adaptive bias)", neurov.simulate(scenario, one))]


SECTIONS = {"kd_gamma": ("K_d and gamma (sigma = 30, N = 64)", kd_gamma),
            "width": ("Width sigma and number of centres N (gamma = 0.3, our K_d)", width),
            "learns": ("What the network learns with sigma = 30", learns)}


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--section", choices=sorted(SECTIONS), default=None, help="print one section only, untitled")
    p.add_argument("--out", type=Path, default=None, metavar="FILE", help="also write the tables to FILE")
    a = p.parse_args(argv)
    start = time.perf_counter()
    scenario = paper_scenario("paper_fig3")
    if a.section:
        text = "\n".join(SECTIONS[a.section][1](scenario)) + "\n"
    else:
        text = "\n".join(f"### {title}\n\n" + "\n".join(make(scenario)) + "\n" for title, make in SECTIONS.values())
    print(text, end="")
    if a.out is not None:
        a.out.write_text(text)
        print(f"wrote {a.out}", file=sys.stderr)
    print(f"(all runs: {time.perf_counter() - start:.1f} s)", file=sys.stderr)


if __name__ == "__main__":
    main()
