"""Stub-only piece of :mod:`neurov._core` for type checkers (nothing imports it
at runtime): the layer ``sim``, the configuration of a run, the closed loop
and the simulator stepped from Python (``python/bindings/sim``)."""

# The pieces share their private helpers (arrays, descriptors, bases).
# pyright: reportPrivateUsage=false

from collections.abc import Callable, Sequence
from typing import Any, ClassVar, SupportsFloat, TypedDict, final, overload, type_check_only

import numpy
import numpy.typing

from .control import (
    ComputedTorqueController,
    LinearAdaptiveController,
    NNAdaptiveController,
    PDController,
    PIDController,
    SlidingModeController,
    SuperTwistingController,
)
from .core import (
    Status,
    _Array,
    _ArrayField,
    _ArrayLike,
    _BoolField,
    _Enum,
    _Field,
    _Fields,
    _FloatField,
    _IntField,
    _ReadOnly,
    _TupleField,
    _ValidatedFields,
)
from .model import ThrusterConfig, Vehicle

# The configuration of a run (neurov/sim/config.hpp), field by field: Python
# holds the C++ object. Fixed-size vectors are writable views into it;
# dynamic arrays (command times and poses, thruster arrays) are read-only
# copies and lists of structs tuples of copies: assign them whole.

MAX_SUBSTEPS: int
"""The most RK4 substeps per control period (C++ ``neurov::kMaxSubsteps``, 10000)."""
MAX_WAVE_COMPONENTS: int
"""The most wave components of a run (C++ ``neurov::kMaxWaveComponents``, 512)."""

@type_check_only
class _SensorConfig(_Fields):
    """A sensor's configuration: its rate and latency."""

    rate: _FloatField = ...
    """[Hz], > 0."""
    latency: _FloatField = ...
    """[s], >= 0."""

class SensorFaultKind(_Enum):
    """What a sensor fault does to a measurement."""

    freeze: ClassVar[SensorFaultKind]
    """Repeats the last measurement delivered."""
    dropout: ClassVar[SensorFaultKind]
    """NaN, which the controller refuses."""
    noise_burst: ClassVar[SensorFaultKind]
    """Extra white noise."""
    __members__: ClassVar[dict[str, SensorFaultKind]]

class RefusedStepPolicy(_Enum):
    """The force applied when the controller refuses a step."""

    zero: ClassVar[RefusedStepPolicy]
    """No force."""
    hold: ClassVar[RefusedStepPolicy]
    """The last force the controller accepted."""
    __members__: ClassVar[dict[str, RefusedStepPolicy]]

class CurrentModel(_Enum):
    """The model of the current a run uses."""

    constant: ClassVar[CurrentModel]
    """Mean + sinusoid + steps (current, current_amplitude, current_period, current_steps)."""
    gauss_markov: ClassVar[CurrentModel]
    """First-order Gauss-Markov speed and direction (gauss_markov_current)."""
    __members__: ClassVar[dict[str, CurrentModel]]

class WaveSpectrum(_Enum):
    """The spectrum the waves realise."""

    jonswap: ClassVar[WaveSpectrum]
    """JONSWAP (hs, tp, gamma)."""
    pierson_moskowitz: ClassVar[WaveSpectrum]
    """Two-parameter Pierson-Moskowitz (Bretschneider/ITTC: hs, tp)."""
    __members__: ClassVar[dict[str, WaveSpectrum]]

@final
class EstimatorType(_Enum):
    """What the controller is given from the sensors."""

    none: ClassVar[EstimatorType]
    """Each sensor's latest reading, as it is."""
    ekf: ClassVar[EstimatorType]
    """The extended Kalman filter's estimate."""
    __members__: ClassVar[dict[str, EstimatorType]]

@final
class UsblConfig(_SensorConfig):
    """An acoustic position fix (USBL-like): NED position."""

    latency: _FloatField = ...
    """[s], >= 0 (acoustic travel and processing)."""
    noise: _FloatField = ...
    """Standard deviation per axis [m], >= 0."""
    bias: _ArrayField = ...
    """NED [m] (3,)."""

