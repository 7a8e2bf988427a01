"""What the 3-D replay draws, as numbers (no plotting library here): the
frames' times, the vehicle's body and thrusters, and each frame's arrows,
in display coordinates.

Display coordinates: x east, y north, z up (= -depth). This is NED with x
and y swapped and z flipped, a proper rotation (determinant +1), so the
vehicle is not mirrored, and the horizontal view is the run plots' map
(east to the right, north up).

Frames: at most ``max_frames`` times, evenly spaced from the earliest start
to the latest end of the results; each result shows its last row at or
before the frame's time (a run that ended early, diverged say, stays where
it stopped; rows whose pose is not finite are passed over). Only the frames are decimated: the paths are drawn from every
row (at most :data:`MAX_PATH_POINTS` points each).

Sizes: a vehicle is a few tenths of a metre on a path of tens of metres, so
its body (and its thrusters' positions) is drawn enlarged by a round factor
(1, 2, 5, 10, ...) to at least :data:`BODY_SHARE` of the scene's extent; the
legend says the factor. Arrows are scaled by the largest value of their kind
over every result and frame, which gets an arrow as long as the longest
drawn body; the legend says that value.

Absurd values: a finite value no run can have (a position beyond
:data:`MAX_POSITION_M`, a force or thrust beyond :data:`MAX_FORCE_N`, a
flow beyond :data:`MAX_FLOW_M_S`: a damaged file, say, holding 1e300) would
set the scene's extent or an arrow's scale and shrink everything else to a
point. Such values are passed over as a non-finite one is (a pose: its rows
are not drawn; an arrow: not drawn in those rows), and the scene's
``notes`` say which, how many and from when; ``neurov view`` prints them
and :func:`build_scene` warns (:class:`AbsurdValuesWarning`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core

if TYPE_CHECKING:
    from neurov.results.timeseries import Result

__all__ = ["AbsurdValuesWarning", "BODY_SHARE", "MAX_FLOW_M_S", "MAX_FORCE_N", "MAX_FRAMES", "MAX_PATH_POINTS",
           "MAX_POSITION_M", "NED_TO_DISPLAY", "Scene", "Track", "build_scene"]

Array = NDArray[np.float64]

MAX_FRAMES = 150
"""Frames of a replay by default: 0.5 MB of the file for one run of
``paper_fig3``, beside plotly.js's 4.8 MB (docs/replay.md)."""
MAX_PATH_POINTS = 5000
"""Points of a drawn path at most (every k-th row and the last)."""
BODY_SHARE = 0.1
"""The body is drawn at least this share of the scene's extent long."""
MAX_POSITION_M = 1e7
"""The farthest position drawn [m] from the origin along an axis: a quarter of
the Earth's circumference; beyond it a pose is absurd (see the module)."""
MAX_FORCE_N = 1e9
"""The largest force or thrust drawn [N]: a thousand times a ship's largest
thruster."""
MAX_FLOW_M_S = 1e3
"""The fastest current or wave velocity drawn [m/s]."""

# The series checked, each a (name, columns or None for all, bound, unit): a row beyond is passed over.
_BOUNDS = (("eta", slice(0, 3), MAX_POSITION_M, "m"), ("eta_d", slice(0, 3), MAX_POSITION_M, "m"),
           ("thrusts", slice(None), MAX_FORCE_N, "N"), ("tau_applied", slice(0, 3), MAX_FORCE_N, "N"),
           ("current", slice(None), MAX_FLOW_M_S, "m/s"), ("wave_velocity", slice(None), MAX_FLOW_M_S, "m/s"))


class AbsurdValuesWarning(UserWarning):
    """A result holds finite values no run can have; they are not drawn."""

NED_TO_DISPLAY = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
"""NED (x north, y east, z down) to display (x east, y north, z up)."""

# Faces of the eight-corner hull: 0-3 the stern face, 4-7 the (smaller) bow
# face, corners in the order (-y,-z), (+y,-z), (+y,+z), (-y,+z).
FACES = np.array([(0, 1, 2), (0, 2, 3), (4, 6, 5), (4, 7, 6), (0, 1, 5), (0, 5, 4),
                  (3, 6, 2), (3, 7, 6), (0, 4, 7), (0, 7, 3), (1, 5, 6), (1, 6, 2)])
