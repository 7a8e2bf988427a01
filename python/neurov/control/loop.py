"""A scenario's closed loop in python-control: the reference model, the
controller and the sampled plant of :mod:`neurov.control.sampled` made from
the scenario and joined by ``control.interconnect``, and the time grid, the
command and the initial state that ``control.input_output_response`` needs
to run the loop :func:`neurov.simulate` runs."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from neurov import _core
from neurov.control import INPUT_NAMES, STATE_NAMES
from neurov.control.sampled import (COMMAND_NAMES, DESIRED_NAMES, controller_system, reference_system,
                                    sampled_plant)
from neurov.errors import ScenarioError
from neurov.config.scenario import ControllerSpec, Scenario
from neurov.laws.registry import build_controller
from neurov.running.plant import build_vehicle, simulation_config

import control as ct

__all__ = ["closed_loop", "command_input", "initial_state", "scenario_systems", "simulate", "time_grid",
           "unsupported_features"]

Array = NDArray[np.float64]


def unsupported_features(scenario: Scenario) -> list[str]:
    """What of the scenario the python-control loop does not model, each
    with the scenario field that sets it; empty when the loop is neurov's.

    The loop is the controller, the reference model and the rigid-body plant
    with a constant current, the force acting directly and held over each
    period, the true state measured. Thrusters, disturbances, noise,
    sensors and their estimator, sensor faults, a control delay, waves,
    payload events and a time-varying current are neurov.simulate's alone.
    """
    sim = scenario.simulation
    found = []
    if sim.use_thrusters:
        found.append("thrusters (use_thrusters: allocation, saturation and lag)")
    if len(sim.disturbances):
        found.append("disturbances")
    if np.any(np.asarray(sim.noise_eta)) or np.any(np.asarray(sim.noise_nu)):
        found.append("measurement noise (noise_eta, noise_nu)")
    if sim.sensors.any():
        found.append("sensors (and the estimator they feed)")
    if len(sim.sensor_faults):
        found.append("sensor faults (sensor_faults)")
    if sim.control_delay:
        found.append("a control delay (control_delay)")
    if sim.waves is not None:
        found.append("waves")
    if len(sim.payload):
        found.append("payload events (payload)")
    if sim.current_model != _core.CurrentModel.constant:
        found.append("a Gauss-Markov current (current_model)")
    if len(sim.current_steps):
        found.append("current steps (current_steps)")
    if sim.current_period > 0 and np.any(np.asarray(sim.current_amplitude)):
        found.append("a sinusoidal current (current_amplitude, current_period)")
    return found


def _require_scenario(scenario: Any) -> Scenario:
    if not isinstance(scenario, Scenario):
        raise TypeError(f"argument 'scenario' must be a neurov.Scenario, got {type(scenario).__name__}")
    found = unsupported_features(scenario)
    if found:
        raise ScenarioError(f"argument 'scenario' ({scenario.name!r}) has what the python-control loop does not "
                         f"model: {'; '.join(found)}. Run it with neurov.simulate, or remove these "
                         "(e.g. scenario.replace(use_thrusters=False, disturbances=[]))")
    simulation_config(scenario)  # the C++ validator names a bad field
    return scenario


def scenario_systems(scenario: Scenario, controller: ControllerSpec | Any = None, *,
                     vehicle: _core.Vehicle | None = None) -> tuple[ct.NonlinearIOSystem, ...]:
    """The reference model, the controller and the sampled plant of the
    scenario's loop, as :func:`neurov.simulate` builds them: `controller` a
    :class:`ControllerSpec` (None: the scenario's) or a built-in controller
    object (copied, in the state it is in); `vehicle` the plant (default:
    the scenario's vehicle with its parameter overrides). A
    :class:`neurov.errors.ScenarioError` (a ValueError) names what of the
    scenario the loop does not model (:func:`unsupported_features`)."""
    _require_scenario(scenario)
    sim = scenario.simulation
    if controller is None or isinstance(controller, ControllerSpec):
        ctrl = build_controller(controller or scenario.controller, scenario)
    else:
        ctrl = controller
    plant_vehicle = vehicle if vehicle is not None else build_vehicle(scenario)
    eta0 = np.asarray(sim.eta0, dtype=np.float64)
    reference = _core.ReferenceModel(sim.lambda_d, sim.omega, eta0)
    return (reference_system(reference, sim.dt),
            controller_system(ctrl, sim.dt),
            sampled_plant(plant_vehicle, sim.dt, sim.substeps, sim.current,
                          x0=np.concatenate([eta0, np.asarray(sim.nu0, dtype=np.float64)])))


def closed_loop(scenario: Scenario, controller: ControllerSpec | Any = None, *,
                vehicle: _core.Vehicle | None = None, name: str | None = None) -> ct.InterconnectedSystem:
    """The scenario's closed loop as one discrete-time system: the
    :func:`scenario_systems` joined by their signal names. Input: the
    commanded pose (:data:`neurov.control.sampled.COMMAND_NAMES`, see
    :func:`command_input`); outputs: eta and nu, tau, and eta_d and
    eta_d_dot; ``x0``: the loop's initial state."""
    systems = scenario_systems(scenario, controller, vehicle=vehicle)
    loop = ct.interconnect(list(systems), inputs=list(COMMAND_NAMES),
                           outputs=list(STATE_NAMES + INPUT_NAMES + DESIRED_NAMES[:12]),
                           name=name or f"{scenario.name} closed loop")
    loop.x0 = initial_state(loop)
    return loop


def time_grid(scenario: Scenario) -> Array:
    """The rows' times of the scenario's run, t_k = k dt for k = 0 ...
    round(duration / dt), computed as neurov's loop computes them."""
    _require_scenario(scenario)
    # The C++ counts the rows (round half away from zero, as Python's round does not).
    rows = _core.Simulator(build_vehicle(scenario), scenario.simulation).planned_steps
    t: Array = np.arange(rows, dtype=np.float64) * scenario.simulation.dt  # float(k) * dt, as in C++
    return t


def command_input(scenario: Scenario, t: ArrayLike) -> Array:
    """The commanded pose at each time of `t`, shape (6, len(t)): the
    input ``U`` of the loop (the scenario's command, as the C++ loop
    evaluates it)."""
    times = np.asarray(t, dtype=np.float64)
    if times.ndim != 1 or not np.all(np.isfinite(times)):
        raise ValueError(f"argument 't' must be a 1-D array of finite times, got shape {times.shape}")
    command = scenario.simulation.command
    poses: Array = np.array([command.at(float(tk)) for tk in times], dtype=np.float64).reshape(len(times), 6)
    return poses.T


def initial_state(system: ct.InputOutputSystem) -> Array:
    """The initial state of a system of neurov.control or of an
    interconnection of them (each subsystem's ``x0``, in the
    interconnection's state order): ``X0`` for input_output_response."""
    parts = getattr(system, "syslist", None) or [system]
    missing = [s.name for s in parts if not hasattr(s, "x0")]
    if missing:
        raise ValueError(f"argument 'system': the subsystems {missing} are not neurov.control's and "
                         "have no initial state x0; give input_output_response their X0 yourself")
    return np.concatenate([np.asarray(s.x0, dtype=np.float64) for s in parts])


def simulate(scenario: Scenario, controller: ControllerSpec | Any = None, *,
             vehicle: _core.Vehicle | None = None) -> ct.TimeResponseData:
    """The scenario's loop run by ``control.input_output_response`` on the
    run's time grid: the same rows as :func:`neurov.simulate` (eta, nu,
    tau, eta_d, eta_d_dot at t_k) for a scenario the loop models."""
    loop = closed_loop(scenario, controller, vehicle=vehicle)
    t = time_grid(scenario)
    return ct.input_output_response(loop, t, command_input(scenario, t), X0=loop.x0)