@final
class DvlConfig(_SensorConfig):
    """A Doppler velocity log: body velocity over ground."""

    noise: _FloatField = ...
    """Standard deviation per axis [m/s], >= 0."""
    dropout_rate: _FloatField = ...
    """Probability that a sample has no bottom lock, in [0, 1)."""
    bias: _ArrayField = ...
    """[m/s] (3,)."""

@final
class DepthConfig(_SensorConfig):
    """A pressure depth sensor: z, down positive."""

    noise: _FloatField = ...
    """Standard deviation [m], >= 0."""
    bias: _FloatField = ...
    """[m]."""

@final
class ImuConfig(_SensorConfig):
    """An AHRS/IMU: attitude and gyro rates, the gyro's bias walking."""

    attitude_noise: _FloatField = ...
    """Standard deviation of the angles [rad], >= 0."""
    gyro_noise: _FloatField = ...
    """Standard deviation of the rates [rad/s], >= 0."""
    gyro_bias_walk: _FloatField = ...
    """Bias random walk [rad/s/sqrt(s)], >= 0."""
    gyro_bias: _ArrayField = ...
    """Initial gyro bias [rad/s] (3,)."""

@final
class SensorsConfig(_Fields):
    """The sensors of a run, each optional; none configured: ideal sensing."""

    usbl: _Field[UsblConfig | None, UsblConfig | None] = ...
    """A UsblConfig, or None."""
    dvl: _Field[DvlConfig | None, DvlConfig | None] = ...
    """A DvlConfig, or None."""
    depth: _Field[DepthConfig | None, DepthConfig | None] = ...
    """A DepthConfig, or None."""
    imu: _Field[ImuConfig | None, ImuConfig | None] = ...
    """An ImuConfig, or None."""
    def any(self) -> bool:
        """Some sensor is configured."""

@final
class EstimatorConfig(_Fields):
    """What the controller is given from the sensors; the EKF's measurement noises are the sensors' own."""

    type: _Field[EstimatorType, EstimatorType] = ...
    """An EstimatorType."""
    linear_acceleration_noise: _FloatField = ...
    """sqrt of the PSD of the velocities' random walk [m/s^2/sqrt(Hz)], >= 0."""
    angular_acceleration_noise: _FloatField = ...
    """sqrt of the PSD of the rates' random walk [rad/s^2/sqrt(Hz)], >= 0."""
    initial_std: _ArrayField = ...
    """Standard deviations of the initial estimate (15,): position, angles, body velocity, rates, gyro bias."""

@final
class SinusoidalDisturbance(_Fields):
    """A force or moment in one body DOF: amplitude * sin(2 pi frequency (t - start) + phase) for t >= start."""

    dof: _IntField = ...
    """0..5: surge, sway, heave, roll, pitch, yaw."""
    amplitude: _FloatField = ...
    """[N] or [N m]."""
    frequency: _FloatField = ...
    """[Hz]."""
    phase: _FloatField = ...
    """[rad]."""
    start: _FloatField = ...
    """[s]."""

@final
class ThrusterFailure(_Fields):
    """Thruster ``index`` works at ``efficiency`` (0: failed) from ``time`` on."""

    index: _IntField = ...
    """The thruster (a column of the thruster matrix)."""
    efficiency: _FloatField = ...
    """In [0, 1]."""
    time: _FloatField = ...
    """[s]."""

@final
class SensorFault(_Fields):
    """A sensor fault over [start, end): the measurement of eta and/or nu freezes, drops out (NaN) or gets extra white noise."""

    kind: _Field[SensorFaultKind, SensorFaultKind] = ...
    """What the fault does."""
    start: _FloatField = ...
    """[s]."""
    end: _FloatField = ...
    """[s], >= start."""
    eta: _BoolField = ...
    """Affects the pose measurement."""
    nu: _BoolField = ...
    """Affects the velocity measurement."""
    noise_eta: _ArrayField = ...
    """Standard deviations (6,); noise_burst only."""
    noise_nu: _ArrayField = ...
    """Standard deviations (6,); noise_burst only."""

