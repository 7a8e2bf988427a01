"""The rank of the NN controller's basis along paper_fig3: the paper's
network (64 Sobol centres in the scenario's box, width 30, inputs in SI
units) against the same network with its 64 centres along the commanded
path (``centres.method = "path"``), at the paper's width and at narrower
ones. Prints one row per network: the basis values' range, sigma2/sigma1
and the effective rank of the (steps x centres) basis matrix, and the RMS
position error of the run.

    PYTHONPATH=python python bench/basis_rank_path.py
"""

from __future__ import annotations

import neurov
from neurov.config.scenario import scenario_path
from neurov.laws.registry import build_controller
from neurov.study.basis_rank import BasisRecorder, rank_diagnostic


def row(scenario: neurov.Scenario, label: str, centres: dict, width: float) -> str:
    spec = scenario.controller.replace(width=width)
    spec.centres = centres
    recorder = BasisRecorder(build_controller(spec, scenario))
    result = neurov.simulate(scenario, recorder)
    d = rank_diagnostic(recorder.matrix())
    rmse = result.metrics()["rmse_position_m"]
    return (f"| {label} | {width:g} | {d['min']:.3f}–{d['max']:.3f} | {d['sigma2_ratio']:.3f} | "
            f"{d['effective_rank']:.2f} | {rmse:.3f} |")


def main() -> None:
    sc = neurov.load_scenario(scenario_path("paper_fig3"))
    print("| centres | width | basis values | σ₂/σ₁ | effective rank | RMS position error [m] |")
    print("|---|---|---|---|---|---|")
    for width in (30.0, 3.0, 1.0):
        print(row(sc, "64 Sobol in the box (paper_fig3's)", dict(sc.controller.centres), width))
        print(row(sc, "64 along the commanded path", {"method": "path", "n": 64, "seed": 1}, width))


if __name__ == "__main__":
    main()
