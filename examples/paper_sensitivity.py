"""How the paper's NN controller depends on the settings the paper leaves open
or states: K_d, gamma, the width sigma, the number of centres N, and what the
network actually learns with sigma = 30. Prints Markdown tables (quoted in
docs/paper-reproduction.md).

    python examples/paper_sensitivity.py
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from neurov.paper.experiments import TRANSIENT, paper_scenario
from neurov.laws.registry import build_controller
from neurov.running.simulation import simulate


def row(label: str, result) -> str:  # type: ignore[no-untyped-def]
    m = result.metrics(after=TRANSIENT)
    status = "diverged" if m["diverged"] else f"{m['max_adaptive_norm']:.1f}"
    return (f"| {label} | {m['rmse_position_m']:.4f} | {m['rmse_yaw_rad']:.4f} | "
            f"{m['max_abs_tau']:.0f} | {status} |")


HEAD = ("| setting | RMS position [m] | RMS yaw [rad] | max abs tau | max norm of W |\n"
        "|---|---|---|---|---|")


def main() -> None:
    start = time.perf_counter()
    scenario = paper_scenario("paper_fig3")
    base = scenario.controller
    kd = np.array(base.kd)

    print("### K_d and gamma (sigma = 30, N = 64)\n")
    print(HEAD)
    for scale in (0.0, 0.25, 1.0, 2.0):
        for gamma in (0.3, 3.0, 30.0):
            spec = dataclasses.replace(base, kd=kd * scale, gamma=gamma)
            print(row(f"K_d = {scale:g} x ours, gamma = {gamma:g}", simulate(scenario, spec)))

    print("\n### Width sigma and number of centres N (gamma = 0.3, our K_d)\n")
    print(HEAD)
    for width in (1.0, 3.0, 10.0, 30.0, 100.0):
        spec = dataclasses.replace(base, width=width)
        print(row(f"sigma = {width:g}", simulate(scenario, spec)))
    for n in (16, 64, 256, 1024):
        spec = dataclasses.replace(base, centres={"method": "sobol", "n": n, "seed": 1})
        print(row(f"N = {n}", simulate(scenario, spec)))
    print(row("gamma = 0 (no learning)", simulate(scenario, dataclasses.replace(base, gamma=0.0))))

    print("\n### What the network learns with sigma = 30\n")
    result = simulate(scenario, base)
    controller = build_controller(base, scenario)
    basis = []
    for k in range(len(result.t)):
        controller.step(result.eta[k], result.nu[k], result.eta_d[k], result.eta_d_dot[k], np.zeros(6))
        basis.append(controller.basis.copy())
    g = np.array(basis)
    print(f"Along the run every basis value g_j stays in [{g.min():.3f}, {g.max():.3f}]; "
          f"each centre's value moves by {np.mean(g.max(0) - g.min(0)):.3f} on average.\n")
    gain = base.gamma * float(np.sum(g.mean(axis=0) ** 2))
    one = dataclasses.replace(base, centres=np.zeros((1, 24)), gamma=gain)
    print(HEAD)
    print(row("N = 64 Sobol centres (the paper's set-up)", result))
    print(row(f"N = 1 centre at 0, gamma = {gain:.2f} (an adaptive bias)", simulate(scenario, one)))
    print(f"\n(all runs: {time.perf_counter() - start:.1f} s)")


if __name__ == "__main__":
    main()