@final
class GaussMarkovCurrentConfig(_Fields):
    """A current whose speed, direction and vertical angle wander about their means as first-order Gauss-Markov processes (Fossen 2011, 8.3)."""

    speed: _FloatField = ...
    """Mean speed [m/s], within [speed_min, speed_max]."""
    speed_std: _FloatField = ...
    """Stationary standard deviation [m/s], >= 0."""
    time_constant: _FloatField = ...
    """Of all three processes [s], > 0."""
    speed_min: _FloatField = ...
    """Lower bound of the speed given out [m/s], >= 0."""
    speed_max: _FloatField = ...
    """Upper bound of the speed given out [m/s]."""
    direction: _FloatField = ...
    """Mean direction the current flows toward [deg from north]."""
    direction_std: _FloatField = ...
    """[deg], >= 0."""
    vertical_angle: _FloatField = ...
    """Mean angle below the horizontal plane [deg], positive flowing down."""
    vertical_angle_std: _FloatField = ...
    """[deg], >= 0."""

@final
class TetherConfig(_Fields):
    """A ROV's umbilical from a surface anchor to the vehicle: a quasi-static straight line whose normal drag, integrated along it, acts half at the vehicle's attachment point."""

    diameter: _FloatField = ...
    """d [m], > 0."""
    drag_coefficient: _FloatField = ...
    """C_d of the flow normal to the cable, >= 0."""
    anchor: _ArrayField = ...
    """The surface end, NED [m] (3,)."""
    attachment: _ArrayField = ...
    """The vehicle end, body axes [m] (3,)."""
    length: _FloatField = ...
    """[m]; 0: the straight distance at t = 0, which it may not be shorter than (slack is not modelled)."""

class WaveConfig(_Fields):
    """Linear deep-water waves realised from a spectrum as a sum of seeded components."""

    spectrum: _Field[WaveSpectrum, WaveSpectrum] = ...
    """A WaveSpectrum."""
    hs: _FloatField = ...
    """Significant wave height [m], > 0."""
    tp: _FloatField = ...
    """Peak period [s], > 0."""
    gamma: _FloatField = ...
    """JONSWAP peak enhancement, >= 1."""
    direction: _FloatField = ...
    """Direction the waves travel toward [deg from north]."""
    spreading: _FloatField = ...
    """n of the cos^n directional spreading; 0: long-crested."""
    components: _IntField = ...
    """Number of components, 1 to 512."""
    def spectral_density(self, omega: _ArrayLike) -> _Array:
        """S(omega) [m^2 s/rad] at the circular frequencies ``omega`` [rad/s] (0 for omega <= 0); JONSWAP normalised so that its m0 is hs^2/16."""

@final
class PayloadEvent(_Fields):
    """A change of the vehicle at ``time`` that the controller is not told about: mass, buoyancy, damping and added mass."""

    time: _FloatField = ...
    """When it happens [s], >= 0."""
    mass: _FloatField = ...
    """Mass added [kg] (negative: dropped); weight mass * 9.81."""
    mass_position: _Field[_Array | None, _ArrayLike | None] = ...
    """Where the mass sits, body axes [m] (3,); None: the centre of gravity."""
    buoyancy: _FloatField = ...
    """Buoyancy added [N] (negative: lost)."""
    buoyancy_position: _Field[_Array | None, _ArrayLike | None] = ...
    """Where it acts, body axes [m] (3,); None: the centre of buoyancy."""
    damping_scale: _ArrayField = ...
    """Factors on the linear and quadratic damping per DOF (6,)."""
    added_mass_scale: _FloatField = ...
    """Factor on the added-mass matrix."""

@final
class CurrentStep(_Fields):
    """From ``time`` on, the mean current is ``velocity``."""

    time: _FloatField = ...
    """[s]."""
    velocity: _ArrayField = ...
    """NED [m/s] (3,)."""

