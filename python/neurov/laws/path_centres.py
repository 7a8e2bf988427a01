"""Centres along the commanded path: the network's inputs that a run which
tracked its desired trajectory exactly would see.

The NN controller's input is x = [nu_r_dot; nu_r; nu; eta]
(:data:`neurov.centres.INPUT_NAMES`). With no tracking error, eta = eta_d,
nu = nu_r = nu_d (the reference model's body velocity) and nu_r_dot =
nu_d_dot, so the path's inputs are x_d(t) = [nu_d_dot; nu_d; nu_d; eta_d](t),
from the scenario's reference model driven by its command, stepped as the
loop steps it. A box-filling placement (Sobol, Latin hypercube) spreads its
centres over a 24-dimensional box the run never fills; these lie where the
run goes.

The rule: the run's duration T is cut into n equal intervals and one time is
drawn uniformly in each (seeded), t_i = (i + u_i) T / n; centre i is x_d at
the control step nearest t_i. The same scenario, n and seed give the same
centres."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from neurov import _core
from neurov.laws.centres import check_count

__all__ = ["along_path", "path_inputs"]

Array = NDArray[np.float64]


def path_inputs(scenario: Any) -> tuple[Array, Array]:
    """The times t_k = k dt of the scenario's run and the inputs x_d(t_k)
    along its desired trajectory, shape (steps + 1, 24). nu_d_dot is the
    central difference of nu_d (one-sided at the ends)."""
    sim = scenario.simulation
    dt = float(sim.dt)
    steps = int(round(float(sim.duration) / dt))
    eta0 = np.asarray(sim.eta0, dtype=np.float64)
    reference = _core.ReferenceModel(sim.lambda_d, sim.omega, eta0)
    eta_d = np.empty((steps + 1, 6))
    nu_d = np.empty((steps + 1, 6))
    eta_d[0], nu_d[0] = eta0, 0.0  # at rest at its initial pose, as the loop starts
    command = sim.command
    for k in range(steps):
        # The command at t_k, held over the period, gives the desired state at t_{k+1}.
        eta_d[k + 1] = reference.step(command.at(k * dt), dt)[0]
        nu_d[k + 1] = reference.nu_d
    nu_d_dot = np.gradient(nu_d, dt, axis=0) if steps >= 1 else np.zeros_like(nu_d)
    times = np.arange(steps + 1, dtype=np.float64) * dt
    return times, np.hstack([nu_d_dot, nu_d, nu_d, eta_d])


def along_path(scenario: Any, n: int, seed: int = 0) -> Array:
    """``n`` centres (n, 24) on the scenario's desired trajectory, one in each
    of n equal intervals of its duration, at a seeded time within it (the
    rule of this module's docstring)."""
    if int(n) != n or n < 1:
        raise ValueError(f"argument 'n' must be a positive integer, got {n!r}")
    check_count(int(n))
    times, inputs = path_inputs(scenario)
    duration = times[-1]
    u = np.random.default_rng(seed).random(int(n))
    t = (np.arange(int(n)) + u) * duration / int(n)
    dt = float(scenario.simulation.dt)
    rows = np.clip(np.rint(t / dt).astype(np.int64), 0, len(times) - 1)
    return np.ascontiguousarray(inputs[rows])
