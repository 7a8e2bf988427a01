"""An independent numpy implementation of the model in docs/model.md (Fossen's
equations written from the textbook, not from the C++), so that the tests can
check the compiled core against it. Nothing here imports neurov."""

from __future__ import annotations

from typing import Any

import numpy as np

Array = np.ndarray


def rx(phi: float) -> Array:
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def ry(theta: float) -> Array:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rz(psi: float) -> Array:
    c, s = np.cos(psi), np.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation(phi: float, theta: float, psi: float) -> Array:
    """R = Rz(psi) Ry(theta) Rx(phi)."""
    return rz(psi) @ ry(theta) @ rx(phi)


def attitude_transform(phi: float, theta: float) -> Array:
    """T(phi, theta): body rates to Euler-angle rates."""
    sf, cf, tt, ct = np.sin(phi), np.cos(phi), np.tan(theta), np.cos(theta)
    return np.array([[1.0, sf * tt, cf * tt], [0.0, cf, -sf], [0.0, sf / ct, cf / ct]])


def attitude_transform_inverse(phi: float, theta: float) -> Array:
    sf, cf, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    return np.array([[1.0, 0.0, -st], [0.0, cf, ct * sf], [0.0, -sf, ct * cf]])


def block_diag(a: Array, b: Array) -> Array:
    out = np.zeros((6, 6))
    out[:3, :3] = a
    out[3:, 3:] = b
    return out


def jacobian(eta: Array) -> Array:
    phi, theta, psi = eta[3:]
    return block_diag(rotation(phi, theta, psi), attitude_transform(phi, theta))


def jacobian_inverse(eta: Array) -> Array:
    phi, theta, psi = eta[3:]
    return block_diag(rotation(phi, theta, psi).T, attitude_transform_inverse(phi, theta))


def skew(a: Array) -> Array:
    """S(a) with S(a) b = a x b."""
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def diag_or_matrix(x: Any, n: int) -> Array:
    x = np.asarray(x, dtype=float)
    return np.diag(x) if x.shape == (n,) else x.reshape(n, n)


def rigid_body_mass(p: dict[str, Any]) -> Array:
    m = float(p["mass"])
    s = skew(np.asarray(p.get("centre_of_gravity", np.zeros(3)), dtype=float))
    out = np.zeros((6, 6))
    out[:3, :3] = m * np.eye(3)
    out[:3, 3:] = -m * s
    out[3:, :3] = m * s
    out[3:, 3:] = diag_or_matrix(p["inertia"], 3)
    return out


def mass_matrix(p: dict[str, Any]) -> Array:
    return rigid_body_mass(p) + diag_or_matrix(p["added_mass"], 6)


def m2c(mat: Array, nu: Array) -> Array:
    """Fossen's C(nu) from a symmetric 6x6 inertia matrix (Kirchhoff form)."""
    a = mat @ nu
    s1, s2 = skew(a[:3]), skew(a[3:])
    out = np.zeros((6, 6))
    out[:3, 3:] = -s1
    out[3:, :3] = -s1
    out[3:, 3:] = -s2
    return out


def coriolis(p: dict[str, Any], nu: Array) -> Array:
    """C_RB + C_A. 'velocity_independent': Fossen (2011) eq. 3.57,
    C_RB = [[m S(w), -m S(w) S(r_g)], [m S(r_g) S(w), -S(I_o w)]];
    'kirchhoff': C_RB = m2c(M_RB). C_A = m2c(M_A) in both."""
    nu = np.asarray(nu, dtype=float)
    form = p.get("coriolis_form", "velocity_independent")
    if form == "kirchhoff":
        c_rb = m2c(rigid_body_mass(p), nu)
    else:
        m = float(p["mass"])
        sw = skew(nu[3:])
        sr = skew(np.asarray(p.get("centre_of_gravity", np.zeros(3)), dtype=float))
        inertia = diag_or_matrix(p["inertia"], 3)
        c_rb = np.zeros((6, 6))
        c_rb[:3, :3] = m * sw
        c_rb[:3, 3:] = -m * sw @ sr
        c_rb[3:, :3] = m * sr @ sw
        c_rb[3:, 3:] = -skew(inertia @ nu[3:])
    return c_rb + m2c(diag_or_matrix(p["added_mass"], 6), nu)


def damping(p: dict[str, Any], nu: Array) -> Array:
    return np.diag(
        np.asarray(p["linear_damping"], float) + np.asarray(p["quadratic_damping"], float) * np.abs(nu)
    )