@final
class Command(_Fields):
    """Commanded poses at increasing times; held before the first and after the last; between them linear or held."""

    times: _ArrayField = ...
    """(K,) strictly increasing [s] (a read-only copy)."""
    poses: _ArrayField = ...
    """(K, 6) poses eta (a read-only copy)."""
    linear: _BoolField = ...
    """Linear between the poses; False: piecewise constant."""
    def at(self, t: SupportsFloat) -> _Array:
        """The commanded pose at time t."""

@final
class SimulationConfig(_ValidatedFields):
    """Everything of a closed-loop run but the vehicle and the controller.

    Rows of a run are at t_k = k dt; the force is held over each control
    period and the plant integrated by RK4 at dt / substeps.
    """

    dt: _FloatField = ...
    """Control period [s]."""
    substeps: _IntField = ...
    """RK4 steps per control period, 1 to 10000 (MAX_SUBSTEPS)."""
    duration: _FloatField = ...
    """[s]."""
    eta0: _ArrayField = ...
    """Initial pose (6,)."""
    nu0: _ArrayField = ...
    """Initial body velocity (6,)."""
    command: _Field[Command, Command] = ...
    """The commanded path."""
    lambda_d: _ArrayField = ...
    """Reference-model damping (6,)."""
    omega: _ArrayField = ...
    """Reference-model stiffness (6,)."""
    disturbances: _TupleField[SinusoidalDisturbance] = ...
    """Sinusoidal forces (a tuple of copies; assign a list)."""
    current: _ArrayField = ...
    """Mean current, NED [m/s] (3,)."""
    current_amplitude: _ArrayField = ...
    """Amplitude of the current's sinusoid per axis (3,)."""
    current_period: _FloatField = ...
    """[s]; 0 means a constant current."""
    noise_eta: _ArrayField = ...
    """Standard deviations of the pose noise (6,)."""
    noise_nu: _ArrayField = ...
    """Standard deviations of the velocity noise (6,)."""
    seed: _IntField = ...
    """Seed of the measurement noise; the current's and the waves' streams are derived from it."""
    use_thrusters: _BoolField = ...
    """Allocate the force to ``thrusters``; False: the force acts directly."""
    thrusters: _Field[ThrusterConfig, ThrusterConfig] = ...
    """The thruster layout."""
    thruster_failures: _TupleField[ThrusterFailure] = ...
    """Thruster failures (a tuple of copies; assign a list)."""
    sensor_faults: _TupleField[SensorFault] = ...
    """Sensor faults (a tuple of copies; assign a list)."""
    current_steps: _TupleField[CurrentStep] = ...
    """Steps of the mean current, in increasing time (a tuple of copies; assign a list)."""
    refused_step_policy: _Field[RefusedStepPolicy, RefusedStepPolicy] = ...
    """The force applied on a refused step."""
    current_model: _Field[CurrentModel, CurrentModel] = ...
    """A CurrentModel."""
    gauss_markov_current: _Field[GaussMarkovCurrentConfig, GaussMarkovCurrentConfig] = ...
    """The Gauss-Markov current, used with current_model gauss_markov."""
    waves: _Field[WaveConfig | None, WaveConfig | None] = ...
    """A WaveConfig, or None for a calm sea."""
    payload: _TupleField[PayloadEvent] = ...
    """Payload events in non-decreasing time (a tuple of copies; assign a list)."""
    control_delay: _IntField = ...
    """Control periods between a measurement and the force computed from it acting, 0..16 (0: in the same period)."""
    water_density: _FloatField = ...
    """[kg/m^3], > 0 (sea water by default); a vehicle file's displaced volume gives its buoyancy as buoyancy_in_water(water_density, volume)."""
    sensors: _Field[SensorsConfig, SensorsConfig] = ...
    """The sensors; none: ideal sensing."""
    estimator: _Field[EstimatorConfig, EstimatorConfig] = ...
    """The estimator."""
    tether: _Field[TetherConfig | None, TetherConfig | None] = ...
    """A TetherConfig, or None: no tether."""