TOP_FACES = (4, 5)
"""The deck (body -z): drawn lighter, so that up and down read at a glance."""


@dataclass
class Track:
    """One result's frames, in display coordinates [m]."""

    label: str
    rows: NDArray[np.int64]  #: (F,) the row each frame shows
    position: Array  #: (F, 3)
    depth: Array  #: (F,) [m], NED z
    hull: Array  #: (F, 8, 3) the body's corners
    thrust_base: Array | None = None  #: (F, n, 3)
    thrust_vector: Array | None = None  #: (F, n, 3) scaled
    force_vector: Array | None = None  #: (F, 3) scaled, at the body's centre
    current_vector: Array | None = None  #: (F, 3) scaled
    wave_vector: Array | None = None  #: (F, 3) scaled
    travelled: Array = field(default_factory=lambda: np.zeros((0, 3)))  #: every row (thinned)
    desired: Array = field(default_factory=lambda: np.zeros((0, 3)))
    body_scale: float = 1.0
    vehicle: str = ""


@dataclass
class Scene:
    """Every track on one set of frames, with the arrows' common scales."""

    times: Array  #: (F,) [s]
    tracks: list[Track]
    thrust_peak: float = 0.0  #: [N], the longest thrust arrow
    force_peak: float = 0.0  #: [N], the longest applied-force arrow
    flow_peak: float = 0.0  #: [m/s], the longest current or wave arrow
    reach: float = 1.0  #: [m] the longest arrow: the largest drawn body's largest extent
    lower: Array = field(default_factory=lambda: np.zeros(3))  #: the scene's box
    upper: Array = field(default_factory=lambda: np.ones(3))
    notes: list[str] = field(default_factory=list)  #: absurd values passed over (see the module)


def _passed_over(result: Result, label: str) -> tuple[Result, list[str]]:
    """`result` with its absurd values (see the module) made NaN, so that
    they are passed over as non-finite ones are, and a note for each series."""
    changed: dict[str, Array] = {}
    notes = []
    for name, columns, bound, unit in _BOUNDS:
        values = np.asarray(getattr(result, name), dtype=np.float64)
        if values.ndim != 2 or not values.size:
            continue
        part = values[:, columns]
        # Finite only: NaN and inf are passed over already, as a diverged run's last rows are.
        bad = np.any(np.isfinite(part) & (np.abs(part) > bound), axis=1)
        if not bad.any():
            continue
        first = int(np.flatnonzero(bad)[0])
        worst = float(np.max(np.abs(part[bad]), where=np.isfinite(part[bad]), initial=0.0))
        notes.append(f"{label}: {name} beyond {bound:g} {unit} in {int(bad.sum())} of {len(bad)} rows (first at "
                     f"t = {result.t[first]:g} s, up to {worst:.3g} {unit}): absurd for any run, not drawn")
        copy = values.copy()
        copy[bad] = np.nan
        changed[name] = copy
    return (dataclasses.replace(result, **changed) if changed else result), notes


def frame_times(results: Sequence[Result], max_frames: int) -> Array:
    """At most `max_frames` evenly spaced times covering every result."""
    starts = [r.t[0] for r in results]
    ends = [r.t[-1] for r in results]
    count = min(max_frames, max(len(r.t) for r in results))
    return np.linspace(min(starts), max(ends), max(count, 1))


def _rows(result: Result, times: Array) -> NDArray[np.int64]:
    """The row each frame shows: the last at or before its time whose pose
    is finite (a diverged run's last rows may not be)."""
    rows = np.clip(np.searchsorted(result.t, times, side="right") - 1, 0, len(result.t) - 1)
    finite = np.all(np.isfinite(result.eta), axis=1)
    last_finite = np.maximum.accumulate(np.where(finite, np.arange(len(finite)), 0))
    return last_finite[rows]


