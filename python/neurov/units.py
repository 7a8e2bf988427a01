"""The units of everything printed, tabled or drawn for people, said once.

**Angles are shown in degrees** (and angular rates in deg/s) in every
printout, Markdown table and figure of neurov. Files written for programs
(``runs.csv``, ``metrics.json``, ``result.npz``) keep SI, radians, with the
unit in the column name (``rmse_yaw_rad``); a column or label shown to people
passes through :func:`for_people`, which turns a radian unit into degrees and
gives the factor its values are multiplied by.

Forces and moments are in N and N m; ``mean_abs_tau`` and ``max_abs_tau``
mix the two (over the six DOFs), hence ``[N, N m]``.
"""

from __future__ import annotations

import math
import re

__all__ = ["ANGLE_UNIT", "DEGREES_PER_RADIAN", "for_people", "label_for_people"]

#: The angle unit of every printout, table and figure.
ANGLE_UNIT = "deg"
DEGREES_PER_RADIAN = 180.0 / math.pi

# A radian unit: "rad", "rad/s", "rad s" (an integral over time).
_RAD = re.compile(r"\brad\b")


def for_people(unit: str) -> tuple[str, float]:
    """`unit` as shown to people and the factor that turns a value in `unit`
    into one in the shown unit: ``("deg", 57.29...)`` for ``"rad"``,
    ``("deg/s", ...)`` for ``"rad/s"``, ``(unit, 1.0)`` for anything else."""
    if _RAD.search(unit) and "/rad" not in unit:  # not a quantity per radian
        return _RAD.sub(ANGLE_UNIT, unit), DEGREES_PER_RADIAN
    return unit, 1.0


def label_for_people(label: str) -> tuple[str, float]:
    """A label ending in ``[unit]`` with its unit :func:`for_people`, and the
    factor for its values (1.0 when the label has no bracketed unit)."""
    m = re.search(r"\[([^\[\]]*)\]\s*$", label)
    if m is None:
        return label, 1.0
    unit, factor = for_people(m.group(1))
    return label[: m.start(1)] + unit + label[m.end(1):], factor