def buoyancy_in_water(water_density: SupportsFloat, displaced_volume: SupportsFloat) -> float:
    """B = rho g V [N]: the buoyancy of displaced_volume [m^3] in water of water_density [kg/m^3]."""

RESULT_SERIES: tuple[tuple[str, int | None, str, tuple[str, ...], str, str, str, str], ...]
"""The series a run logs (NEUROV_RESULT_SERIES in neurov/sim/result.hpp), in
the order of the CSV's columns, each (name, width or None where it varies,
varies_with, labels, unit, dtype, kind, description); :func:`run_closed_loop`
returns one array per entry. :data:`neurov.columns.RESULT_SERIES` names the
fields."""

@type_check_only
class _SimulationResult(TypedDict):
    """What :func:`run_closed_loop` returns: one row per control step t_k = k dt,
    one array per entry of :data:`RESULT_SERIES` (in its order)."""

    t: _Array
    eta: _Array
    nu: _Array
    eta_d: _Array
    eta_d_dot: _Array
    tau_demanded: _Array
    tau_applied: _Array
    disturbance: _Array
    s: _Array
    eta_estimate: _Array
    nu_estimate: _Array
    thrusts: _Array
    theta: _Array
    adaptive_norm: _Array
    controller_status: numpy.typing.NDArray[numpy.uint8]
    plant_status: numpy.typing.NDArray[numpy.uint8]
    faults: numpy.typing.NDArray[numpy.uint8]
    """Per step: bit 1 freeze, 2 dropout, 4 noise burst, 8 a thruster below full efficiency,
    16 the row's eta_d came from a pitch-limited reference step, 32 the vehicle above the
    wave model's minimum depth."""
    current: _Array
    """(N, 3) NED current at the vehicle [m/s]."""
    wave_velocity: _Array
    """(N, 3) NED orbital velocity at the vehicle [m/s] (zeros in a calm sea)."""
    wave_elevation: _Array
    """(N,) surface elevation above the vehicle [m]."""
    payload_mass: _Array
    """(N,) payload mass in effect [kg]."""
    diverged: bool

@overload
def run_closed_loop(vehicle: Vehicle, controller: NNAdaptiveController, config: SimulationConfig) -> _SimulationResult:
    """Runs a closed loop in C++ with ``config`` and returns a dict of arrays (rows at t_k = k dt).

    Keys: one per entry of :data:`RESULT_SERIES` (t, eta, nu, ...), and
    diverged (bool). The controller is used as given and
    left in its final state; the GIL is released meanwhile. A bad configuration
    raises ValueError naming the field. ``neurov.simulate(scenario)`` is the
    friendly front end.
    """
@overload
def run_closed_loop(vehicle: Vehicle, controller: LinearAdaptiveController, config: SimulationConfig) -> _SimulationResult: ...
@overload
def run_closed_loop(vehicle: Vehicle, controller: PDController, config: SimulationConfig) -> _SimulationResult: ...
@overload
def run_closed_loop(vehicle: Vehicle, controller: PIDController, config: SimulationConfig) -> _SimulationResult: ...
@overload
def run_closed_loop(vehicle: Vehicle, controller: SlidingModeController, config: SimulationConfig) -> _SimulationResult: ...
@overload
def run_closed_loop(vehicle: Vehicle, controller: ComputedTorqueController, config: SimulationConfig) -> _SimulationResult: ...
@overload
def run_closed_loop(vehicle: Vehicle, controller: SuperTwistingController, config: SimulationConfig) -> _SimulationResult: ...

