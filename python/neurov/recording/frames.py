"""neurov's frames to ROS's and back (REP 103, REP 105).

neurov simulates in a north-east-down world (``map_ned``) and a
forward-starboard-down body (``base_link_frd``); ROS tools expect an
east-north-up world (``map``) and a forward-left-up body (``base_link``).
The two world frames differ by R_enu_ned (x and y swapped, z negated), the
two body frames by a half turn about x (y and z negated), so

    R_enu_flu = R_enu_ned R_ned_frd R_frd_flu = Rz(pi/2 - psi) Ry(-theta) Rx(phi),

position (x, y, z)_ned -> (y, x, -z)_enu, body vectors (velocities, forces,
torques) (x, y, z)_frd -> (x, -y, -z)_flu. Both maps are their own inverse.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

__all__ = ["BODY_FLU_FROM_FRD", "WORLD_ENU_FROM_NED", "body_to_flu", "enu_quaternions",
           "euler_from_enu_quaternions", "position_to_enu"]

Array = NDArray[np.float64]

# The static transforms of /tf_static as quaternions (x, y, z, w): the
# rotation of map_ned in map (a half turn about (1, 1, 0)/sqrt 2) and of
# base_link_frd in base_link (a half turn about x).
WORLD_ENU_FROM_NED = (np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0)
BODY_FLU_FROM_FRD = (1.0, 0.0, 0.0, 0.0)


def position_to_enu(p: Array) -> Array:
    """(n, 3) NED positions as ENU (and back: the map is its own inverse)."""
    p = np.asarray(p, dtype=np.float64)
    return np.column_stack([p[:, 1], p[:, 0], -p[:, 2]])


def body_to_flu(v: Array) -> Array:
    """(n, 3) or (n, 6) FRD body vectors as FLU (and back)."""
    v = np.asarray(v, dtype=np.float64)
    flip = np.tile([1.0, -1.0, -1.0], v.shape[1] // 3)
    return v * flip


def enu_quaternions(euler: Array) -> Array:
    """(n, 4) quaternions (x, y, z, w) of base_link in map for (n, 3) NED
    Euler angles (phi, theta, psi, ZYX)."""
    e = np.asarray(euler, dtype=np.float64)
    return Rotation.from_euler("ZYX", np.column_stack([np.pi / 2 - e[:, 2], -e[:, 1], e[:, 0]])).as_quat()


def euler_from_enu_quaternions(q: Array) -> Array:
    """(n, 3) NED Euler angles (phi, theta, psi) of (n, 4) ENU/FLU
    quaternions (x, y, z, w): the inverse of :func:`enu_quaternions`, the
    heading in (-pi, pi]."""
    zyx = Rotation.from_quat(np.asarray(q, dtype=np.float64)).as_euler("ZYX")
    psi = (np.pi / 2 - zyx[:, 0] + np.pi) % (2 * np.pi) - np.pi
    return np.column_stack([zyx[:, 2], -zyx[:, 1], psi])
