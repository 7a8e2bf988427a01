"""The 3-D replay of one or more runs in the browser, behind ``neurov view``
and :meth:`neurov.Result.view` (needs ``neurov[view]``: plotly).

One self-contained HTML file (plotly.js inside, no network needed): the
vehicle as a body oriented by its Euler angles, its thrusters as arrows
scaled by thrust (a run with thrusters) or the applied force (one without),
the desired and the travelled path, the current and the wave velocity at the
vehicle, a time slider and play/pause, and the time and each vehicle's depth
above the scene. What is sampled and how it is scaled:
:mod:`neurov.replay.scene`.
"""

from __future__ import annotations

import base64
import html
import os
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from neurov.replay.scene import FACES, MAX_FRAMES, TOP_FACES, Scene, Track, build_scene, labels_for
from neurov.results.columns import is_result
from neurov.running.folder import writing

if TYPE_CHECKING:
    from neurov.results.timeseries import Result

__all__ = ["Replay", "replay"]

# One colour per result (plotly's qualitative "Plotly" set, which the
# default theme uses), the desired path black.
COLOURS = ("#636efa", "#ef553b", "#00cc96", "#ab63fa", "#ffa15a", "#19d3f3", "#ff6692", "#b6e880",
           "#ff97ff", "#fecb52")
_CURRENT, _WAVE = "#1f77b4", "#17becf"
# Playback: the whole run in about this long, but no frame shorter than _FASTEST_MS.
_PLAY_S, _FASTEST_MS = 20.0, 60


def _f32(a: Any, dtype: str = "f4") -> dict[str, str]:
    """An array as plotly.js's typed array (base64 of float32: 5.3 characters
    a number in the file rather than about 18 for its decimal text)."""
    data = np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<")).ravel()
    return {"dtype": dtype, "bdata": base64.b64encode(data.tobytes()).decode("ascii")}


def _xyz(points: np.ndarray) -> dict[str, Any]:
    return {"x": _f32(points[..., 0]), "y": _f32(points[..., 1]), "z": _f32(points[..., 2])}


def _segments(base: np.ndarray, vector: np.ndarray) -> dict[str, Any]:
    """Line segments base -> base + vector, (n, 3) each, as one line with gaps."""
    gap = np.full_like(base, np.nan)
    return _xyz(np.stack([base, base + vector, gap], axis=1).reshape(-1, 3))


def _heads(base: np.ndarray, vector: np.ndarray, reach: float) -> dict[str, Any]:
    """Cone heads at the arrows' tips, a third of the arrow long, at most a
    fifth of the longest arrow (so short arrows keep a visible shaft)."""
    length = np.linalg.norm(vector, axis=-1, keepdims=True)
    head = np.minimum(length / 3, 0.2 * reach)
    unit = np.divide(vector, length, out=np.zeros_like(vector), where=length > 0)
    d = unit * np.maximum(head, 1e-6 * reach)  # a zero arrow: a vanishing head, never a NaN
    return {**_xyz(base + vector), "u": _f32(d[:, 0]), "v": _f32(d[:, 1]), "w": _f32(d[:, 2])}


class _Traces:
    """The traces each frame updates: per result its body, its trail so far
    and its arrows (:attr:`parts`, in the order of the figure's traces)."""

    def __init__(self, scene: Scene) -> None:
        self.reach = scene.reach
        self.parts: list[tuple[int, Track, str, str, str]] = []  # (result, track, kind, colour, name)
        for i, t in enumerate(scene.tracks):
            colour = COLOURS[i % len(COLOURS)]
            scale = f", drawn {t.body_scale:g}x its size" if t.body_scale != 1 else ""
            self.parts += [(i, t, "body", colour, f"{t.label}: {t.vehicle}{scale}"),
                           (i, t, "trail", colour, f"{t.label}: so far")]
            if t.thrust_vector is not None:
                self.parts.append((i, t, "thrust", colour, f"{t.label}: thrusts (longest {scene.thrust_peak:.3g} N)"))
            else:
                self.parts.append((i, t, "force", colour,
                                   f"{t.label}: applied force X, Y, Z (longest {scene.force_peak:.3g} N)"))
            if t.current_vector is not None:
                self.parts.append((i, t, "current", _CURRENT, f"{t.label}: current (longest {scene.flow_peak:.3g} m/s)"))
            if t.wave_vector is not None:
                self.parts.append((i, t, "wave", _WAVE,
                                   f"{t.label}: wave velocity (longest {scene.flow_peak:.3g} m/s)"))
        self.count = sum(1 if kind in ("body", "trail") else 2 for _, _, kind, _, _ in self.parts)

    def at(self, f: int) -> list[Any]:
        """The moving traces at frame `f` (a line and a cone per arrow)."""
        out: list[dict[str, Any]] = []
        for i, t, kind, colour, name in self.parts:
            group = f"result {i}"
            if kind == "body":
                faces = [("#f2f2f2" if j in TOP_FACES else colour) for j in range(len(FACES))]
                out.append(dict(type="mesh3d", **_xyz(t.hull[f]), i=_f32(FACES[:, 0], "i4"),
                                j=_f32(FACES[:, 1], "i4"), k=_f32(FACES[:, 2], "i4"), facecolor=faces,
                                flatshading=True, name=name, legendgroup=group, showlegend=True,
                                hoverinfo="name"))
            elif kind == "trail":
                out.append(dict(type="scatter3d", mode="lines", line={"color": colour, "width": 6}, name=name,
                                legendgroup=group, showlegend=False, hoverinfo="skip",
                                **_xyz(t.position[: f + 1])))
            else:
                base, vector = _arrow(t, kind, f)
                out.append(dict(type="scatter3d", mode="lines", line={"color": colour, "width": 5}, name=name,
                                legendgroup=group, showlegend=True, hoverinfo="skip", **_segments(base, vector)))
                out.append(dict(type="cone", anchor="tip", sizemode="raw", sizeref=1.0, showscale=False,
                                colorscale=[[0, colour], [1, colour]], legendgroup=group, showlegend=False,
                                hoverinfo="skip", name=name, **_heads(base, vector, self.reach)))
        return out