@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: NNAdaptiveController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None:
    """The run of :func:`run_closed_loop` with its rows handed over in chunks:
    ``on_rows(dict)`` gets each chunk of at most ``chunk_rows`` rows in time order
    (the last chunk's ``diverged`` says how the run ended), so a run of any length
    holds one chunk in memory. A bad configuration or ``chunk_rows`` < 1 raises
    ValueError before any step; an exception raised by ``on_rows`` ends the run and
    propagates."""
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: LinearAdaptiveController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: PDController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: PIDController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: SlidingModeController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: ComputedTorqueController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...
@overload
def run_closed_loop_chunks(vehicle: Vehicle, controller: SuperTwistingController, config: SimulationConfig, chunk_rows: int,
                           on_rows: Callable[[_SimulationResult], None]) -> None: ...

# The simulator stepped from Python (neurov/sim/simulator.hpp)

@final
class Observation:
    """What a controller is given at t_k: the measured pose and velocity (noise and
    sensor faults applied; NaN in a dropout) and the desired state."""

    def __init__(
        self,
        t: float,
        eta: _ArrayLike,
        nu: _ArrayLike,
        eta_d: _ArrayLike,
        eta_d_dot: _ArrayLike,
        eta_d_ddot: _ArrayLike,
    ) -> None:
        """An observation, e.g. to test a controller (eta and nu may hold NaN, as in a dropout)."""
    t: _ReadOnly[float] = ...
    """Time t_k [s]."""
    eta: _ReadOnly[_Array] = ...
    """Measured pose (6,)."""
    nu: _ReadOnly[_Array] = ...
    """Measured body velocity (6,)."""
    eta_d: _ReadOnly[_Array] = ...
    """Desired pose (6,)."""
    eta_d_dot: _ReadOnly[_Array] = ...
    """Its first time derivative (6,)."""
    eta_d_ddot: _ReadOnly[_Array] = ...
    """Its second time derivative (6,)."""

@final
class Simulator:
    """Everything of a run except the controller, stepped one control period at a time.

    The same rows as :func:`run_closed_loop` for the same forces.
    """

    def __init__(self, vehicle: Vehicle, config: SimulationConfig, logged_parameters: int = 0,
                 log_rows: int = 0) -> None:
        """Copies the vehicle and the configuration; ``logged_parameters`` is the number
        of parameters :meth:`step` logs per row (the result's theta columns);
        ``log_rows`` > 0 keeps a window of at most that many rows, emptied by
        :meth:`drain` (0: every row of the run). Raises ValueError naming a bad field."""
    def reset(self, seed: int | None = None) -> None:
        """Back to t = 0 with noise from ``seed``; None: the seed of the last reset
        (the configuration's at first), so the same run again."""
    observation: _ReadOnly[Observation] = ...
    """What the controller is to be given at t_k = steps * dt."""
    def step(
        self,
        tau: _ArrayLike,
        status: Status = Status.ok,
        s: _ArrayLike | None = None,
        adaptive_norm: float = 0.0,
        parameters: _ArrayLike | None = None,
    ) -> Status:
        """Logs row k with the force ``tau`` (6,) and the controller's report, and
        advances one control period; returns the plant's status.

        ``status`` other than ok is a refused step: the refused-step policy decides
        the force. ``s``, ``adaptive_norm`` and ``parameters`` (logged_parameters,)
        are logged. ``tau`` must be finite when ``status`` is ok. After done,
        raises RuntimeError and changes nothing.
        """
    done: _ReadOnly[bool] = ...
    """Every row simulated, or the plant diverged."""
    diverged: _ReadOnly[bool] = ...
    """The plant diverged (its last row is the one where it did)."""
    steps: _ReadOnly[int] = ...
    """Rows logged so far."""
    planned_steps: _ReadOnly[int] = ...
    """Rows of a whole run: round(duration / dt) + 1."""
    logged_parameters: _ReadOnly[int] = ...
    """Parameters logged per row."""
    faults: _ReadOnly[int] = ...
    """Fault bits of the sensor faults and pitch limit in the observation."""
    state: _ReadOnly[tuple[_Array, _Array]] = ...
    """The true (eta, nu) at t_k."""
    estimate_covariance: _ReadOnly[_Array | None] = ...
    """The EKF's covariance (15, 15) at t_k (position, angles, body velocity, rates, gyro bias), or None without the ekf estimator."""
    config: _ReadOnly[SimulationConfig] = ...
    """A copy of the configuration."""
    log_rows: _ReadOnly[int] = ...
    """Rows the log holds at most (the whole run, or the window)."""
    logged_from: _ReadOnly[int] = ...
    """The run's index of the log's first row (the rows drained before it)."""
    log_full: _ReadOnly[bool] = ...
    """The log window is full: :meth:`step` refuses until :meth:`drain`."""
    def result(self) -> _SimulationResult:
        """The rows in the log (logged so far, or since the last drain), as the dict
        :func:`run_closed_loop` returns."""
    def drain(self) -> _SimulationResult:
        """The rows in the log, as :meth:`result` gives them, and empties the log so
        that stepping goes on past a full window."""

