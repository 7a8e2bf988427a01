"""The same equations as neurov's C++ core, written the way a user would write
them without neurov: plain numpy, vectorised over the RBF centres (no Python
loop over neurons), ``math`` for the scalar trigonometry.

It is the baseline of ``bench/compare.py`` and is checked there against
neurov on the same inputs (the closed loops agree to round-off), so the two
sides do the same work. Equations: docs/model.md (eq. 2, 12-16, 30, 35, 37, 39);
the NEROV model with its diagonal M, the velocity-independent C(nu) of
eq. 39, D(nu) and g(eta).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# ------------------------------------------------------------------ kinematics


def kinematics(eta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """R, T and T^-1 of a pose (ZYX Euler angles)."""
    sf, cf = math.sin(eta[3]), math.cos(eta[3])
    st, ct = math.sin(eta[4]), math.cos(eta[4])
    sp, cp = math.sin(eta[5]), math.cos(eta[5])
    r = np.array([
        [cp * ct, -sp * cf + cp * st * sf, sp * sf + cp * cf * st],
        [sp * ct, cp * cf + sf * st * sp, -cp * sf + st * sp * cf],
        [-st, ct * sf, ct * cf],
    ])
    tt = st / ct
    t = np.array([[1.0, sf * tt, cf * tt], [0.0, cf, -sf], [0.0, sf / ct, cf / ct]])
    t_inv = np.array([[1.0, 0.0, -st], [0.0, cf, ct * sf], [0.0, -sf, ct * cf]])
    return r, t, t_inv


def j_apply(r: np.ndarray, t: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.concatenate((r @ v[:3], t @ v[3:]))


def j_inv_apply(r: np.ndarray, t_inv: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.concatenate((r.T @ v[:3], t_inv @ v[3:]))


def j_transpose_apply(r: np.ndarray, t: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.concatenate((r.T @ v[:3], t.T @ v[3:]))


def j_dot_apply(eta: np.ndarray, r: np.ndarray, t: np.ndarray, nu: np.ndarray, v: np.ndarray) -> np.ndarray:
    """J_dot(eta, nu) v: R_dot = R S(omega), T_dot from dT/dphi, dT/dtheta."""
    omega = nu[3:]
    phi_dot, theta_dot, _ = t @ omega
    sf, cf = math.sin(eta[3]), math.cos(eta[3])
    st, ct = math.sin(eta[4]), math.cos(eta[4])
    tt = st / ct
    sec2 = 1.0 / (ct * ct)
    t_dot = np.array([
        [0.0, cf * tt * phi_dot + sf * sec2 * theta_dot, -sf * tt * phi_dot + cf * sec2 * theta_dot],
        [0.0, -sf * phi_dot, -cf * phi_dot],
        [0.0, (cf * phi_dot + sf * tt * theta_dot) / ct, (-sf * phi_dot + cf * tt * theta_dot) / ct],
    ])
    return np.concatenate((r @ np.cross(omega, v[:3]), t_dot @ v[3:]))


# --------------------------------------------------------------------- vehicle


@dataclass
class Nerov:
    """NEROV (docs/model.md; the paper's section 5)."""

    m: float = 185.0
    inertia: tuple[float, float, float] = (25.0, 50.0, 50.0)
    added: tuple[float, ...] = (30.0, 80.0, 80.0, 15.0, 30.0, 30.0)
    d_lin: tuple[float, ...] = (70.0, 100.0, 100.0, 30.0, 50.0, 50.0)
    d_quad: tuple[float, ...] = (100.0, 200.0, 200.0, 50.0, 100.0, 100.0)
    zb_b: float = 0.02 * 1800.0  # metacentric moment z_g W - z_b B

    def __post_init__(self) -> None:
        m, (ix, iy, iz), a = self.m, self.inertia, self.added
        self.m_inv = np.diag(1.0 / np.array([m + a[0], m + a[1], m + a[2], ix + a[3], iy + a[4], iz + a[5]]))
        self.dl = np.array(self.d_lin)
        self.dq = np.array(self.d_quad)

    def coriolis(self, nu: np.ndarray) -> np.ndarray:
        """C(nu) of eq. 39."""
        u, v, w, p, q, r = nu
        m, (ix, iy, iz) = self.m, self.inertia
        xa, ya, za, ka, ma, na = self.added  # positive: -X_udot, ...
        return np.array([
            [0.0, -m * r, m * q, 0.0, za * w, -ya * v],
            [m * r, 0.0, -m * p, -za * w, 0.0, xa * u],
            [-m * q, m * p, 0.0, ya * v, -xa * u, 0.0],
            [0.0, za * w, -ya * v, 0.0, (iz + na) * r, -(iy + ma) * q],
            [-za * w, 0.0, xa * u, -(iz + na) * r, 0.0, (ix + ka) * p],
            [ya * v, -xa * u, 0.0, (iy + ma) * q, -(ix + ka) * p, 0.0],
        ])

    def derivative(self, eta: np.ndarray, nu: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(eta_dot, nu_dot) of eq. 1-2."""
        r, t, _ = kinematics(eta)
        sf, cf = math.sin(eta[3]), math.cos(eta[3])
        st, ct = math.sin(eta[4]), math.cos(eta[4])
        g = np.array([0.0, 0.0, 0.0, self.zb_b * ct * sf, self.zb_b * st, 0.0])
        d = self.dl + self.dq * np.abs(nu)
        nu_dot = self.m_inv @ (tau - self.coriolis(nu) @ nu - d * nu - g)
        return j_apply(r, t, nu), nu_dot


def rk4_step(vehicle: Nerov, eta: np.ndarray, nu: np.ndarray, tau: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    k1e, k1n = vehicle.derivative(eta, nu, tau)
    k2e, k2n = vehicle.derivative(eta + 0.5 * h * k1e, nu + 0.5 * h * k1n, tau)
    k3e, k3n = vehicle.derivative(eta + 0.5 * h * k2e, nu + 0.5 * h * k2n, tau)
    k4e, k4n = vehicle.derivative(eta + h * k3e, nu + h * k3n, tau)
    return (eta + h / 6.0 * (k1e + 2.0 * (k2e + k3e) + k4e),
            nu + h / 6.0 * (k1n + 2.0 * (k2n + k3n) + k4n))


# ------------------------------------------------------------- reference model


class ReferenceModel:
    """eq. 12-13, RK4 at the control rate with r held."""

    def __init__(self, lambda_d: np.ndarray, omega: np.ndarray, eta0: np.ndarray) -> None:
        self.lambda_d, self.omega = lambda_d, omega
        self.eta_d, self.nu_d = eta0.copy(), np.zeros(6)
        self.desired = self._desired(self.eta_d, self.nu_d, np.zeros(6))

    def _derivative(self, eta_d: np.ndarray, nu_d: np.ndarray, r_cmd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        r, t, _ = kinematics(eta_d)
        return j_apply(r, t, nu_d), -self.lambda_d * nu_d + j_transpose_apply(r, t, self.omega * (r_cmd - eta_d))

    def _desired(self, eta_d: np.ndarray, nu_d: np.ndarray, nu_d_dot: np.ndarray) -> tuple[np.ndarray, ...]:
        r, t, _ = kinematics(eta_d)
        return (eta_d.copy(), j_apply(r, t, nu_d), j_apply(r, t, nu_d_dot) + j_dot_apply(eta_d, r, t, nu_d, nu_d))

    def step(self, r_cmd: np.ndarray, dt: float) -> tuple[np.ndarray, ...]:
        e, n = self.eta_d, self.nu_d
        k1e, k1n = self._derivative(e, n, r_cmd)
        k2e, k2n = self._derivative(e + 0.5 * dt * k1e, n + 0.5 * dt * k1n, r_cmd)
        k3e, k3n = self._derivative(e + 0.5 * dt * k2e, n + 0.5 * dt * k2n, r_cmd)
        k4e, k4n = self._derivative(e + dt * k3e, n + dt * k3n, r_cmd)
        self.eta_d = e + dt / 6.0 * (k1e + 2.0 * (k2e + k3e) + k4e)
        self.nu_d = n + dt / 6.0 * (k1n + 2.0 * (k2n + k3n) + k4n)
        _, nu_dot = self._derivative(self.eta_d, self.nu_d, r_cmd)
        self.desired = self._desired(self.eta_d, self.nu_d, nu_dot)
        return self.desired


# --------------------------------------------------------------- NN controller


class NNController:
    """eq. 30, 35, 37: tau = W g(x) - J^T K_d s, W <- W - dt (J^-1 s) (gamma g)^T."""

    def __init__(self, centres: np.ndarray, width: float, lambda_: np.ndarray, kd: np.ndarray,
                 gamma: float, dt: float) -> None:
        self.centres = np.asarray(centres, dtype=np.float64)  # (N, 24)
        self.inv = 1.0 / (2.0 * width * width)
        self.lambda_, self.kd, self.gamma, self.dt = lambda_, kd, gamma, dt
        self.w = np.zeros((6, len(self.centres)))

    def step(self, eta: np.ndarray, nu: np.ndarray, eta_d: np.ndarray, eta_d_dot: np.ndarray,
             eta_d_ddot: np.ndarray) -> np.ndarray:
        r, t, t_inv = kinematics(eta)
        lam = self.lambda_
        eta_tilde = eta - eta_d
        eta_tilde_dot = j_apply(r, t, nu) - eta_d_dot
        s = eta_tilde_dot + lam * eta_tilde
        nu_r = j_inv_apply(r, t_inv, eta_d_dot - lam * eta_tilde)
        nu_r_dot = j_inv_apply(r, t_inv, eta_d_ddot - lam * eta_tilde_dot - j_dot_apply(eta, r, t, nu, nu_r))
        x = np.concatenate((nu_r_dot, nu_r, nu, eta))
        g = np.exp(-np.sum((self.centres - x) ** 2, axis=1) * self.inv)
        tau = self.w @ g - j_transpose_apply(r, t, self.kd * s)
        a = self.dt * j_inv_apply(r, t_inv, s)
        self.w -= np.outer(a, self.gamma * g)
        self.s = s
        return tau


# ----------------------------------------------------------------- closed loop


def simulate(vehicle: Nerov, controller: NNController, *, dt: float, substeps: int, duration: float,
             eta0: np.ndarray, command_times: np.ndarray, command_poses: np.ndarray,
             lambda_d: np.ndarray, omega: np.ndarray) -> dict[str, np.ndarray]:
    """neurov.simulate's loop (simulation.hpp): control at dt with tau held,
    RK4 plant at dt / substeps, reference model at dt with the command of t_k."""
    rows = int(round(duration / dt)) + 1
    out = {k: np.zeros((rows, 6)) for k in ("eta", "nu", "eta_d", "tau")}
    eta, nu = eta0.astype(np.float64).copy(), np.zeros(6)
    reference = ReferenceModel(lambda_d, omega, eta0)
    desired = reference.desired
    h = dt / substeps
    for k in range(rows):
        t = k * dt
        tau = controller.step(eta, nu, *desired)
        out["eta"][k], out["nu"][k], out["eta_d"][k], out["tau"][k] = eta, nu, desired[0], tau
        for _ in range(substeps):
            eta, nu = rk4_step(vehicle, eta, nu, tau, h)
        command = np.array([np.interp(t, command_times, command_poses[:, i]) for i in range(6)])
        desired = reference.step(command, dt)
    return out
