"""The estimator's velocity lag, estimated from the data.

An estimator that fuses a DVL at a few Hz with a kinematic model (an EKF
that does not know the forces) gives a linear velocity that lags the motion;
a lag reads as extra inertia. Like a model's input delay (the delay search of
classical system identification: fit each candidate, keep the one that
predicts best), the lag is the whole number of rows by which moving the
logged linear velocities earlier gives the smallest output-error residual:
the fitted model's prediction of the velocity from the force that acted
(stage 1's residual is no judge: its errors in the variables bias it, and
measured on ``bluerov2_excitation_realistic`` its minimum is one row past
the true lag, while stage 2's is on it)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from neurov.identification.errors import IdentificationError
from neurov.identification.log import Log, advance_linear_velocity

__all__ = ["MAX_LAG_S", "profile_lag"]

T = TypeVar("T")

# The longest lag tried [s]: several DVL periods of a slow one.
MAX_LAG_S = 0.5


def profile_lag(logs: list[Log], fit: Callable[[list[Log]], T], rms: Callable[[T], float],
                max_s: float = MAX_LAG_S) -> tuple[float, list[Log], T, list[tuple[float, float]]]:
    """Fits the logs moved 0, 1, 2, ... rows (`fit`), up to `max_s`, and
    stops once the residual (`rms` of a fit) has risen past its smallest
    (the profile measured on the realistic excitation runs has one minimum).
    Returns the lag [s], the moved logs and the fit at it, and the profile
    (lag, rms) of every lag tried."""
    dt = max(log.dt for log in logs)
    if not max_s >= 0:
        raise IdentificationError(f"velocity_lag: the longest lag tried must be >= 0 s, got {max_s}")
    best: tuple[float, float, list[Log], T] | None = None
    profile: list[tuple[float, float]] = []
    for rows in range(int(max_s / dt + 1e-9) + 1):
        lag = rows * dt
        try:
            moved = [advance_linear_velocity(log, lag) for log in logs]
        except IdentificationError:
            break  # segments too short for this lag: longer ones are too
        result = fit(moved)
        r = rms(result)
        profile.append((lag, r))
        if best is None or r < best[1]:
            best = (lag, r, moved, result)
        elif r > best[1]:
            break
    if best is None:
        raise IdentificationError("velocity_lag='auto': no lag could be tried (segments too short)")
    return best[0], best[2], best[3], profile
