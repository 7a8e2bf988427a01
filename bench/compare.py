"""neurov against a plain numpy implementation of the same equations
(bench/numpy_baseline.py), on the same inputs, in one run:

  1. the two closed loops side by side, to show they compute the same thing;
  2. the NN controller step: numpy per call, neurov per call from Python, and
     neurov inside a C++ loop (timed in C++);
  3. one plant evaluation (nu_dot of NEROV), the same three ways;
  4. a whole closed loop (NEROV, NN with N = 64, 600 s at 5 Hz, 10 RK4
     substeps) as a real-time factor, simulated seconds per wall second;
  5. multi-run throughput: a Monte-Carlo batch of closed loops with perturbed
     vehicles and noise seeds on 1 and 2 threads (run_closed_loop releases
     the GIL), in runs per second.

    python bench/compare.py            # the full run (about a minute)
    python bench/compare.py --quick    # CI smoke test (a few seconds)
    python bench/compare.py --json out.json

It needs the timing module neurov._bench, which a default install leaves
out; install with it:

    pip install -Ccmake.define.NEUROV_BUILD_BENCH=ON .

Times are medians of repeated measurements; on a shared machine compare the
ratios, which are measured back to back in the same run.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

import neurov
from neurov import _core

try:
    from neurov import _bench
except ImportError:
    raise SystemExit("bench/compare.py needs neurov._bench, the timing helpers a default install "
                     "leaves out: pip install -Ccmake.define.NEUROV_BUILD_BENCH=ON .") from None

sys.path.insert(0, str(Path(__file__).resolve().parent))
import numpy_baseline as nb  # noqa: E402

LAMBDA = np.full(6, 0.5)
KD = np.array([200.0, 200.0, 200.0, 50.0, 50.0, 50.0])
GAMMA, DT, WIDTH, SUBSTEPS = 0.3, 0.2, 30.0, 10


# ------------------------------------------------------------------ inputs


def centres(n: int, seed: int = 1) -> np.ndarray:
    """N centres uniform in the box bench_common.hpp uses: +-0.5 for nu_r_dot,
    +-1 / +-0.5 for the velocities, +-12 m / +-0.9 rad for the pose."""
    half = np.concatenate([np.full(6, 0.5), [1, 1, 1, 0.5, 0.5, 0.5], [1, 1, 1, 0.5, 0.5, 0.5],
                           [12, 12, 12, 0.9, 0.9, 0.9]])
    return np.random.default_rng(seed).uniform(-half, half, size=(n, 24))


def step_inputs(count: int, seed: int = 7) -> np.ndarray:
    """(count, 30) rows [eta, nu, eta_d, eta_d_dot, eta_d_ddot] near a moving
    reference, as a tracking controller sees them."""
    rng = np.random.default_rng(seed)
    ang = np.array([False, False, False, True, True, True])
    eta = np.where(ang, rng.uniform(-0.4, 0.4, (count, 6)), rng.uniform(-10, 10, (count, 6)))
    nu = np.where(ang, rng.uniform(-0.2, 0.2, (count, 6)), rng.uniform(-0.5, 0.5, (count, 6)))
    eta_d = eta + np.where(ang, rng.uniform(-0.05, 0.05, (count, 6)), rng.uniform(-0.5, 0.5, (count, 6)))
    eta_d_dot = np.where(ang, rng.uniform(-0.1, 0.1, (count, 6)), rng.uniform(-0.3, 0.3, (count, 6)))
    eta_d_ddot = rng.uniform(-0.05, 0.05, (count, 6))
    return np.hstack([eta, nu, eta_d, eta_d_dot, eta_d_ddot])


def square_command() -> tuple[np.ndarray, np.ndarray]:
    """bench_common.hpp's command: a 10 m square at 2 m depth, heading along
    each leg, four laps over 581 s."""
    corners = [(0, 0), (10, 0), (10, 10), (0, 10)]
    headings = [0.0, np.pi / 2, np.pi, 3 * np.pi / 2]
    legs = 16
    times = 5.0 + 36.0 * np.arange(legs + 1)
    poses = np.zeros((legs + 1, 6))
    for k in range(legs + 1):
        leg = min(k, legs - 1)
        poses[k] = [*corners[k % 4], 2.0, 0.0, 0.0, headings[leg % 4] + 2 * np.pi * (leg // 4)]
    return times, poses


def neurov_controller(c: np.ndarray) -> neurov.NNAdaptiveController:
    return neurov.NNAdaptiveController(neurov.RbfNetwork(c, WIDTH), LAMBDA, KD, GAMMA, DT)


def numpy_controller(c: np.ndarray) -> nb.NNController:
    return nb.NNController(c, WIDTH, LAMBDA, KD, GAMMA, DT)


# ------------------------------------------------------------------ timing


def per_call(fn: Callable[[int], Any], calls: int, repeats: int) -> float:
    """Median over `repeats` of the mean seconds per call of fn(k), k = 0..calls-1."""
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for k in range(calls):
            fn(k)
        out.append((time.perf_counter() - t0) / calls)
    return statistics.median(out)


def fmt(seconds: float) -> str:
    for unit, scale in (("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("ns", 1e-9)):
        if seconds >= scale or unit == "ns":
            return f"{seconds / scale:8.2f} {unit}"
    return str(seconds)


def closed_loop_config(duration: float, **extra: Any) -> _core.SimulationConfig:
    times, poses = square_command()
    return _core.SimulationConfig(dt=DT, substeps=SUBSTEPS, duration=duration, eta0=np.zeros(6),
                                  command=_core.Command(times=times, poses=poses), lambda_d=np.ones(6),
                                  omega=np.full(6, 0.25), **extra)


# ------------------------------------------------------------------ sections


def check_same_work(duration: float, report: dict[str, Any]) -> None:
    c = centres(64)
    cfg = closed_loop_config(duration)
    ours = _core.run_closed_loop(_core.Vehicle.nerov(), neurov_controller(c), cfg)
    base = nb.simulate(nb.Nerov(), numpy_controller(c), dt=DT, substeps=SUBSTEPS, duration=duration,
                       eta0=np.zeros(6), command_times=cfg.command.times,
                       command_poses=cfg.command.poses, lambda_d=cfg.lambda_d, omega=cfg.omega)
    d_eta = float(np.max(np.abs(ours["eta"] - base["eta"])))
    d_tau = float(np.max(np.abs(ours["tau_demanded"] - base["tau"])))
    scale_tau = float(np.max(np.abs(base["tau"])))
    print(f"same work: {duration:.0f} s closed loop, neurov vs numpy: max |d eta| = {d_eta:.2e}, "
          f"max |d tau| = {d_tau:.2e} (|tau| up to {scale_tau:.0f})")
    report["same_work"] = {"duration_s": duration, "max_abs_eta_diff": d_eta, "max_abs_tau_diff": d_tau}
    if not (d_eta < 1e-6 and d_tau < 1e-6 * max(1.0, scale_tau)):
        raise SystemExit("the numpy baseline and neurov disagree: they are not doing the same work")


def nn_step(ns: list[int], quick: bool, report: dict[str, Any]) -> None:
    inputs = step_inputs(256)
    rows = [tuple(r.reshape(5, 6)) for r in inputs]
    print("\nNN controller step (24 inputs, double): numpy per call | neurov per call from Python | "
          "neurov in a C++ loop")
    out = []
    for n in ns:
        c = centres(n)
        npc, nvc = numpy_controller(c), neurov_controller(c)
        calls = 200 if quick else 2000
        t_np = per_call(lambda k: npc.step(*rows[k & 255]), calls, 3 if quick else 7)
        t_py = per_call(lambda k: nvc.step(*rows[k & 255]), calls, 3 if quick else 7)
        steps = 20000 if quick else 200000
        t_cpp = _bench.time_controller_steps(neurov_controller(c), inputs, steps, 3 if quick else 9)
        print(f"  N = {n:5d}: {fmt(t_np)} | {fmt(t_py)} | {fmt(t_cpp)}   numpy / C++ loop = "
              f"{t_np / t_cpp:6.0f}x, numpy / Python call = {t_np / t_py:5.1f}x")
        out.append({"N": n, "numpy_s": t_np, "neurov_python_call_s": t_py, "neurov_cpp_loop_s": t_cpp,
                    "ratio_numpy_over_cpp": t_np / t_cpp, "ratio_numpy_over_python_call": t_np / t_py})
    report["nn_step"] = out


def plant(quick: bool, report: dict[str, Any]) -> None:
    rows = step_inputs(256)
    tau = np.array([100.0, 20.0, -30.0, 2.0, -3.0, 5.0])
    base, veh = nb.Nerov(), _core.Vehicle.nerov()
    calls, reps = (500, 3) if quick else (5000, 7)
    t_np = per_call(lambda k: base.derivative(rows[k & 255, :6], rows[k & 255, 6:12], tau), calls, reps)
    t_py = per_call(lambda k: veh.acceleration(rows[k & 255, :6], rows[k & 255, 6:12], tau), calls, reps)
    t_cpp = _bench.time_acceleration(veh, rows[0, :6], rows[0, 6:12], tau, 200000 if quick else 2000000,
                                     3 if quick else 9)
    print(f"\nOne plant evaluation (NEROV nu_dot): numpy {fmt(t_np)} | neurov from Python {fmt(t_py)} | "
          f"C++ loop {fmt(t_cpp)}   numpy / C++ = {t_np / t_cpp:.0f}x")
    report["plant"] = {"numpy_s": t_np, "neurov_python_call_s": t_py, "neurov_cpp_loop_s": t_cpp,
                       "ratio_numpy_over_cpp": t_np / t_cpp}


def closed_loop(duration: float, numpy_duration: float, quick: bool, report: dict[str, Any]) -> None:
    c = centres(64)
    veh = _core.Vehicle.nerov()
    cfg = closed_loop_config(duration)
    times = []
    for _ in range(5 if quick else 21):
        ctl = neurov_controller(c)
        t0 = time.perf_counter()
        _core.run_closed_loop(veh, ctl, cfg)
        times.append(time.perf_counter() - t0)
    t_ours = statistics.median(times)
    cfg_np = closed_loop_config(numpy_duration)
    np_times = []
    for _ in range(1 if quick else 3):
        t0 = time.perf_counter()
        nb.simulate(nb.Nerov(), numpy_controller(c), dt=DT, substeps=SUBSTEPS, duration=numpy_duration,
                    eta0=np.zeros(6), command_times=cfg_np.command.times,
                    command_poses=cfg_np.command.poses, lambda_d=cfg_np.lambda_d, omega=cfg_np.omega)
        np_times.append(time.perf_counter() - t0)
    t_np = statistics.median(np_times)
    rtf_ours, rtf_np = duration / t_ours, numpy_duration / t_np
    print(f"\nClosed loop (NEROV, NN N = 64, {DT:g} s control, {SUBSTEPS} RK4 substeps, no thrusters):")
    print(f"  neurov : {duration:.0f} s simulated in {fmt(t_ours)} (median of {len(times)}) -> "
          f"real-time factor {rtf_ours:,.0f}")
    print(f"  numpy  : {numpy_duration:.0f} s simulated in {fmt(t_np)} (median of {len(np_times)}) -> "
          f"real-time factor {rtf_np:,.0f}")
    print(f"  neurov / numpy real-time factor = {rtf_ours / rtf_np:,.0f}x")
    report["closed_loop"] = {"duration_s": duration, "neurov_wall_s": t_ours, "neurov_rtf": rtf_ours,
                             "numpy_duration_s": numpy_duration, "numpy_wall_s": t_np, "numpy_rtf": rtf_np,
                             "ratio": rtf_ours / rtf_np}


def throughput(runs: int, duration: float, report: dict[str, Any]) -> None:
    """A Monte-Carlo batch: mass +-10 %, damping +-20 %, start within 1 m,
    measurement noise with one seed per run."""
    rng = np.random.default_rng(2024)
    base = neurov.Vehicle.nerov().parameters()
    jobs = []
    for r in range(runs):
        p = dict(base)
        p["mass"] = base["mass"] * rng.uniform(0.9, 1.1)
        p["linear_damping"] = np.asarray(base["linear_damping"]) * rng.uniform(0.8, 1.2)
        p["quadratic_damping"] = np.asarray(base["quadratic_damping"]) * rng.uniform(0.8, 1.2)
        eta0 = np.zeros(6)
        eta0[:2] = rng.uniform(-1, 1, 2)
        jobs.append((p, eta0, r))
    c = centres(64)

    def one(job: tuple[dict[str, Any], np.ndarray, int]) -> bool:
        p, eta0, seed = job
        cfg = closed_loop_config(duration, noise_eta=np.full(6, 0.01), noise_nu=np.full(6, 0.005), seed=seed)
        cfg.eta0 = eta0
        return bool(_core.run_closed_loop(_core.Vehicle(**p), neurov_controller(c), cfg)["diverged"])

    print(f"\nMonte-Carlo batch: {runs} closed loops of {duration:.0f} s (perturbed NEROV, noise seeds), "
          f"threads over one process ({os.cpu_count()} CPUs):")
    out = {}
    for workers in (1, 2):
        t0 = time.perf_counter()
        with concurrent.futures.ThreadPoolExecutor(workers) as pool:
            diverged = sum(pool.map(one, jobs))
        wall = time.perf_counter() - t0
        out[workers] = runs / wall
        print(f"  {workers} worker{'s' if workers > 1 else ' '}: {runs / wall:7.1f} runs/s "
              f"({wall:.2f} s wall, {diverged} diverged)")
    print(f"  scaling 1 -> 2 workers: {out[2] / out[1]:.2f}x")
    report["throughput"] = {"runs": runs, "duration_s": duration, "runs_per_s_1": out[1],
                            "runs_per_s_2": out[2], "scaling": out[2] / out[1]}


def machine() -> dict[str, Any]:
    model = platform.processor()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": model, "cpus": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "neurov": neurov.__version__, "kernels": neurov._core._kernel_isa()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a short smoke run (CI)")
    ap.add_argument("--json", type=Path, help="write the figures to this JSON file")
    args = ap.parse_args()
    report: dict[str, Any] = {"machine": machine(), "quick": args.quick}
    m = report["machine"]
    print(f"{m['cpu']}, {m['cpus']} CPUs; Python {m['python']}, numpy {m['numpy']}, neurov {m['neurov']} "
          f"(RBF loops: {m['kernels']})\n")
    check_same_work(20.0 if args.quick else 600.0, report)
    nn_step([64, 256] if args.quick else [16, 64, 256, 1024], args.quick, report)
    plant(args.quick, report)
    closed_loop(600.0, 30.0 if args.quick else 600.0, args.quick, report)
    throughput(20 if args.quick else 200, 600.0, report)
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))
        print(f"\nwrote {args.json}")


if __name__ == "__main__":
    main()
