"""How often the 95 % intervals of ``neurov identify`` cover the truth:
runs of a shipped excitation scenario on a vehicle that differs from the
template (damping +40 %, added mass -30 %), each with its own noise seed,
each fitted, and the fraction of (run, parameter) pairs whose interval holds
the true value printed (docs/identification.md quotes its output).

    PYTHONPATH=python python examples/identify_coverage.py bluerov2 --runs 10 --duration 60
    PYTHONPATH=python python examples/identify_coverage.py bluerov2 --realistic --runs 5
    PYTHONPATH=python python examples/identify_coverage.py bluerov2 --realistic --velocity-lag auto --estimator off

Without --realistic the measurement is the true state plus white noise
(``[noise]``: 0.01 m/s on u, v, w, 0.002 on the rates and angles); with it,
the scenario's sensors, EKF and one-period delay; the EKF's updates are
modelled in the output error unless --estimator off (--velocity-lag auto
estimates a lag instead). --true rates|attitude|linear|rotation|all gives
the fit the true values of those signals in place of the EKF's, to find
which signal a bias comes from; --no-depth runs without the depth sensor:

    PYTHONPATH=python python examples/identify_coverage.py nerov --realistic --runs 3 --duration 60 --estimator linear --true rates
"""

from __future__ import annotations

import argparse

import numpy as np

import neurov
from neurov.identification import make_log
from neurov.study.spec import SCENARIO_DIR
from neurov.config.vehicle_file import preset_path, read_vehicle_file

PRESETS = {"bluerov2": "bluerov2_heavy", "nerov": "nerov"}
# --true: the (array, columns) of the run taken from the truth instead of the estimate.
TRUE = {"rates": [("nu", slice(3, 6))], "attitude": [("eta", slice(3, 6))],
        "linear": [("nu", slice(0, 3))], "rotation": [("nu", slice(3, 6)), ("eta", slice(3, 6))],
        "all": [("nu", slice(0, 6)), ("eta", slice(0, 6))]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("vehicle", choices=sorted(PRESETS))
    p.add_argument("--runs", type=int, default=10)
    p.add_argument("--duration", type=float, default=60.0)
    p.add_argument("--realistic", action="store_true")
    p.add_argument("--noise", type=float, default=0.01)
    p.add_argument("--velocity-lag", default="0", metavar="SECONDS|auto",
                   help="passed to neurov.identify (the EKF's velocity lag; 'auto' estimates it)")
    p.add_argument("--estimator", choices=("auto", "on", "off", "linear"), default="auto",
                   help="passed to neurov.identify: model the EKF's updates in the output error "
                        "(linear: the DVL's staircase, not the rates' filter)")
    p.add_argument("--no-depth", action="store_true",
                   help="with --realistic, run without the depth sensor (whose updates move the EKF's "
                        "velocity between the DVL's)")
    p.add_argument("--true", choices=sorted(TRUE), default=None,
                   help="give the fit the true values of these signals instead of the estimate's "
                        "(which signal of the estimate a bias comes from)")
    a = p.parse_args()
    if a.no_depth and not a.realistic:
        p.error("--no-depth: only with --realistic (the white-noise runs have no sensors)")
    template = read_vehicle_file(preset_path(PRESETS[a.vehicle]))
    q = template.parameters
    over = {"linear_damping": [1.4 * x for x in q["linear_damping"]],
            "quadratic_damping": [1.4 * x for x in q["quadratic_damping"]],
            "added_mass": [0.7 * x for x in q["added_mass"]]}
    truth = np.asarray(neurov.regressor_parameters(template.vehicle(over)))
    name = f"{a.vehicle}_excitation{'_realistic' if a.realistic else ''}.toml"
    lag = a.velocity_lag if a.velocity_lag == "auto" else float(a.velocity_lag)
    hits = []
    errors = []
    widths = []
    for seed in range(a.runs):
        s = neurov.load_scenario(SCENARIO_DIR / name)
        s.duration, s.seed, s.vehicle_parameters = a.duration, seed, over
        if a.no_depth:
            s.simulation.sensors.depth = None
        if not a.realistic:
            s.noise_nu = np.array([a.noise] * 3 + [a.noise / 5] * 3)
            s.noise_eta = np.array([0.0] * 3 + [a.noise / 5] * 3)
        r = neurov.simulate(s)
        eta, nu = np.array(r.eta_estimate), np.array(r.nu_estimate)
        for array, rows in TRUE.get(a.true, ()):
            (eta if array == "eta" else nu)[:, rows] = getattr(r, array)[:, rows]
        log = make_log("run", r.t, eta, nu, np.asarray(r.tau_applied) + np.asarray(r.disturbance), r.current)
        fit = neurov.identify(log, preset_path(PRESETS[a.vehicle]), velocity_lag=lag,
                              estimator={"auto": "auto", "on": True, "off": False,
                                         "linear": "linear"}[a.estimator])
        lo, hi = fit.interval[fit.fitted].T
        inside = (lo <= truth[fit.fitted]) & (truth[fit.fitted] <= hi)
        hits.append(inside)
        errors.append((fit.theta - truth)[fit.fitted])
        widths.append(hi - lo)
        print(f"seed {seed}: {inside.sum()} of {inside.size} intervals cover the truth"
              + "".join(f"; {w}" for w in fit.warnings if "velocity lag" in w or "staircase" in w), flush=True)
    hits_a, err = np.array(hits), np.array(errors)
    print(f"coverage: {hits_a.mean():.3f} over {hits_a.size} intervals ({a.runs} runs of {a.duration:g} s)")
    names = [neurov.THETA_NAMES[i] for i in fit.fitted]
    scale = np.maximum(np.abs(truth[fit.fitted]), 1e-12)
    # width: the intervals' mean width over 2 x 1.96 standard deviations of
    # the estimates across runs (1 if the intervals are as wide as the spread);
    # bias: the mean error in those standard deviations (what a width of 1
    # cannot cover).
    spread = err.std(axis=0, ddof=1) if a.runs > 1 else np.full(err.shape[1], np.nan)
    sd = np.where(spread > 0, spread, np.nan)
    ratio = np.array(widths).mean(axis=0) / (2 * 1.96 * sd)
    bias = err.mean(axis=0) / sd
    for n, c, e, sc, w, b in zip(names, hits_a.mean(axis=0), err.mean(axis=0), scale, ratio, bias):
        head = f"  {n:<10} coverage {c:.2f}  width {w:.2f}  bias {b:+.2f} sd  mean error {e:+.4g}"
        print(head + (f" ({100 * e / sc:+.1f} % of the true value)" if sc > 1e-12 else " (true value 0)"))


if __name__ == "__main__":
    main()
