"""The batch: _core.BatchSimulator stepped from Python, _core.run_batch and
neurov.simulate_many. A lane gives exactly the run alone (every built-in
controller; thrusters, sensors and the EKF, waves; a diverging lane), the
metrics-only sums give the metrics of the rows, and bad input is named."""

from __future__ import annotations

import math
import re
from pathlib import Path

import neurov
import numpy as np
import pytest
from neurov import _core
from neurov.config.scenario import ControllerSpec
from neurov.errors import NeurovError
from neurov.laws.registry import REGISTRY, build_controller
from neurov.results.metrics import WindowSums
from neurov.running.many import simulate_many
from neurov.running.plant import build_vehicle, simulation_config
from neurov.running.simulation import simulate

SCENARIOS = Path(neurov.__file__).parent / "scenarios"


def short(name: str, duration: float = 4.0, seed: int = 0) -> neurov.Scenario:
    sc = neurov.load_scenario(SCENARIOS / f"{name}.toml").replace()
    sc.duration = duration
    sc.simulation.seed = seed
    return sc


#: plain; thrusters, sensors, EKF, delay, current; waves with thrusters.
FEATURES = ("paper_fig3", "nerov_square_realistic", "nerov_square_sea_state_3")


def same_result(a: dict, b: dict) -> None:
    assert a.keys() == b.keys()
    for k, v in a.items():
        if isinstance(v, np.ndarray):
            np.testing.assert_array_equal(v, b[k], err_msg=k)
        else:
            assert v == b[k], k


def wild() -> neurov.Scenario:
    """A run whose plant diverges at t = 8 s (row 5 of 16): stiff PD gains
    on a 2 s step without substeps."""
    sc = short("paper_fig3", duration=30.0)
    sc.simulation.dt, sc.simulation.substeps = 2.0, 1
    return sc


WILD_PD = ControllerSpec("pd", kp=[1e7] * 6, kd=[1e7] * 6)


def spec_for(kind: str, sc: neurov.Scenario) -> ControllerSpec:
    return sc.controller if kind == "nn" else ControllerSpec(kind)


def test_run_batch_lanes_equal_the_runs_alone_for_every_controller_mixed() -> None:
    scenarios = [short(n, seed=i) for i, n in enumerate(FEATURES)]
    lanes = [(sc, build_controller(spec_for(kind, sc), sc)) for kind in REGISTRY for sc in scenarios]
    # A lane whose plant diverges early while the others go on.
    lanes.append((wild(), build_controller(WILD_PD, wild())))
    vehicles = [build_vehicle(sc) for sc, _ in lanes]
    configs = [simulation_config(sc) for sc, _ in lanes]
    batch = _core.run_batch(vehicles, [c for _, c in lanes], configs, threads=2)
    assert batch[-1]["diverged"] and len(batch[-1]["t"]) == 5
    for (sc, c), got in zip(lanes, batch):
        same_result(got, _core.run_closed_loop(build_vehicle(sc), c, simulation_config(sc)))


def test_a_payload_picked_up_between_two_substeps_moves_only_its_lane() -> None:
    """Payloads held at the centre of gravity (the plant stays in the SIMD
    kernel) picked up inside a control period, at a substep's start, by
    every other lane of a block: each lane is still its run alone, and the
    event did change the lanes that had it."""
    lanes = []
    for i in range(20):
        sc = short("paper_fig3", seed=i)
        if i % 2 == 0:
            sc.simulation.payload = [_core.PayloadEvent(time=1.03 + 0.1 * (i % 4), mass=20.0 + i, buoyancy=0.0)]
        lanes.append((sc, build_controller(ControllerSpec("pd"), sc)))
    vehicles = [build_vehicle(sc) for sc, _ in lanes]
    configs = [simulation_config(sc) for sc, _ in lanes]
    batch = _core.run_batch(vehicles, [c for _, c in lanes], configs, threads=1)
    for i, ((sc, c), got) in enumerate(zip(lanes, batch)):
        same_result(got, _core.run_closed_loop(build_vehicle(sc), c, simulation_config(sc)))
        assert (got["payload_mass"][-1] > 0) == (i % 2 == 0)
    without = short("paper_fig3", seed=0)
    plain = _core.run_closed_loop(build_vehicle(without), build_controller(ControllerSpec("pd"), without),
                                  simulation_config(without))
    assert not np.array_equal(plain["eta"], batch[0]["eta"])