def _arrow(track: Track, kind: str, f: int) -> tuple[np.ndarray, np.ndarray]:
    """The bases and vectors of a kind of arrow at frame `f`, (n, 3) each."""
    if kind == "thrust":
        assert track.thrust_base is not None and track.thrust_vector is not None
        return track.thrust_base[f], track.thrust_vector[f]
    vector = {"force": track.force_vector, "current": track.current_vector, "wave": track.wave_vector}[kind]
    assert vector is not None
    return track.position[f][None, :], vector[f][None, :]


_MOVING_KEYS = ("type", "x", "y", "z", "u", "v", "w")


def _figure(scene: Scene, title: str) -> dict[str, Any]:
    """The figure as plotly's JSON (plain dicts: plotly's own validation of
    150 frames took seconds); frames carry only what moves."""
    traces = _Traces(scene)
    static: list[dict[str, Any]] = []
    tracks = scene.tracks
    shared = all(np.array_equal(t.desired, tracks[0].desired) for t in tracks)
    for t in tracks[:1] if shared else tracks:
        static.append(dict(type="scatter3d", mode="lines", line={"color": "black", "width": 3, "dash": "dash"},
                           name="desired" if shared else f"{t.label}: desired", hoverinfo="skip", **_xyz(t.desired)))
    for i, t in enumerate(tracks):
        static.append(dict(type="scatter3d", mode="lines", line={"color": _light(COLOURS[i % len(COLOURS)]),
                                                                  "width": 2},
                           name=f"{t.label}: travelled", legendgroup=f"result {i}", hoverinfo="skip",
                           **_xyz(t.travelled)))
    moving = list(range(len(static), len(static) + traces.count))
    frames = [{"name": f"{f}", "traces": moving, "layout": {"title": {"text": _caption(title, scene, f)}},
               "data": [{k: v for k, v in trace.items() if k in _MOVING_KEYS} for trace in traces.at(f)]}
              for f in range(len(scene.times))]
    ms = max(_FASTEST_MS, int(1000 * _PLAY_S / max(len(scene.times), 1)))
    play = {"frame": {"duration": ms, "redraw": True}, "fromcurrent": True, "transition": {"duration": 0}}
    jump = {"frame": {"duration": 0, "redraw": True}, "mode": "immediate", "transition": {"duration": 0}}
    steps = [{"method": "animate", "label": f"{time:.1f}", "args": [[f"{f}"], jump]}
             for f, time in enumerate(scene.times)]
    size = scene.upper - scene.lower
    ratio = size / size[0]  # one scale on every axis (see neurov.replay.scene)
    axis = {"backgroundcolor": "#f7f9fc", "showbackground": True}
    lo, hi = scene.lower.tolist(), scene.upper.tolist()
    layout = dict(
        title={"text": _caption(title, scene, 0), "x": 0.02, "font": {"size": 14}},
        margin={"l": 0, "r": 0, "t": 40, "b": 0}, legend={"x": 0.0, "y": 0.95, "font": {"size": 11}},
        scene={"xaxis": {**axis, "title": {"text": "east, NED y [m]"}, "range": [lo[0], hi[0]]},
               "yaxis": {**axis, "title": {"text": "north, NED x [m]"}, "range": [lo[1], hi[1]]},
               "zaxis": {**axis, "title": {"text": "up = -depth (NED z flipped) [m]"}, "range": [lo[2], hi[2]]},
               "aspectmode": "manual", "aspectratio": dict(zip("xyz", map(float, ratio))),
               "camera": {"eye": {"x": -1.05, "y": -1.25, "z": 0.75}}},
        updatemenus=[{"type": "buttons", "direction": "left", "x": 0.02, "y": 0.02, "xanchor": "left",
                      "yanchor": "bottom", "showactive": False,
                      "buttons": [{"label": "Play", "method": "animate", "args": [None, play]},
                                  {"label": "Pause", "method": "animate", "args": [[None], jump]}]}],
        # The steps' own labels (150 of them) would overprint: only the current one is shown.
        sliders=[{"active": 0, "x": 0.2, "len": 0.78, "y": 0.02, "yanchor": "bottom", "steps": steps,
                  "ticklen": 0, "minorticklen": 0, "font": {"color": "rgba(0,0,0,0)"},
                  "currentvalue": {"prefix": "t = ", "suffix": " s", "font": {"color": "#444"}},
                  "pad": {"t": 0}}],
    )
    return {"data": static + traces.at(0), "layout": layout, "frames": frames}


