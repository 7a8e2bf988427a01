"""Commanded trajectories: timed poses r(t) for the reference model.

Each generator returns ``(times, poses)`` with ``times`` (K,) increasing and
``poses`` (K, 6) = [x, y, z, phi, theta, psi] in NED (z down, so a positive z
is a depth). The closed loop interpolates between them (linearly, or held)
and the reference model smooths the result.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["circle", "helix", "lawnmower", "square", "waypoints"]

Timed = tuple[NDArray[np.float64], NDArray[np.float64]]


def _check_positive(name: str, value: float) -> None:
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"argument '{name}' must be > 0 and finite, got {value!r}")


def waypoints(times: object, poses: object) -> Timed:
    """Timed poses as given, checked: times (K,) strictly increasing, poses (K, 6)."""
    t = np.asarray(times, dtype=np.float64)
    p = np.asarray(poses, dtype=np.float64)
    if t.ndim != 1 or t.size < 1:
        raise ValueError(f"argument 'times' must be a non-empty 1-D list, got shape {t.shape}")
    if p.shape != (t.size, 6):
        raise ValueError(f"argument 'poses' must have shape ({t.size}, 6), got {p.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
        raise ValueError("arguments 'times' and 'poses' must be finite")
    if np.any(np.diff(t) <= 0):
        raise ValueError("argument 'times' must be strictly increasing")
    return t, p


def _unwrap_heading(poses: NDArray[np.float64]) -> NDArray[np.float64]:
    # Headings as a continuous angle so the reference never swings the long way round.
    poses[:, 5] = np.unwrap(poses[:, 5])
    return poses


def _legs(corners: NDArray[np.float64], speed: float, depth: float, start: float,
          face_travel: bool, turn_time: float) -> Timed:
    """Visits corners (M, 2) in the horizontal plane at `speed`; with
    face_travel the heading turns to each leg's direction at its start, taking
    turn_time while holding position."""
    times = [start]
    first_leg = corners[1] - corners[0]
    psi0 = float(np.arctan2(first_leg[1], first_leg[0])) if face_travel else 0.0
    poses = [[corners[0, 0], corners[0, 1], depth, 0.0, 0.0, psi0]]
    t = start
    for a, b in zip(corners[:-1], corners[1:]):
        heading = float(np.arctan2(b[1] - a[1], b[0] - a[0])) if face_travel else 0.0
        if face_travel:
            t += turn_time
            times.append(t)
            poses.append([a[0], a[1], depth, 0.0, 0.0, heading])
        t += float(np.hypot(*(b - a))) / speed
        times.append(t)
        poses.append([b[0], b[1], depth, 0.0, 0.0, heading])
    return np.asarray(times), _unwrap_heading(np.asarray(poses, dtype=np.float64))


def square(side: float = 10.0, speed: float = 0.25, depth: float = 2.0, start: float = 5.0,
           face_travel: bool = True, turn_time: float = 10.0) -> Timed:
    """A closed square of the given side from the origin: north, east, south,
    west. The vehicle faces along each leg (turning on the spot between legs,
    `turn_time` seconds) when `face_travel`, so X, Y, depth and heading are all
    exercised."""
    _check_positive("side", side)
    _check_positive("speed", speed)
    _check_positive("turn_time", turn_time)
    c = np.array([[0, 0], [side, 0], [side, side], [0, side], [0, 0]], dtype=np.float64)
    return _legs(c, speed, depth, start, face_travel, turn_time)


def lawnmower(width: float = 20.0, spacing: float = 5.0, lanes: int = 4, speed: float = 0.25,
              depth: float = 2.0, start: float = 5.0, face_travel: bool = True,
              turn_time: float = 10.0) -> Timed:
    """A survey pattern: `lanes` parallel legs of length `width` along x,
    `spacing` apart in y, joined at alternate ends."""
    _check_positive("width", width)
    _check_positive("spacing", spacing)
    _check_positive("speed", speed)
    if int(lanes) != lanes or lanes < 1:
        raise ValueError(f"argument 'lanes' must be a positive integer, got {lanes!r}")
    corners = []
    for i in range(int(lanes)):
        xs = (0.0, width) if i % 2 == 0 else (width, 0.0)
        corners += [[xs[0], i * spacing], [xs[1], i * spacing]]
    return _legs(np.asarray(corners, dtype=np.float64), speed, depth, start, face_travel, turn_time)


def circle(radius: float = 8.0, period: float = 150.0, depth: float = 2.0, turns: float = 1.0,
           start: float = 5.0, points_per_turn: int = 72, face_travel: bool = True) -> Timed:
    """A circle of `radius` about (0, radius) starting at the origin heading
    north, `period` seconds a turn; with face_travel the heading follows the
    tangent."""
    return helix(radius=radius, period=period, depth_start=depth, depth_change=0.0, turns=turns,
                 start=start, points_per_turn=points_per_turn, face_travel=face_travel)


def helix(radius: float = 8.0, period: float = 150.0, depth_start: float = 0.0,
          depth_change: float = 5.0, turns: float = 1.0, start: float = 5.0,
          points_per_turn: int = 72, face_travel: bool = True) -> Timed:
    """A helix: the circle of :func:`circle` while the depth changes by
    `depth_change` over the `turns`."""
    _check_positive("radius", radius)
    _check_positive("period", period)
    _check_positive("turns", turns)
    if not np.isfinite(depth_start) or not np.isfinite(depth_change):
        raise ValueError("arguments 'depth_start' and 'depth_change' must be finite")
    k = max(2, int(np.ceil(points_per_turn * turns)) + 1)
    phase = np.linspace(0.0, 2 * np.pi * turns, k)
    times = start + phase / (2 * np.pi) * period
    poses = np.zeros((k, 6))
    poses[:, 0] = radius * np.sin(phase)
    poses[:, 1] = radius * (1 - np.cos(phase))
    poses[:, 2] = depth_start + depth_change * phase / phase[-1]
    if face_travel:
        poses[:, 5] = phase
    return times, poses
