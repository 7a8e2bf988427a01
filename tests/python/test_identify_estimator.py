"""An estimator between the vehicle and its log: a velocity held between a
DVL's updates and moved part of the way to each sample (an EKF's
staircase), modelled in the output error; and a lag estimated from the data."""

from __future__ import annotations

import numpy as np
import pytest
from identify_runs import excitation_run, true_theta

import neurov
from neurov.identification import IdentificationError, make_log
from neurov.identification.estimator_model import refresh_rows, staircase
from neurov.config.vehicle_file import preset_path

GAIN = np.array([0.85, 0.8, 0.9])
RATE_GAIN = np.array([0.95, 0.93, 0.96])


def _staircase_log(every: int = 4, depth_gain: float = 0.0) -> neurov.identification.Log:
    """A noise-free NEROV run whose linear velocity went through an
    estimator that takes a sample every `every` rows with gains GAIN; with
    `depth_gain`, a second sensor moves w by that gain toward the truth
    half-way between (as an EKF's depth updates do, through the position)."""
    r = excitation_run("nerov", 20.0)
    nu = r.nu.copy()
    e = nu[0, :3].copy()
    for k in range(len(nu)):
        if k % every == 0 and k > 0:
            e = e + GAIN * (r.nu[k, :3] - e)
        elif depth_gain and k % every == every // 2:
            e[2] += depth_gain * (r.nu[k, 2] - e[2])
        nu[k, :3] = e
    return make_log("staircase", r.t, r.eta, nu, r.tau_applied + r.disturbance)


def test_a_staircase_velocity_is_modelled_and_the_vehicle_recovered() -> None:
    log = _staircase_log()
    assert staircase(log)
    assert abs(refresh_rows(log).mean() - 0.25) < 0.02
    truth = true_theta("nerov")
    free = "added_mass,linear_damping"
    plain = neurov.identify(log, preset_path("nerov"), free=free, replicates=20, output_error=False)
    fit = neurov.identify(log, preset_path("nerov"), free=free, replicates=20)
    added = slice(4, 7)
    # Read as the vehicle's velocity, the staircase adds inertia ...
    assert np.max(np.abs(plain.theta[added] / truth[added] - 1)) > 0.05
    # ... modelled, the model that made the log is found (noise-free: to the solver's tolerance).
    np.testing.assert_allclose(fit.theta[fit.fitted], truth[fit.fitted], rtol=1e-4)
    note = next(w for w in fit.warnings if "staircase" in w)
    linear, angular = (note.split(f"({axes}) ")[1].split(", (")[0] for axes in ("u, v, w", "p, q, r"))
    np.testing.assert_allclose([float(g) for g in linear.split(", ")], GAIN, atol=1e-3)
    # The rates are the vehicle's own here (no filter on them): their update gain is 1.
    np.testing.assert_allclose([float(g) for g in angular.split(", ")], 1.0, atol=1e-3)


def test_another_sensor_s_moves_between_the_updates_are_no_updates() -> None:
    """Moves between the DVL's updates (an EKF's depth updates, a few % of
    an update's step) are neither held nor taken for updates: the model
    takes them from the log, and the vehicle is recovered as without them."""
    log = _staircase_log(depth_gain=0.1)
    fresh = refresh_rows(log)
    rows = np.arange(len(log.t))
    moved = np.linalg.norm(np.diff(log.nu[:, :3], axis=0), axis=1)
    between = rows[1:][(rows[1:] % 4 == 2) & (moved > 0)]
    assert len(between) > 0.2 * len(log.t) and not fresh[between].any()
    assert fresh[rows % 4 == 0].mean() > 0.95
    truth = true_theta("nerov")
    fit = neurov.identify(log, preset_path("nerov"), free="added_mass,linear_damping", replicates=20)
    np.testing.assert_allclose(fit.theta[fit.fitted], truth[fit.fitted], rtol=1e-4)


def test_a_filter_on_the_rates_is_modelled_too() -> None:
    """An EKF's body rates: moved at every row by a gain just below 1 (a lag
    of (1 - K) / K periods), which read as extra rotational inertia."""
    log = _staircase_log()
    rates = log.nu.copy()
    e = rates[0, 3:].copy()
    for k in range(1, len(rates)):
        e = e + RATE_GAIN * (log.nu[k, 3:] - e)
        rates[k, 3:] = e
    filtered = make_log("filtered rates", log.t, log.eta, rates, log.tau)
    truth = true_theta("nerov")
    fit = neurov.identify(filtered, preset_path("nerov"), free="added_mass,linear_damping", replicates=20)
    np.testing.assert_allclose(fit.theta[fit.fitted], truth[fit.fitted], rtol=1e-4)
    note = next(w for w in fit.warnings if "staircase" in w)
    angular = note.split("(p, q, r) ")[1]
    np.testing.assert_allclose([float(g) for g in angular.split(", ")], RATE_GAIN, atol=1e-3)
    # With the staircase alone modelled the rates' lag reads as rotational added mass.
    linear = neurov.identify(filtered, preset_path("nerov"), free="added_mass,linear_damping", replicates=20,
                             estimator="linear")
    assert np.min(linear.theta[7:10] / truth[7:10] - 1) > 0.002


def test_a_log_sampled_at_every_row_is_no_staircase() -> None:
    r = excitation_run("nerov", 20.0, noise=0.01)
    log = make_log("run", r.t, r.eta_estimate, r.nu_estimate, r.tau_applied + r.disturbance)
    assert not staircase(log)
    # ... so no estimator is modelled and none reported.
    fit = neurov.identify(log, preset_path("nerov"), free="added_mass,linear_damping", replicates=20)
    assert not any("staircase" in w for w in fit.warnings)


def test_a_lag_is_estimated_from_the_data() -> None:
    r = excitation_run("nerov", 20.0)
    nu = r.nu.copy()
    nu[2:, :3] = nu[:-2, :3]  # the linear velocities two rows (0.1 s) late
    late = make_log("late", r.t, r.eta, nu, r.tau_applied + r.disturbance)
    fit = neurov.identify(late, preset_path("nerov"), free="added_mass,linear_damping", replicates=20,
                          velocity_lag="auto")
    assert any(w.startswith("velocity lag estimated from the data: 0.1 s") for w in fit.warnings)
    truth = true_theta("nerov")
    np.testing.assert_allclose(fit.theta[4:7], truth[4:7], rtol=1e-3)
    with pytest.raises(IdentificationError, match="velocity_lag='auto' .* needs the output-error stage"):
        neurov.identify(late, preset_path("nerov"), velocity_lag="auto", output_error=False)
    with pytest.raises(IdentificationError, match="velocity_lag: expected seconds >= 0 or 'auto', got 'soon'"):
        neurov.identify(late, preset_path("nerov"), velocity_lag="soon")