def _thinned(points: Array) -> Array:
    if not len(points):
        return points
    step = max(1, math.ceil(len(points) / MAX_PATH_POINTS))
    keep = np.unique(np.r_[np.arange(0, len(points), step), len(points) - 1])
    return points[keep]


def _display(ned: Array) -> Array:
    """NED points in display axes (NED_TO_DISPLAY, as a permutation: an
    infinite coordinate stays where it is rather than making NaNs)."""
    return ned[..., [1, 0, 2]] * np.array([1.0, 1.0, -1.0])


def _path(ned: Array) -> Array:
    """A drawn path: its finite points, in display axes, thinned."""
    return _thinned(_display(ned[np.all(np.isfinite(ned), axis=1)]))


def _layout(result: Result) -> tuple[Array, Array | None, Array | None, str]:
    """The body's half extents (x, y, z), the thrusters' positions and unit
    directions (None without thrusters in the run) and the vehicle's name."""
    data = result.scenario.vehicle_data()
    name = str(data.parameters.get("name") or data.path.stem)
    t = data.thrusters
    positions = directions = None
    if t is not None:
        matrix = np.asarray(t["matrix"], dtype=np.float64)
        directions = matrix[:3].T / np.linalg.norm(matrix[:3].T, axis=1, keepdims=True)
        # Without positions (a file giving the matrix), the point of each line
        # of action nearest the centre: r = d x (r x d) for a unit d.
        given = t.get("positions")
        positions = (np.asarray(given, dtype=np.float64) if given is not None
                     else np.cross(directions, matrix[3:].T))
        half = np.abs(positions).max(axis=0)
        half = half + 0.15 * half.max()
        half[2] = max(half[2], 0.35 * half[0])
    else:
        volume = data.displaced_volume or float(data.parameters["mass"]) / 1025.0
        length = (4.0 * volume) ** (1 / 3)  # a box L x L/2 x L/2
        half = np.array([length / 2, length / 4, length / 4])
    if not result.scenario.use_thrusters or positions is None or result.thrusts.shape[1] != len(positions):
        return half, None, None, name
    return half, positions, directions, name


def _hull(half: Array) -> Array:
    hx, hy, hz = half
    stern = [(-hx, -hy, -hz), (-hx, hy, -hz), (-hx, hy, hz), (-hx, -hy, hz)]
    bow = [(hx, -0.5 * hy, -0.6 * hz), (hx, 0.5 * hy, -0.6 * hz), (hx, 0.5 * hy, 0.6 * hz),
           (hx, -0.5 * hy, 0.6 * hz)]
    return np.array(stern + bow)


def _round_up(x: float) -> float:
    """The least of 1, 2, 5, 10, 20, ... that is >= x."""
    if x <= 1.0:
        return 1.0
    decade = 10.0 ** math.floor(math.log10(x))
    return next(m * decade for m in (1.0, 2.0, 5.0, 10.0) if m * decade >= x * (1 - 1e-12))


def _rotations(eta: Array) -> Array:
    """(F, 3, 3): body to display."""
    return np.array([NED_TO_DISPLAY @ _core.rotation(float(p), float(q), float(r)) for p, q, r in eta[:, 3:]])


def _peak(values: list[Array], axis: int) -> float:
    finite = [np.nan_to_num(np.linalg.norm(v, axis=axis) if axis >= 0 else np.abs(v), posinf=0.0, neginf=0.0)
              for v in values if v.size]
    return float(max((f.max() for f in finite if f.size), default=0.0))


