"""The sea in the closed loop from Python: the bound configuration (the
Gauss-Markov current, the waves, the payload events) and the new result
series, on long seeded runs against the physics (see docs/disturbances.md)."""

from __future__ import annotations

import copy
import pickle
from pathlib import Path

import numpy as np
import pytest

from neurov import _core

G = 9.81
ROOT = Path(__file__).resolve().parents[2]


def still(duration: float, depth: float, dt: float = 0.2, substeps: int = 10) -> _core.SimulationConfig:
    eta0 = np.array([0.0, 0, depth, 0, 0, 0])
    return _core.SimulationConfig(dt=dt, substeps=substeps, duration=duration, eta0=eta0,
                                  command=_core.Command(times=[0.0], poses=eta0[None, :]))


def neutral_nerov(**changes: object) -> _core.Vehicle:
    """NEROV with rho V = B / g = m and r_b = r_g = 0: the water carries it."""
    p = _core.Vehicle.nerov().parameters()
    p.update(weight=p["mass"] * G, buoyancy=p["mass"] * G, centre_of_buoyancy=np.zeros(3))
    p.update(changes)
    return _core.Vehicle(**p)


def uncontrolled(vehicle: _core.Vehicle, config: _core.SimulationConfig) -> dict:
    sim = _core.Simulator(vehicle, config)
    while not sim.done:
        sim.step(np.zeros(6))
    return sim.result()


def test_sea_fields_are_bound_field_by_field() -> None:
    c = _core.SimulationConfig()
    assert c.current_model == _core.CurrentModel.constant and c.waves is None and c.payload == ()
    c.current_model = _core.CurrentModel.gauss_markov
    c.gauss_markov_current.speed_std = 0.2  # the getter gives the held struct
    assert c.gauss_markov_current.speed_std == 0.2
    c.waves = _core.WaveConfig(spectrum=_core.WaveSpectrum.pierson_moskowitz, hs=1.5, tp=7.0)
    c.waves.components = 100
    assert c.waves.components == 100 and c.waves.spectrum == _core.WaveSpectrum.pierson_moskowitz
    c.payload = [_core.PayloadEvent(time=5.0, mass=10.0, mass_position=[0.1, 0, 0])]
    np.testing.assert_array_equal(c.payload[0].mass_position, [0.1, 0, 0])
    assert c.payload[0].buoyancy_position is None
    d = pickle.loads(pickle.dumps(c))
    assert d.waves.hs == 1.5 and d.payload[0].mass == 10.0 and d.current_model == c.current_model
    e = copy.deepcopy(c)
    e.waves = None
    assert e.waves is None and c.waves is not None
    with pytest.raises(TypeError, match="SimulationConfig.waves must be a WaveConfig"):
        c.waves = 3.0
    with pytest.raises(ValueError, match=r"PayloadEvent.mass_position must have shape \(3,\)"):
        _core.PayloadEvent(mass_position=[1.0, 2.0])


@pytest.mark.parametrize(("change", "field"), [
    (lambda c: setattr(c, "waves", _core.WaveConfig(hs=0.0)), "hs"),
    (lambda c: setattr(c, "waves", _core.WaveConfig(gamma=0.5)), "gamma"),
    (lambda c: (setattr(c, "current_model", _core.CurrentModel.gauss_markov),
                setattr(c.gauss_markov_current, "time_constant", 0.0)), "time_constant"),
    (lambda c: (setattr(c, "current_model", _core.CurrentModel.gauss_markov),
                setattr(c.gauss_markov_current, "speed_min", 3.0)), "speed_max"),
    (lambda c: setattr(c, "payload", [_core.PayloadEvent(time=2.0), _core.PayloadEvent(time=1.0)]),
     "payload.time"),
])
def test_bad_sea_configurations_are_refused_by_name(change, field: str) -> None:
    c = still(10.0, 10.0)
    change(c)
    with pytest.raises(ValueError, match=rf"\b{field}\b"):
        c.validate()


def test_a_payload_that_leaves_no_mass_is_refused_by_the_simulator() -> None:
    c = still(10.0, 10.0)
    c.payload = [_core.PayloadEvent(time=1.0, mass=-500.0)]
    with pytest.raises(ValueError, match=r"payload\.mass"):
        _core.Simulator(_core.Vehicle.nerov(), c)


def test_neutrally_buoyant_vehicle_moves_with_the_orbital_flow() -> None:
    c = still(600.0, 12.0)
    c.waves = _core.WaveConfig(hs=2.5, tp=9.0, direction=30.0)
    c.seed = 21
    # Start at rest: the relative velocity then decays under damping (the
    # Munk moment may turn the body meanwhile, nothing turns it back) and
    # stays near zero while the water carries the body.
    r = uncontrolled(neutral_nerov(), c)
    assert not r["diverged"]
    flow = np.linalg.norm(r["wave_velocity"], axis=1)
    ned = np.array([_core.rotation(*e[3:]) @ n[:3] for e, n in zip(r["eta"], r["nu"])])
    relative = np.linalg.norm(ned - r["wave_velocity"], axis=1)
    late = r["t"] > 60.0
    assert flow.max() > 0.3
    assert relative[late].max() < 1e-3 * flow.max()
    assert np.all(r["faults"] == 0)
    assert np.all(r["current"] == 0) and np.ptp(r["wave_elevation"]) > 2.0


