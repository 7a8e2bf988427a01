"""The controllers' laws written again in numpy from docs/model.md, for the
controller tests: J_dot and the tracking error (eq. 11, 14-16), the RBF basis
(eq. 30), the NN control law (eq. 35) and weight step (eq. 37), random NN
cases, and the model of NEROV (eq. 39). Nothing here calls the code under
test's kinematics or tracking error (neurov.tracking_error is not used)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

import neurov
import reference_model as ref

Array = np.ndarray


def jac_dot(eta: Array, nu: Array) -> Array:
    """blockdiag(R S(omega), dT/dphi phi_dot + dT/dtheta theta_dot)."""
    phi, theta = eta[3], eta[4]
    w = nu[3:]
    phi_dot, theta_dot, _ = ref.attitude_transform(phi, theta) @ w
    cf, sf, ct, st, tt = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.tan(theta)
    d_phi = np.array([[0, cf * tt, -sf * tt], [0, -sf, -cf], [0, cf / ct, -sf / ct]])
    d_theta = np.array([[0, sf / ct**2, cf / ct**2], [0, 0, 0], [0, sf * st / ct**2, cf * st / ct**2]])
    s_w = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return ref.block_diag(ref.rotation(*eta[3:]) @ s_w, d_phi * phi_dot + d_theta * theta_dot)


@dataclass
class Tracking:
    s: Array
    nu_r: Array
    nu_r_dot: Array
    j: Array
    j_inv: Array


def tracking(eta: Array, nu: Array, eta_d: Array, eta_d_dot: Array, eta_d_ddot: Array, lam: Array) -> Tracking:
    j, j_inv = ref.jacobian(eta), ref.jacobian_inverse(eta)
    e = eta - eta_d
    e_dot = j @ nu - eta_d_dot
    eta_r_dot = eta_d_dot - lam * e
    eta_r_ddot = eta_d_ddot - lam * e_dot
    nu_r = j_inv @ eta_r_dot
    nu_r_dot = j_inv @ (eta_r_ddot - jac_dot(eta, nu) @ nu_r)
    return Tracking(e_dot + lam * e, nu_r, nu_r_dot, j, j_inv)


@dataclass
class Case:
    eta: Array
    nu: Array
    eta_d: Array
    eta_d_dot: Array
    eta_d_ddot: Array
    lam: Array
    kd: Array
    centres: Array
    widths: Array
    weights: Array
    gamma: float
    dt: float

    def args(self) -> tuple[Array, ...]:
        return (self.eta, self.nu, self.eta_d, self.eta_d_dot, self.eta_d_ddot)


def random_state(rng: np.random.Generator) -> dict[str, Array]:
    eta = np.r_[rng.uniform(-3, 3, 3), rng.uniform(-np.pi, np.pi), rng.uniform(-1.2, 1.2), rng.uniform(-np.pi, np.pi)]
    return {
        "eta": eta,
        "nu": rng.uniform(-1, 1, 6),
        "eta_d": eta + rng.uniform(-0.5, 0.5, 6),
        "eta_d_dot": rng.uniform(-1, 1, 6),
        "eta_d_ddot": rng.uniform(-1, 1, 6),
    }


def network_input(e: Tracking, nu: Array, eta: Array) -> Array:
    return np.r_[e.nu_r_dot, e.nu_r, nu, eta]


def random_case(rng: np.random.Generator, n_centres: int = 12) -> Case:
    st = random_state(rng)
    lam, kd = rng.uniform(0.5, 2.0, 6), rng.uniform(0, 50, 6)
    e = tracking(st["eta"], st["nu"], st["eta_d"], st["eta_d_dot"], st["eta_d_ddot"], lam)
    x = network_input(e, st["nu"], st["eta"])
    # Most centres within a few widths of x (g well inside (0, 1)), a few far away.
    centres = x + rng.uniform(-1.5, 1.5, (n_centres, 24))
    centres[-3:] = rng.uniform(-10, 10, (3, 24))
    return Case(
        **st,
        lam=lam,
        kd=kd,
        centres=centres,
        widths=rng.uniform(2, 6, n_centres),
        weights=rng.uniform(-5, 5, (6, n_centres)),
        gamma=float(rng.uniform(0.5, 2.0)),
        dt=float(rng.uniform(0.05, 0.2)),
    )


@dataclass
class Expected:
    tau: Array
    f_hat: Array
    g: Array
    weights: Array
    s: Array
    nu_r: Array
    nu_r_dot: Array
    adapted: bool


def nn_reference(
    c: Case,
    w: Array,
    rates: Array | None = None,
    modification: str = "none",
    sigma_m: float = 0.0,
    kappa: float = 0.0,
    w_max: float = 0.0,
    dead_zone: float = 0.0,
) -> Expected:
    """tau = W g(x) - J^T K_d s with W from before the step, then
    W <- W (1 - dt leak gamma_j) - dt gamma_j (J^-1 s) g_j, then projection."""
    rates = np.full(len(c.widths), c.gamma) if rates is None else rates
    e = tracking(c.eta, c.nu, c.eta_d, c.eta_d_dot, c.eta_d_ddot, c.lam)
    x = network_input(e, c.nu, c.eta)
    g = np.exp(-np.sum((x - c.centres) ** 2, axis=1) / (2 * c.widths**2))
    f_hat = w @ g
    tau = f_hat - e.j.T @ (c.kd * e.s)
    a = e.j_inv @ e.s
    adapted = not (dead_zone > 0 and np.linalg.norm(e.s) < dead_zone)
    w_new = w.copy()
    if adapted:
        leak = {"sigma": sigma_m, "e_modification": kappa * np.linalg.norm(a)}.get(modification, 0.0)
        w_new = w * (1 - c.dt * leak * rates) - c.dt * np.outer(a, rates * g)
        if modification == "projection" and np.linalg.norm(w_new) > w_max:
            w_new *= w_max / np.linalg.norm(w_new)
    return Expected(tau, f_hat, g, w_new, e.s, e.nu_r, e.nu_r_dot, adapted)


def make_nn(c: Case, **kwargs: Any) -> neurov.NNAdaptiveController:
    net = neurov.RbfNetwork(c.centres, c.widths)
    net.weights = c.weights
    return neurov.NNAdaptiveController(net, c.lam, c.kd, c.gamma, c.dt, **kwargs)


def assert_step_matches(ctl: neurov.NNAdaptiveController, tau: Array, ex: Expected, w_before: Array) -> None:
    scale = 1 + np.abs(ex.tau).max() + np.abs(w_before).max()
    np.testing.assert_allclose(tau, ex.tau, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(ctl.network_output, ex.f_hat, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(ctl.basis, ex.g, rtol=0, atol=1e-13)
    np.testing.assert_allclose(ctl.weights, ex.weights, rtol=0, atol=1e-12 * (1 + np.abs(ex.weights).max()))
    np.testing.assert_allclose(ctl.weight_norm, np.linalg.norm(ex.weights), rtol=1e-12)
    np.testing.assert_allclose(ctl.s, ex.s, rtol=0, atol=1e-12 * (1 + np.abs(ex.s).max()))
    t = ctl.tracking
    np.testing.assert_allclose(t["nu_r"], ex.nu_r, rtol=0, atol=1e-12 * (1 + np.abs(ex.nu_r).max()))
    np.testing.assert_allclose(t["nu_r_dot"], ex.nu_r_dot, rtol=0, atol=1e-11 * (1 + np.abs(ex.nu_r_dot).max()))
    assert ctl.adapted == ex.adapted


M_NEROV, IX, IY, IZ = 185.0, 25.0, 50.0, 50.0
XU, YV, ZW, KP, MQ, NR = -30.0, -80.0, -80.0, -15.0, -30.0, -30.0


def nerov_c(nu: Array) -> Array:
    """C(nu) of NEROV, eq. 39 as docs/model.md prints it."""
    u, v, w, p, q, r = nu
    m = M_NEROV
    return np.array(
        [
            [0, -m * r, m * q, 0, -ZW * w, YV * v],
            [m * r, 0, -m * p, ZW * w, 0, -XU * u],
            [-m * q, m * p, 0, -YV * v, XU * u, 0],
            [0, -ZW * w, YV * v, 0, (IZ - NR) * r, -(IY - MQ) * q],
            [ZW * w, 0, -XU * u, -(IZ - NR) * r, 0, (IX - KP) * p],
            [-YV * v, XU * u, 0, (IY - MQ) * q, -(IX - KP) * p, 0],
        ]
    )


def nerov_f(nu_r_dot: Array, nu_r: Array, nu: Array, eta: Array) -> Array:
    """M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) for NEROV (docs/model.md; the paper's section 5)."""
    m = M_NEROV
    mass = np.diag([m - XU, m - YV, m - ZW, IX - KP, IY - MQ, IZ - NR])
    d = np.diag(np.array([70, 100, 100, 30, 50, 50]) + np.array([100, 200, 200, 50, 100, 100]) * np.abs(nu))
    b = 1800.0
    g = np.array([0, 0, 0, 0.02 * b * np.cos(eta[4]) * np.sin(eta[3]), 0.02 * b * np.sin(eta[4]), 0])
    return mass @ nu_r_dot + nerov_c(nu) @ nu_r + d @ nu_r + g
