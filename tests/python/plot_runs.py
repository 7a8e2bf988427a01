"""The runs the plotting tests draw: the NN controller and a PD baseline on a
3 m square with thrusters."""

from __future__ import annotations

import numpy as np

from neurov.config.scenario import CommandSpec, ControllerSpec, Scenario
from neurov.results.timeseries import Result
from neurov.running.simulation import simulate

PD = ControllerSpec(type="pd", kp=np.full(6, 200.0), kd=np.full(6, 300.0))


def square(name: str, duration: float) -> Scenario:
    """A 3 m square from t = 1 s under the NN controller (16 Sobol centres)."""
    return Scenario(
        name=name, duration=duration, use_thrusters=True,
        command=CommandSpec(type="square", args={"side": 3.0, "start": 1.0}),
        controller=ControllerSpec(type="nn", centres={"method": "sobol", "n": 16, "seed": 0}),
    )


def nn_and_pd(scenario: Scenario) -> list[Result]:
    """The scenario's own NN run and the PD run on it."""
    return [simulate(scenario), simulate(scenario, PD)]


def assert_demanded_and_applied(ax, result, dofs) -> int:  # type: ignore[no-untyped-def]
    """`ax` draws each DOF's applied tau, and its demanded tau only where the
    two differ (one line where they agree); one legend entry per line.
    Returns how many DOFs were drawn with both."""
    import numpy as np

    from neurov.plotting.runs import FORCE_NAMES

    both = 0
    for i in dofs:
        mine = [line for line in ax.lines if line.get_label().startswith(FORCE_NAMES[i] + " ")]
        labels = [line.get_label() for line in mine]
        if labels == [f"{FORCE_NAMES[i]} applied = demanded"]:
            np.testing.assert_array_equal(mine[0].get_ydata(), result.tau_applied[:, i])
            np.testing.assert_allclose(result.tau_demanded[:, i], result.tau_applied[:, i], rtol=0,
                                       atol=1e-6 * max(1.0, float(np.max(np.abs(result.tau_demanded[:, i])))))
        else:
            assert labels == [f"{FORCE_NAMES[i]} applied", f"{FORCE_NAMES[i]} demanded"], labels
            np.testing.assert_array_equal(mine[0].get_ydata(), result.tau_applied[:, i])
            np.testing.assert_array_equal(mine[1].get_ydata(), result.tau_demanded[:, i])
            both += 1
    legend = ax.get_legend()
    assert [t.get_text() for t in legend.get_texts()] == [line.get_label() for line in ax.lines
                                                        if not line.get_label().startswith("_")]
    return both