def test_payload_pick_up_sinks_the_vehicle_at_rest() -> None:
    vehicle = neutral_nerov(linear_damping=[70.0, 100, 0, 30, 50, 50],
                            quadratic_damping=[100.0, 200, 0, 50, 100, 100])
    c = still(2.0, 10.0, dt=0.01, substeps=2)
    c.payload = [_core.PayloadEvent(time=0.5, mass=10.0)]
    r = uncontrolled(vehicle, c)
    m_a = vehicle.parameters()["added_mass"][2, 2]
    a = 10.0 * G / (vehicle.parameters()["mass"] + 10.0 + m_a)
    after = r["t"] >= 0.5
    np.testing.assert_allclose(r["nu"][after, 2], a * (r["t"][after] - 0.5), rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(r["nu"][~after, 2], 0.0)
    np.testing.assert_array_equal(r["payload_mass"], np.where(after, 10.0, 0.0))


def test_pid_settles_with_the_heave_force_changed_by_the_added_weight() -> None:
    c = still(200.0, 10.0, dt=0.1)
    c.payload = [_core.PayloadEvent(time=50.0, mass=10.0)]
    pid = _core.PIDController(_core.PIDConfig(kp=np.full(6, 400.0), kd=np.full(6, 400.0),
                                              ki=np.full(6, 100.0), integral_limit=np.full(6, 500.0),
                                              dt=0.1))
    r = _core.run_closed_loop(_core.Vehicle.nerov(), pid, c)
    before, after = 499, -1  # t = 49.9 s and 200 s
    assert r["tau_demanded"][after, 2] - r["tau_demanded"][before, 2] == pytest.approx(-10.0 * G, rel=1e-3)
    assert r["eta"][after, 2] == pytest.approx(10.0, abs=1e-4)


def current_speed_stats(dt: float, substeps: int, duration: float, tc: float) -> tuple[float, float, float]:
    c = still(duration, 10.0, dt=dt, substeps=substeps)
    c.current_model = _core.CurrentModel.gauss_markov
    c.gauss_markov_current = _core.GaussMarkovCurrentConfig(time_constant=tc, speed_max=5.0)
    c.seed = 5
    v = np.linalg.norm(uncontrolled(_core.Vehicle.nerov(), c)["current"], axis=1)
    x = v - v.mean()
    lag = round(tc / dt)
    return v.mean(), x.std(), float(np.dot(x[:-lag], x[lag:]) / (len(x) - lag) / x.var())


@pytest.mark.slow
def test_gauss_markov_current_statistics_do_not_depend_on_dt_or_substeps() -> None:
    tc, duration = 30.0, 30000.0
    n = duration / tc
    for dt, substeps in ((0.5, 1), (2.0, 1), (2.0, 5)):
        mean, std, rho = current_speed_stats(dt, substeps, duration, tc)
        assert mean == pytest.approx(0.5, abs=5 * 0.1 * np.sqrt(2 / n))
        assert std == pytest.approx(0.1, abs=5 * 0.1 * np.sqrt(1 / n))
        assert rho == pytest.approx(np.exp(-1), abs=5 * np.sqrt(2 / n))


def test_gauss_markov_realisation_does_not_change_with_substeps() -> None:
    runs = []
    for substeps in (1, 6):
        c = still(300.0, 10.0, dt=0.5, substeps=substeps)
        c.current_model = _core.CurrentModel.gauss_markov
        runs.append(uncontrolled(_core.Vehicle.nerov(), c)["current"])
    np.testing.assert_array_equal(runs[0], runs[1])


def test_waves_and_current_leave_the_measurement_noise_as_it_was() -> None:
    def noise(config: _core.SimulationConfig) -> np.ndarray:
        sim = _core.Simulator(_core.Vehicle.nerov(), config)
        out = []
        while not sim.done:
            o = sim.observation
            eta, nu = sim.state
            out.append(np.concatenate([o.eta - eta, o.nu - nu]))
            sim.step(np.zeros(6))
        return np.array(out)

    c = still(60.0, 10.0)
    c.noise_eta, c.noise_nu, c.seed = np.full(6, 0.1), np.full(6, 0.05), 3
    calm = noise(c)
    c.waves = _core.WaveConfig()
    c.current_model = _core.CurrentModel.gauss_markov
    np.testing.assert_allclose(noise(c), calm, rtol=0, atol=1e-12)


def test_result_exports_the_sea_series(tmp_path) -> None:
    import neurov
    from neurov.results.timeseries import Result

    c = still(20.0, 1.0)  # above 1.2 Hs: the shallow bit
    c.waves = _core.WaveConfig()
    c.current_model = _core.CurrentModel.gauss_markov
    c.payload = [_core.PayloadEvent(time=10.0, mass=5.0)]
    raw = _core.run_closed_loop(_core.Vehicle.nerov(), _core.PDController(_core.PDConfig()), c)
    diverged = bool(raw.pop("diverged"))
    scenario = neurov.load_scenario(ROOT / "examples" / "scenarios" / "square_nn.toml")
    run = Result(scenario=scenario, controller="pd", diverged=diverged, **raw)
    cols = run.columns()
    np.testing.assert_array_equal(cols["current_E"], raw["current"][:, 1])
    np.testing.assert_array_equal(cols["wave_velocity_D"], raw["wave_velocity"][:, 2])
    np.testing.assert_array_equal(cols["payload_mass"], np.where(raw["t"] >= 10.0, 5.0, 0.0))
    df = run.to_pandas()
    np.testing.assert_array_equal(df["wave_elevation"].to_numpy(), raw["wave_elevation"])
    assert df["faults"].iloc[0] & 32  # the shallow bit
    np.testing.assert_array_equal(df["faults"].to_numpy(), raw["faults"])
    with np.load(run.to_npz(tmp_path / "r.npz")) as data:
        np.testing.assert_array_equal(data["wave_velocity"], raw["wave_velocity"])
