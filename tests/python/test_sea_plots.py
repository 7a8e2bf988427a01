"""The sea figures: the flow the vehicle met and the realised wave spectrum
against the target; the target's density against independent references."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from neurov import _core
from neurov.plotting import sea
from neurov.running.command import FIGURES, SEA_FIGURES, run_scenario_file
from neurov.config.reading import load_scenario
from neurov.running.simulation import simulate
from neurov.study.spec import SCENARIO_DIR

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "scenarios"
SEA_STATE_4 = SCENARIO_DIR / "nerov_square_sea_state_4.toml"


def dnv_jonswap(omega: float, hs: float, tp: float, gamma: float) -> float:
    """DNV-RP-C205 (3.5.5) with its fitted normalisation 1 - 0.287 ln(gamma)."""
    wp = 2 * math.pi / tp
    sigma = 0.07 if omega <= wp else 0.09
    pm = 5 / 16 * hs**2 * wp**4 * omega**-5 * math.exp(-1.25 * (wp / omega) ** 4)
    return (1 - 0.287 * math.log(gamma)) * pm * gamma ** math.exp(-0.5 * ((omega - wp) / (sigma * wp)) ** 2)


@pytest.mark.parametrize("gamma", [1.0, 2.0, 3.3, 7.0])
def test_target_spectrum_has_the_asked_hs_and_the_dnv_shape(gamma: float) -> None:
    w = _core.WaveConfig(hs=2.5, tp=9.0, gamma=gamma)
    wp = 2 * math.pi / w.tp
    m0 = quad(lambda x: sea.target_spectrum(w, np.array([x]))[0], 0.0, 60.0, points=[wp], limit=400)[0]
    assert m0 == pytest.approx(w.hs**2 / 16, rel=1e-7)
    # The shape is DNV's; the normalisation differs from DNV's fit by what
    # docs/disturbances.md measures (-0.22 %, +0.24 %, -1.75 % at 2, 3.3, 7).
    ratios = [sea.target_spectrum(w, np.array([x]))[0] / dnv_jonswap(x, w.hs, w.tp, gamma)
              for x in (0.5 * wp, wp, 1.3 * wp, 3 * wp)]
    np.testing.assert_allclose(ratios, ratios[0], rtol=1e-12)
    assert ratios[0] == pytest.approx(1.0, abs=0.02)
    if gamma == 3.3:  # C(3.3) = 0.6558 (the C++ test's property), DNV's fit 0.6573
        assert ratios[0] * (1 - 0.287 * math.log(gamma)) == pytest.approx(0.6558, abs=1e-4)


def test_pierson_moskowitz_target_is_the_ittc_form() -> None:
    w = _core.WaveConfig(spectrum=_core.WaveSpectrum.pierson_moskowitz, hs=0.88, tp=7.5, gamma=5.0)
    t1 = 0.772 * w.tp  # ITTC: 173 Hs^2 T1^-4 w^-5 exp(-691 T1^-4 w^-4)
    for x in (0.7, 0.84, 1.2, 2.0):  # off the far low tail, where the rounded 0.772 tells
        ittc = 173 * w.hs**2 * t1**-4 * x**-5 * math.exp(-691 * t1**-4 * x**-4)
        assert sea.target_spectrum(w, np.array([x]))[0] == pytest.approx(ittc, rel=1e-2)


def test_realised_spectrum_of_a_long_run_matches_the_target() -> None:
    s = load_scenario(SEA_STATE_4).replace(duration=3600.0, payload=[])
    r = simulate(s)
    omega, est = sea.realised_spectrum(r)
    m0 = np.trapezoid(est, omega) if hasattr(np, "trapezoid") else np.trapz(est, omega)
    # An hour of a 8.8 s sea: Hs within 5 % (the bound for the
    # elevation record; the C++ tests check a six-hour record to 0.1 %).
    assert 4 * math.sqrt(m0) == pytest.approx(s.waves.hs, rel=0.05)
    peak = omega[np.argmax(est)]
    assert peak == pytest.approx(2 * math.pi / s.waves.tp, rel=0.1)


def test_sea_figures_draw_what_the_run_met() -> None:
    r = simulate(load_scenario(SEA_STATE_4).replace(duration=200.0))
    fig = sea.sea_flow(r)
    axes = {ax.get_gid(): ax for ax in fig.axes}
    assert list(axes) == ["current", "orbital velocity", "elevation above", "payload"]
    axes = list(axes.values())
    np.testing.assert_array_equal(axes[0].lines[0].get_ydata(), r.current[:, 0])
    np.testing.assert_array_equal(axes[1].lines[2].get_ydata(), r.wave_velocity[:, 2])
    np.testing.assert_array_equal(axes[2].lines[0].get_ydata(), r.wave_elevation)
    np.testing.assert_array_equal(axes[3].lines[0].get_ydata(), r.payload_mass)
    assert r.payload_mass[-1] == 15.0
    fig = sea.wave_spectrum(r)
    target, realised = fig.axes[0].lines[:2]
    np.testing.assert_allclose(target.get_ydata(), sea.target_spectrum(r.scenario.waves, target.get_xdata()))
    np.testing.assert_array_equal(realised.get_ydata(), sea.realised_spectrum(r)[1])


def test_a_constant_current_is_stated_not_drawn_flat() -> None:
    # A steady 0.3 m/s eastward current, no waves, no payload.
    r = simulate(load_scenario(EXAMPLES / "lawnmower_pd_current.toml").replace(duration=5.0))
    assert sea.has_sea(r)
    fig = sea.sea_flow(r)
    (ax,) = fig.axes
    assert not ax.axison and not ax.lines
    assert "current N 0, E 0.3, D 0 m/s" in ax.texts[0].get_text()
    assert "payload 0 kg" in ax.texts[0].get_text()


def test_shallow_rows_are_shaded_and_a_calm_run_has_no_wave_figure() -> None:
    s = load_scenario(SEA_STATE_4)
    shallow = simulate(s.replace(duration=30.0, eta0=np.zeros(6)))  # starts at the surface
    assert np.any(shallow.faults & 32)
    assert "minimum depth" in sea.sea_flow(shallow).axes[0].get_title()
    calm = simulate(load_scenario(SCENARIO_DIR / "nerov_square.toml").replace(duration=20.0))
    assert not sea.has_sea(calm)
    with pytest.raises(ValueError, match="has no waves"):
        sea.wave_spectrum(calm)


def test_neurov_run_plot_writes_the_sea_figures(tmp_path: Path) -> None:
    path = tmp_path / "short_sea.toml"
    path.write_text(SEA_STATE_4.read_text().replace("duration = 250.0", "duration = 40.0")
                    .replace("time = 125.0", "time = 20.0"))
    run_scenario_file(path, tmp_path / "out", plot=True)
    for name in (*FIGURES, *SEA_FIGURES):
        assert (tmp_path / "out" / name).stat().st_size > 1000, name
    calm = tmp_path / "calm"
    run_scenario_file(SCENARIO_DIR / "nerov_depth_step.toml", calm, plot=True)
    assert not any((calm / name).exists() for name in SEA_FIGURES)
