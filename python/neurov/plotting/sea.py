"""The sea a run met (:class:`neurov.Result`): the flow at the
vehicle over time, and the spectrum of the realised surface elevation against
the target spectrum. ``neurov run --plot`` writes them as sea.png and
wave_spectrum.png for a scenario with a sea (docs/disturbances.md).
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray
from scipy.integrate import trapezoid
from scipy.signal import welch

from neurov import _core
from neurov.results.decimation import for_plotting
from neurov.results.timeseries import Result

__all__ = ["has_sea", "realised_spectrum", "sea_flow", "target_spectrum", "wave_spectrum"]

G = 9.81  # m/s^2, as the C++ sea (sea_constants.hpp)
_AXES = ("N", "E", "D")
_GRID = {"alpha": 0.3}
_SHALLOW_BIT = 32  # fault_bits::shallow


def has_sea(result: Result) -> bool:
    """True if the run met a current, waves or a payload change."""
    return result.met_sea


def target_spectrum(waves: _core.WaveConfig, omega: NDArray[np.float64]) -> NDArray[np.float64]:
    """S(omega) [m^2 s/rad] of `waves` at `omega` [rad/s]: the C++ spectral
    density (:meth:`neurov._core.WaveConfig.spectral_density`) the waves are
    realised from."""
    return waves.spectral_density(np.asarray(omega, dtype=np.float64))


def realised_spectrum(result: Result, segment_seconds: float = 200.0) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The one-sided spectrum [m^2 s/rad] of the surface elevation logged
    above the vehicle, by Welch's method (Hann, half overlap, segments of
    `segment_seconds` or the whole record), against circular frequency
    [rad/s]. A moving vehicle sees the waves Doppler-shifted by k U cos(beta)
    (a few per cent at 0.25 m/s in these seas)."""
    dt = float(result.scenario.dt)
    n = len(result.wave_elevation)
    nperseg = max(8, min(n, round(segment_seconds / dt)))
    f, p = welch(result.wave_elevation, fs=1.0 / dt, window="hann", nperseg=nperseg, detrend="constant")
    return 2.0 * math.pi * f, p / (2.0 * math.pi)


def wave_spectrum(result: Result, title: str | None = None) -> Figure:
    """The realised spectrum of the elevation above the vehicle against the
    target spectrum, with the significant wave heights 4 sqrt(m0) of both."""
    waves = result.scenario.waves
    if waves is None:
        raise ValueError(f"run {result.scenario.name!r} has no waves (its scenario has no [waves] table)")
    omega, s = realised_spectrum(result)
    fine = np.linspace(1e-3, max(omega[-1], 4.0 * 2.0 * math.pi / waves.tp), 2000)
    target = target_spectrum(waves, fine)
    hs_realised = 4.0 * math.sqrt(trapezoid(s, omega))
    fig = Figure(figsize=(7.0, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(fine, target, color="black", label=f"target {waves.spectrum.name}, Hs {waves.hs:g} m, Tp {waves.tp:g} s")
    ax.plot(omega, s, color="tab:blue", linestyle="--",
            label=f"realised above the vehicle (Welch), Hs {hs_realised:.2f} m")
    ax.axvline(2.0 * math.pi / waves.tp, color="gray", linewidth=0.8, linestyle=":")
    ax.set_xlim(0.0, min(omega[-1], 6.0 * 2.0 * math.pi / waves.tp))
    ax.set_xlabel("ω [rad/s]")
    ax.set_ylabel("S(ω) [m² s/rad]")
    ax.grid(True, **_GRID)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or f"{result.scenario.name}: wave spectrum, {result.t[-1] - result.t[0]:g} s record")
    return fig


def _constant(series: np.ndarray) -> bool:
    """True if `series` (rows over time) holds one value all run long."""
    x = np.asarray(series, dtype=np.float64)
    return x.size == 0 or bool(np.all(np.ptp(x, axis=0) <= 1e-12 * max(1.0, float(np.max(np.abs(x))))))


def _values(series: np.ndarray, unit: str, names: tuple[str, ...] = ()) -> str:
    row = np.atleast_1d(np.asarray(series, dtype=np.float64)[0]) if len(series) else np.zeros(max(1, len(names)))
    if names:
        return ", ".join(f"{n} {v:g}" for n, v in zip(names, row)) + f" {unit}"
    return f"{row[0]:g} {unit}"


def sea_flow(result: Result, title: str | None = None) -> Figure:
    """The flow the vehicle met: the current and the orbital velocity at the
    vehicle (NED), the surface elevation above it and the payload in effect,
    one panel each for those that change during the run; those that do not
    (a constant current, no waves, no payload) are stated under the title
    instead of drawn flat. Rows where the vehicle was above the wave model's
    minimum depth are shaded. Each panel's legend is outside it, on the right."""
    r = for_plotting(result)
    quantities = [("current", "current [m/s]", r.current, "m/s", _AXES),
                  ("orbital velocity", "orbital velocity [m/s]", r.wave_velocity, "m/s", _AXES),
                  ("elevation above", "elevation above [m]", r.wave_elevation, "m", ()),
                  ("payload", "payload [kg]", r.payload_mass, "kg", ())]
    drawn = [q for q in quantities if not _constant(q[2])]
    constant = [f"{name} {_values(series, unit, names)}" for name, _, series, unit, names in quantities
                if _constant(series)]
    panels = max(1, len(drawn))
    fig = Figure(figsize=(8.0, 1.9 * panels + 1.0), layout="constrained")
    axes = list(fig.subplots(panels, 1, sharex=True, squeeze=False)[:, 0])
    for ax, (name, ylabel, series, _, names) in zip(axes, drawn):
        if names:
            for k in range(3):
                ax.plot(r.t, series[:, k], linewidth=1.0, label=f"{names[k]}")
            ax.plot(r.t, np.linalg.norm(series, axis=1), color="black", linewidth=0.8, label="|v|")
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0)
        elif name == "payload":
            ax.step(r.t, series, where="post", color="tab:brown")
        else:
            ax.plot(r.t, series, color="tab:blue", linewidth=1.0)
        ax.set_ylabel(ylabel)
        ax.set_gid(name)
    if not drawn:
        # Nothing changed: the values in words, not an empty panel.
        axes[0].set_axis_off()
        axes[0].text(0.5, 0.5, "constant all run:\n" + "\n".join(constant), transform=axes[0].transAxes,
                     ha="center", va="center", fontsize=10)
        constant = []
    else:
        axes[-1].set_xlabel("t [s]")
    shallow = (np.asarray(result.faults) & _SHALLOW_BIT) != 0
    for ax in axes:
        ax.grid(True, **_GRID)
        if shallow.any():
            ax.fill_between(result.t, 0, 1, where=shallow, transform=ax.get_xaxis_transform(),
                            color="tab:red", alpha=0.15, linewidth=0, step="post")
    heading = (title or f"{result.scenario.name}: the flow at the vehicle"
               + (" (red: above the wave model's minimum depth)" if shallow.any() else ""))
    if constant:
        heading += "\n" + "\n".join(textwrap.wrap("constant all run: " + "; ".join(constant), 90))
    axes[0].set_title(heading, fontsize=10)
    return fig