def _light(colour: str) -> str:
    """`colour` (#rrggbb) mixed half with white: the whole travelled path under the bold trail so far."""
    rgb = [int(colour[k:k + 2], 16) for k in (1, 3, 5)]
    return "#" + "".join(f"{(c + 255) // 2:02x}" for c in rgb)


def _caption(title: str, scene: Scene, f: int) -> str:
    depths = " · ".join(f"{t.label} {t.depth[f]:.2f} m" for t in scene.tracks)
    return f"{title}   t = {scene.times[f]:.1f} s   depth: {depths}"


class Replay:
    """A replay: :attr:`figure` (the plotly Figure with its frames), written
    as one self-contained HTML file by :meth:`write_html`, shown inline in
    Jupyter (:meth:`_repr_html_`: the same page in an iframe, so that the
    notebook's own scripts and styles do not meet plotly's)."""

    def __init__(self, spec: dict[str, Any], scene: Scene) -> None:
        self.spec = spec
        """The figure as plotly JSON (dicts)."""
        self.scene = scene

    @property
    def figure(self) -> Any:
        """The replay as a ``plotly.graph_objects.Figure`` (checked by plotly:
        a few seconds for 150 frames)."""
        import plotly.graph_objects as go

        return go.Figure(self.spec)

    def html(self) -> str:
        """The whole page, plotly.js inside (no network needed to open it)."""
        import plotly.io as pio

        return str(pio.to_html(self.spec, include_plotlyjs=True, full_html=True, auto_play=False,
                               validate=False, config={"displaylogo": False}))

    def write_html(self, path: str | os.PathLike[str]) -> Path:
        """Writes :meth:`html` to `path` (a new file beside it first, then
        renamed over it: an old replay there stays whole until the new one is)."""
        path = Path(path)
        part = path.with_name(f".{path.name}.part")
        with writing(path):
            try:
                part.write_text(self.html(), encoding="utf-8")
                os.replace(part, path)
            finally:
                part.unlink(missing_ok=True)
        return path

    def _repr_html_(self) -> str:
        return (f'<iframe srcdoc="{html.escape(self.html(), quote=True)}" '
                'style="width: 100%; height: 640px; border: none"></iframe>')


def replay(results: Result | Sequence[Result], labels: Sequence[str] | None = None, *,
           title: str | None = None, max_frames: int = MAX_FRAMES, names: Sequence[str] | None = None) -> Replay:
    """The replay of `results` on one path: each labelled by `labels`
    (default: its controller, told apart by `names` or the scenario where
    two share one), at most `max_frames` frames."""
    runs = [results] if is_result(results) else list(results)
    if not runs:
        raise ValueError("results: expected at least one Result")
    for i, r in enumerate(runs):
        if not is_result(r):
            raise TypeError(f"results[{i}]: expected a neurov Result, got {type(r).__name__}")
        if not len(r.t):
            raise ValueError(f"results[{i}] ({r.controller}): a run without rows cannot be replayed")
    if isinstance(max_frames, bool) or not isinstance(max_frames, int) or max_frames < 2:
        raise ValueError(f"max_frames: expected an integer >= 2, got {max_frames!r}")
    try:
        import plotly  # noqa: F401
    except ImportError:
        raise ImportError("the replay needs plotly: pip install 'neurov[view]'") from None
    scene = build_scene(runs, labels_for(runs, labels, names), max_frames)
    scenarios = sorted({r.scenario.name for r in runs})
    return Replay(_figure(scene, title if title is not None else ", ".join(scenarios)), scene)