# Many runs at once (python/bindings/sim/batch.cpp).

_BuiltIn = (NNAdaptiveController | LinearAdaptiveController | PDController | PIDController
            | SlidingModeController | ComputedTorqueController | SuperTwistingController)

WINDOW_SUMS: tuple[tuple[str, int, str], ...]
"""The sums a run's metrics are computed from: (name, width, description),
the fields of :class:`neurov.metrics.WindowSums`."""

LANE_NOT_STEPPED: int
"""The status :meth:`BatchSimulator.step` gives a lane it did not step (255)."""

@final
class BatchSimulator:
    """K runs (lanes) stepped in lockstep from outside, one call per step for
    every lane; each lane gives the rows of the same run alone."""

    def __init__(self, vehicles: Sequence[Vehicle], configs: Sequence[SimulationConfig],
                 logged_parameters: int = 0) -> None:
        """Lane i from vehicles[i] and configs[i], each copied. A refused lane
        raises ValidationError naming the lane and the field."""
    size: _ReadOnly[int] = ...
    """K, the number of lanes."""
    logged_parameters: _ReadOnly[int] = ...
    observation: _ReadOnly[dict[str, _Array]] = ...
    """t (K,), eta, nu, eta_d, eta_d_dot, eta_d_ddot (K, 6), faults (K,) uint8."""
    state: _ReadOnly[tuple[_Array, _Array]] = ...
    """The true (eta, nu), each (K, 6)."""
    def step(self, tau: numpy.typing.NDArray[numpy.float64],
             mask: numpy.typing.NDArray[numpy.bool_] | None = None,
             parameters: numpy.typing.NDArray[numpy.float64] | None = None) -> numpy.typing.NDArray[numpy.uint8]:
        """Steps the lanes in mask (None: all) that are not done with tau (K, 6);
        returns the (K,) plant statuses, LANE_NOT_STEPPED for a lane not stepped."""
    done: _ReadOnly[numpy.typing.NDArray[numpy.bool_]] = ...
    diverged: _ReadOnly[numpy.typing.NDArray[numpy.bool_]] = ...
    steps: _ReadOnly[numpy.typing.NDArray[numpy.int64]] = ...
    planned_steps: _ReadOnly[numpy.typing.NDArray[numpy.int64]] = ...
    def reset(self, seeds: numpy.typing.NDArray[numpy.integer[Any]],
              mask: numpy.typing.NDArray[numpy.bool_] | None = None) -> None:
        """The lanes in mask (None: all) back to t = 0 with noise from seeds[i]."""
    def replace(self, i: int, vehicle: Vehicle, config: SimulationConfig) -> None:
        """Lane i created again (ValidationError naming the field leaves it untouched)."""
    def result(self, i: int) -> _SimulationResult:
        """Lane i's rows so far, as run_closed_loop returns them."""

def run_batch(vehicles: Sequence[Vehicle], controllers: Sequence[_BuiltIn], configs: Sequence[SimulationConfig],
              threads: int = 0, metrics_only: bool = False,
              after: SupportsFloat | Sequence[SupportsFloat] | None = None) -> list[Any]:
    """Runs K built-in closed loops over threads; one run_closed_loop dict per
    run, or with metrics_only the metric sums of t >= after."""