def test_stepped_batch_equals_simulators_alone() -> None:
    scenarios = [short(n, seed=i + 3) for i, n in enumerate(FEATURES)]
    scenarios[0].simulation.use_thrusters = False  # no thrust limit: lane 0 can be made to diverge
    vehicles = [build_vehicle(sc) for sc in scenarios]
    configs = [simulation_config(sc) for sc in scenarios]
    batch = _core.BatchSimulator(vehicles, configs)
    alone = [_core.Simulator(v, c) for v, c in zip(vehicles, configs)]
    assert batch.size == 3
    rng = np.random.default_rng(1)
    k = 0
    while not batch.done.all():
        obs = batch.observation
        for i, sim in enumerate(alone):
            o = sim.observation
            for name in ("eta", "nu", "eta_d", "eta_d_dot", "eta_d_ddot"):
                np.testing.assert_array_equal(obs[name][i], getattr(o, name))
            assert obs["t"][i] == o.t and obs["faults"][i] == sim.faults
        tau = rng.normal(0.0, 50.0, (3, 6))
        if k == 7:
            tau[0, 0] = 1e300  # lane 0 (no thrusters to saturate it) diverges here
        mask = np.array([True, k % 2 == 0, True])
        statuses = batch.step(tau, mask)
        for i, sim in enumerate(alone):
            if mask[i] and not sim.done:
                assert statuses[i] == int(sim.step(tau[i]))
            else:
                assert statuses[i] == _core.LANE_NOT_STEPPED
        k += 1
    assert list(batch.diverged) == [True, False, False]
    np.testing.assert_array_equal(batch.steps, [s.steps for s in alone])
    np.testing.assert_array_equal(batch.planned_steps, [s.planned_steps for s in alone])
    eta, _ = batch.state
    np.testing.assert_array_equal(eta[1], alone[1].state[0])
    for i, sim in enumerate(alone):
        same_result(batch.result(i), sim.result())
    batch.reset(np.array([5, 6, 7], dtype=np.uint64), mask=np.array([False, True, False]))
    assert list(batch.steps) == [alone[0].steps, 0, alone[2].steps]


@pytest.mark.parametrize("threads", [2, 3])  # the module's kept threads, threads started per call
def test_threads_split_the_lanes_without_changing_a_result(threads: int) -> None:
    """Three shares' worth of lanes (every feature, one diverging, a mask)
    stepped on 1 and on 2 or 3 threads (MIN_LANES_PER_THREAD lanes a thread
    at least: each share holds lanes of every kind) give the same statuses
    and results to the bit."""
    n = 3 * _core.MIN_LANES_PER_THREAD
    diverging = n // 3 + 1  # in the second share
    scenarios = [short(FEATURES[i % 3], seed=i) for i in range(n)]
    for sc in scenarios[::3]:
        sc.simulation.use_thrusters = False
    vehicles = [build_vehicle(sc) for sc in scenarios]
    configs = [simulation_config(sc) for sc in scenarios]
    one, three = _core.BatchSimulator(vehicles, configs), _core.BatchSimulator(vehicles, configs)
    rng = np.random.default_rng(2)
    k = 0
    while not one.done.all():
        tau = rng.normal(0.0, 50.0, (n, 6))
        if k == 5:
            tau[diverging, 0] = 1e300
        mask = rng.random(n) < 0.8
        np.testing.assert_array_equal(one.step(tau, mask, threads=1), three.step(tau, mask, threads=threads))
        k += 1
    assert three.done.all() and one.diverged[diverging] and three.diverged[diverging]
    for i in range(n):
        same_result(one.result(i), three.result(i))
    with pytest.raises(TypeError):
        one.step(np.zeros((n, 6)), threads=-1)


def test_replace_renews_a_lane_and_a_refused_one_is_untouched() -> None:
    sc = short("paper_fig3")
    v, c = build_vehicle(sc), simulation_config(sc)
    batch = _core.BatchSimulator([v, v], [c, c])
    batch.step(np.zeros((2, 6)))
    longer = short("paper_fig3", duration=6.0)
    batch.replace(1, v, simulation_config(longer))
    assert list(batch.steps) == [1, 0] and list(batch.planned_steps) == [21, 31]
    bad = simulation_config(short("paper_fig3"))
    bad.substeps = 0
    with pytest.raises(NeurovError, match="substeps") as e:
        batch.replace(0, v, bad)
    assert e.value.field == "substeps"
    assert list(batch.steps) == [1, 0]
    with pytest.raises(NeurovError, match="'i'"):
        batch.replace(2, v, c)