def restoring(p: dict[str, Any], eta: Array) -> Array:
    """Fossen (2011) eq. 4.6 for weight W at r_g and buoyancy B at r_b."""
    w, b = float(p["weight"]), float(p["buoyancy"])
    xg, yg, zg = np.asarray(p.get("centre_of_gravity", np.zeros(3)), dtype=float)
    xb, yb, zb = np.asarray(p.get("centre_of_buoyancy", np.zeros(3)), dtype=float)
    phi, theta = eta[3], eta[4]
    sf, cf, st, ct = np.sin(phi), np.cos(phi), np.sin(theta), np.cos(theta)
    return np.array(
        [
            (w - b) * st,
            -(w - b) * ct * sf,
            -(w - b) * ct * cf,
            -(yg * w - yb * b) * ct * cf + (zg * w - zb * b) * ct * sf,
            (zg * w - zb * b) * st + (xg * w - xb * b) * ct * cf,
            -(xg * w - xb * b) * ct * sf - (yg * w - yb * b) * st,
        ]
    )


def acceleration(
    p: dict[str, Any], eta: Array, nu: Array, tau: Array, current: Array | None = None
) -> Array:
    """nu_dot from M nu_r_dot + C(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau with
    nu_r = nu - [R^T v_c; 0] and nu_dot = nu_r_dot + [-w x R^T v_c; 0]
    (a constant, irrotational NED current v_c; Fossen 2011, section 10.3)."""
    eta, nu, tau = (np.asarray(x, dtype=float) for x in (eta, nu, tau))
    vc_body = np.zeros(3)
    if current is not None:
        vc_body = rotation(*eta[3:]).T @ np.asarray(current, dtype=float)
    nu_r = nu - np.r_[vc_body, np.zeros(3)]
    rhs = tau - coriolis(p, nu_r) @ nu_r - damping(p, nu_r) @ nu_r - restoring(p, eta)
    nu_dot = np.linalg.solve(mass_matrix(p), rhs)
    nu_dot[:3] -= np.cross(nu[3:], vc_body)
    return nu_dot


def rk4(f: Any, eta: Array, nu: Array, dt: float) -> tuple[Array, Array]:
    """One classical RK4 step of (eta_dot, nu_dot) = f(eta, nu)."""
    k1e, k1n = f(eta, nu)
    k2e, k2n = f(eta + 0.5 * dt * k1e, nu + 0.5 * dt * k1n)
    k3e, k3n = f(eta + 0.5 * dt * k2e, nu + 0.5 * dt * k2n)
    k4e, k4n = f(eta + dt * k3e, nu + dt * k3n)
    return (
        eta + dt / 6.0 * (k1e + 2.0 * k2e + 2.0 * k3e + k4e),
        nu + dt / 6.0 * (k1n + 2.0 * k2n + 2.0 * k3n + k4n),
    )


def random_pose(rng: np.random.Generator, max_pitch: float = 1.3) -> np.ndarray:
    """A pose with |theta| <= max_pitch (away from the Euler singularity)."""
    return np.r_[
        rng.uniform(-10.0, 10.0, 3),
        rng.uniform(-np.pi, np.pi),
        rng.uniform(-max_pitch, max_pitch),
        rng.uniform(-np.pi, np.pi),
    ]


def random_velocity(rng: np.random.Generator, scale: float = 1.0) -> np.ndarray:
    return rng.normal(scale=scale, size=6)


# NEROV as docs/model.md states it (section 5 of the paper), written out here
# independently of the preset file and of the C++.
NEROV: dict[str, Any] = {
    "mass": 185.0,
    "inertia": [25.0, 50.0, 50.0],
    "centre_of_gravity": [0.0, 0.0, 0.0],
    "centre_of_buoyancy": [0.0, 0.0, -0.02],
    "weight": 1800.0,
    "buoyancy": 1800.0,
    "added_mass": [30.0, 80.0, 80.0, 15.0, 30.0, 30.0],
    "linear_damping": [70.0, 100.0, 100.0, 30.0, 50.0, 50.0],
    "quadratic_damping": [100.0, 200.0, 200.0, 50.0, 100.0, 100.0],
    "coriolis_form": "velocity_independent",
}


def general_parameters(form: str = "velocity_independent") -> dict[str, Any]:
    """A vehicle with every coupling switched on: off-centre r_g and r_b,
    full symmetric inertia and added mass, W != B."""
    inertia = np.array([[25.0, -1.5, 0.8], [-1.5, 50.0, 2.0], [0.8, 2.0, 45.0]])
    added = np.diag([30.0, 80.0, 80.0, 15.0, 30.0, 30.0])
    added[0, 4] = added[4, 0] = 3.0
    added[1, 5] = added[5, 1] = -4.0
    added[2, 3] = added[3, 2] = 2.5
    return {
        "mass": 185.0,
        "inertia": inertia,
        "centre_of_gravity": np.array([0.02, -0.01, 0.05]),
        "centre_of_buoyancy": np.array([-0.01, 0.015, -0.03]),
        "weight": 1815.0,
        "buoyancy": 1790.0,
        "added_mass": added,
        "linear_damping": np.array([70.0, 100.0, 100.0, 30.0, 50.0, 50.0]),
        "quadratic_damping": np.array([100.0, 200.0, 200.0, 50.0, 100.0, 100.0]),
        "coriolis_form": form,
    }