def build_scene(results: Sequence[Result], labels: Sequence[str], max_frames: int = MAX_FRAMES) -> Scene:
    """The frames of `results` (labelled `labels`), sampled as the module says."""
    checked = [_passed_over(r, label) for r, label in zip(results, labels)]
    results = [r for r, _ in checked]
    notes = [n for _, said in checked for n in said]
    for note in notes:
        warnings.warn(note, AbsurdValuesWarning, stacklevel=2)
    times = frame_times(results, max_frames)
    layouts = [_layout(r) for r in results]
    paths = [(_path(r.eta[:, :3]), _path(r.eta_d[:, :3])) for r in results]
    finite = np.vstack([p for pair in paths for p in pair] + [np.zeros((0, 3))])
    if not len(finite):
        finite = np.zeros((1, 3))
    lower, upper = finite.min(axis=0), finite.max(axis=0)
    extent = float(max((upper - lower).max(), 1.0))
    scales = [_round_up(BODY_SHARE * extent / (2 * half.max())) for half, *_ in layouts]
    reach = max(2 * half.max() * k for (half, *_), k in zip(layouts, scales))  # the longest arrow

    rows = [_rows(r, times) for r in results]
    with_thrusters = [i for i, lay in enumerate(layouts) if lay[1] is not None]
    thrust_peak = _peak([results[i].thrusts[rows[i]] for i in with_thrusters], -1)
    force_peak = _peak([r.tau_applied[k, :3] for i, (r, k) in enumerate(zip(results, rows))
                        if i not in with_thrusters], 1)
    flow_peak = _peak([a[k] for r, k in zip(results, rows) for a in (r.current, r.wave_velocity)], 1)

    def scaled(peak: float) -> float:
        return reach / peak if peak > 0 else 0.0

    tracks = []
    for i, (r, k, (half, positions, directions, vehicle), scale) in enumerate(zip(results, rows, layouts, scales)):
        eta = np.nan_to_num(r.eta[k])
        rot = _rotations(eta)
        position = _display(eta[:, :3])
        track = Track(label=labels[i], rows=k, position=position, depth=r.eta[k, 2],
                      hull=position[:, None, :] + scale * np.einsum("fij,vj->fvi", rot, _hull(half)),
                      travelled=paths[i][0], desired=paths[i][1],
                      body_scale=scale, vehicle=vehicle)
        if positions is not None and directions is not None:
            track.thrust_base = position[:, None, :] + scale * np.einsum("fij,nj->fni", rot, positions)
            along = np.einsum("fij,nj->fni", rot, directions)
            track.thrust_vector = along * (np.nan_to_num(r.thrusts[k]) * scaled(thrust_peak))[:, :, None]
        else:
            track.force_vector = np.einsum("fij,fj->fi", rot, np.nan_to_num(r.tau_applied[k, :3])) \
                * scaled(force_peak)
        if np.any(r.current):
            track.current_vector = _display(np.nan_to_num(r.current[k])) * scaled(flow_peak)
        if np.any(r.wave_velocity):
            track.wave_vector = _display(np.nan_to_num(r.wave_velocity[k])) * scaled(flow_peak)
        tracks.append(track)
    # One scale on every axis (the body undistorted): a square map, and a
    # depth axis of at least a quarter of its width (a flat path keeps one).
    centre, margin = (lower + upper) / 2, 0.5 * reach
    half = np.full(3, max((upper - lower)[:2].max() / 2 + margin, 1.0))
    half[2] = max((upper - lower)[2] / 2 + margin, 0.25 * half[0])
    return Scene(times=times, tracks=tracks, thrust_peak=thrust_peak, force_peak=force_peak,
                 flow_peak=flow_peak, reach=reach, lower=centre - half, upper=centre + half, notes=notes)


def labels_for(results: Sequence[Result], given: Sequence[str] | None = None,
               names: Sequence[str] | None = None) -> list[str]:
    """`given`, else each result's controller, told apart by `names` (or the
    scenario) where two share a controller."""
    if given is not None:
        if len(given) != len(results):
            raise ValueError(f"labels: expected {len(results)} labels (one per result), got {len(given)}")
        return [str(x) for x in given]
    controllers = [r.controller for r in results]
    out: list[Any] = []
    for i, r in enumerate(results):
        shared = controllers.count(r.controller) > 1
        other = names[i] if names is not None else r.scenario.name
        out.append(f"{r.controller} ({other})" if shared else r.controller)
    if len(set(out)) < len(out):
        out = [f"{x} #{i + 1}" for i, x in enumerate(out)]
    return out