def test_bad_input_is_named() -> None:
    sc = short("paper_fig3")
    v, c = build_vehicle(sc), simulation_config(sc)
    batch = _core.BatchSimulator([v, v], [c, c])
    cases = [
        (lambda: batch.step(np.zeros((2, 5))), "tau"),
        (lambda: batch.step(np.zeros((2, 6), dtype=complex)), "tau"),
        (lambda: batch.step([[0.0] * 6] * 2), "tau"),
        (lambda: batch.step(np.zeros((2, 6)), mask=np.ones(2, dtype=int)), "mask"),
        (lambda: batch.step(np.zeros((2, 6)), mask=np.ones(3, dtype=bool)), "mask"),
        (lambda: batch.step(np.zeros((2, 6)), parameters=np.zeros((2, 1))), "parameters"),
        (lambda: batch.reset(np.array([1, -1])), "seeds"),
        (lambda: batch.reset(np.zeros(2)), "seeds"),
        (lambda: _core.BatchSimulator([v], [c, c]), "configs"),
        (lambda: _core.BatchSimulator([v, c], [c, c]), "vehicles[1]"),
        (lambda: _core.run_batch([v], [object()], [c]), "controllers[0]"),
        (lambda: _core.run_batch([v], [_core.PDController(_core.PDConfig())], [c], metrics_only=True), "after"),
    ]
    for call, name in cases:
        with pytest.raises(NeurovError, match=re.escape(f"'{name}'")) as e:
            call()
        assert e.value.field == name or name in str(e.value)
    bad = simulation_config(short("paper_fig3"))
    bad.dt = 0.0
    with pytest.raises(NeurovError, match="lane 1") as e:
        _core.BatchSimulator([v, v], [c, bad])
    assert e.value.field == "dt"


def test_window_sums_are_one_list() -> None:
    assert [name for name, _, _ in _core.WINDOW_SUMS] == list(vars(WindowSums()))


def close(a: float, b: float) -> bool:
    return a == b or (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-12 * max(abs(a), abs(b))


def test_metrics_only_gives_the_metrics_of_the_full_run() -> None:
    runs = [(short(n, duration=30.0, seed=i), None) for i, n in enumerate(FEATURES)]
    runs.append((wild(), WILD_PD))
    runs.append((short("paper_fig3", duration=30.0), ControllerSpec("pid")))
    for after in (None, 12.0, 0.0):  # 12 s: after the diverged run ends, judged over all its rows
        full = [r.metrics(after=after) if after is not None else r.metrics() for r in simulate_many(runs)]
        only = simulate_many(runs, metrics_only=True, after=after)
        assert full[3]["diverged"]
        for f, o in zip(full, only):
            flat_f, flat_o = neurov.results.metrics.flat_metrics(f), neurov.results.metrics.flat_metrics(o)
            assert flat_f.keys() == flat_o.keys()
            for key in flat_f:
                assert close(flat_f[key], flat_o[key]), (after, key, flat_f[key], flat_o[key])
            assert f["window_start_s"] == o["window_start_s"] and f["diverged_at_s"] == o["diverged_at_s"]


class Hold:
    """A Python controller: stepped per run, not batched."""

    def step(self, eta: np.ndarray, nu: np.ndarray, eta_d: np.ndarray, eta_d_dot: np.ndarray,
             eta_d_ddot: np.ndarray) -> np.ndarray:
        return np.zeros(6)


def test_simulate_many_keeps_the_order_and_equals_simulate() -> None:
    base = short("paper_fig3", duration=3.0)
    overrides = [{"name": f"run{i}"} for i in range(3)]
    by_overrides = simulate_many(base, overrides)
    assert [r.scenario.name for r in by_overrides] == ["run0", "run1", "run2"]
    pairs = [(base, ControllerSpec("pd")), (base, Hold()), (short("nerov_square_realistic", 3.0), None)]
    got = simulate_many(pairs, threads=1)
    assert got[1].controller == "Hold"
    for (sc, ctrl), r in zip(pairs, got):
        alone = simulate(sc, ctrl)
        assert r.controller == alone.controller and r.diverged == alone.diverged
        np.testing.assert_array_equal(r.eta, alone.eta)
        np.testing.assert_array_equal(r.tau_demanded, alone.tau_demanded)
    with pytest.raises(TypeError, match="overrides"):
        simulate_many(base, {"name": "x"})
    with pytest.raises(TypeError, match="runs"):
        simulate_many([base, 3])
