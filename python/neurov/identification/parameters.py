"""The parameters the regressor holds (theta, 24 entries, see
``neurov._core.THETA_NAMES``) and the vehicle file's fields they are.

theta = (m, I_x, I_y, I_z, the six added masses, six linear and six
quadratic damping coefficients, W - B, z_g W - z_b B). Of the restoring
terms only the net weight W - B and the restoring moment z_g W - z_b B act
on the motion; the fitted file keeps the template's W and r_g and writes
B = W - (W - B) and z_b = (z_g W - (z_g W - z_b B)) / B."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.identification.errors import IdentificationError

__all__ = ["DEFAULT_FREE", "GROUPS", "UNITS", "free_indices", "template_theta", "vehicle_parameters"]

GROUPS: dict[str, tuple[int, ...]] = {
    "mass": (0,),
    "inertia": (1, 2, 3),
    "added_mass": tuple(range(4, 10)),
    "linear_damping": tuple(range(10, 16)),
    "quadratic_damping": tuple(range(16, 22)),
    "restoring": (22, 23),
}
DEFAULT_FREE = ("added_mass", "linear_damping", "quadratic_damping")
NAMES: tuple[str, ...] = tuple(_core.THETA_NAMES)
# The unit of each entry of theta (SI; the rotational DOF per radian).
_LIN, _ROT = ("kg", "N s/m", "N s^2/m^2"), ("kg m^2", "N m s/rad", "N m s^2/rad^2")
UNITS: tuple[str, ...] = ("kg", "kg m^2", "kg m^2", "kg m^2",
                          *(u for group in range(3) for u in (_LIN[group],) * 3 + (_ROT[group],) * 3),
                          "N", "N m")


def free_indices(free: str | list[str] | tuple[str, ...] | None) -> list[int]:
    """Indices into theta of the free parameters: group names (``mass``,
    ``inertia``, ``added_mass``, ``linear_damping``, ``quadratic_damping``,
    ``restoring``) or single names of THETA_NAMES, comma-separated or a list."""
    items = list(DEFAULT_FREE) if free is None else (
        [s.strip() for s in free.split(",")] if isinstance(free, str) else list(free))
    out: set[int] = set()
    for item in items:
        if item in GROUPS:
            out.update(GROUPS[item])
        elif item in NAMES:
            out.add(NAMES.index(item))
        else:
            raise IdentificationError(
                f"free: unknown parameter {item!r}; expected a group of {sorted(GROUPS)} or one of "
                f"{list(NAMES)}")
    if not out:
        raise IdentificationError("free: no parameter to fit")
    return sorted(out)


def template_theta(vehicle: Any, where: str) -> NDArray[np.float64]:
    """theta of the template vehicle; a template outside the regressor's
    structure (an off-diagonal inertia, r_g != 0, ...) is refused naming the field."""
    try:
        return np.asarray(_core.regressor_parameters(vehicle), dtype=np.float64)
    except ValueError as e:
        raise IdentificationError(f"{where}: the template is outside the identified model: {e}") from None


def vehicle_parameters(template: dict[str, Any], theta: NDArray[np.float64]) -> dict[str, Any]:
    """The keyword arguments of :class:`neurov.Vehicle` with theta's values:
    the template's with mass, inertia, added mass, damping, buoyancy and
    z_b replaced (the template's W and r_g kept)."""
    p = dict(template)
    p["mass"] = float(theta[0])
    p["inertia"] = [float(x) for x in theta[1:4]]
    p["added_mass"] = [float(x) for x in theta[4:10]]
    p["linear_damping"] = [float(x) for x in theta[10:16]]
    p["quadratic_damping"] = [float(x) for x in theta[16:22]]
    weight = float(p["weight"])
    buoyancy = weight - float(theta[22])
    p["buoyancy"] = buoyancy
    p.pop("displaced_volume", None)
    rg = [float(x) for x in (p.get("centre_of_gravity") or [0.0, 0.0, 0.0])]
    rb = [float(x) for x in (p.get("centre_of_buoyancy") or [0.0, 0.0, 0.0])]
    if buoyancy > 0:
        rb[2] = (rg[2] * weight - float(theta[23])) / buoyancy
    p["centre_of_buoyancy"] = rb
    return p
