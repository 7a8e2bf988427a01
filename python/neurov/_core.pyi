"""neurov's C++ core: vehicle dynamics, Euler-angle kinematics, integrator,
reference model, controllers and closed-loop simulation (double precision).
Import from ``neurov``, not from here.

Every array argument accepts anything ``numpy.asarray`` turns into a real
(float or integer) array of the stated shape: lists, integer arrays,
non-contiguous and read-only arrays. A wrong shape, NaN or Inf raises
``ValueError`` and a wrong dtype (str, complex, object, bool) or ``None``
raises ``TypeError``; both name the argument. Scalars are real numbers (not
``bool``). Every returned array is a new, writeable ``float64`` array.
"""

# The declarations are in stub-only modules, one per layer of the bindings
# (core, model, control, sim); this stub re-exports their public names.
from ._core_stubs.core import (
    NeurovError as NeurovError,
    Status as Status,
    ValidationError as ValidationError,
)
from ._core_stubs.model import (
    Saturation as Saturation,
    THETA_NAMES as THETA_NAMES,
    ThrusterConfig as ThrusterConfig,
    ThrusterCurveConfig as ThrusterCurveConfig,
    Vehicle as Vehicle,
    allocate_thrust as allocate_thrust,
    bluerov2_heavy_layout as bluerov2_heavy_layout,
    is_near_singularity as is_near_singularity,
    jacobian as jacobian,
    jacobian_dot as jacobian_dot,
    jacobian_inverse as jacobian_inverse,
    plant_derivative as plant_derivative,
    plant_jacobians as plant_jacobians,
    regressor as regressor,
    regressor_parameters as regressor_parameters,
    rk4_step as rk4_step,
    rotation as rotation,
    singularity_threshold as singularity_threshold,
    to_body as to_body,
)
from ._core_stubs.control import (
    BUILT_IN_CONTROLLERS as BUILT_IN_CONTROLLERS,
    ComputedTorqueConfig as ComputedTorqueConfig,
    ComputedTorqueController as ComputedTorqueController,
    LinearAdaptiveConfig as LinearAdaptiveConfig,
    LinearAdaptiveController as LinearAdaptiveController,
    MAX_CENTRES as MAX_CENTRES,
    NNAdaptiveConfig as NNAdaptiveConfig,
    NNAdaptiveController as NNAdaptiveController,
    PDConfig as PDConfig,
    PDController as PDController,
    PIDConfig as PIDConfig,
    PIDController as PIDController,
    RbfNetwork as RbfNetwork,
    ReferenceModel as ReferenceModel,
    RobustModification as RobustModification,
    SlidingModeConfig as SlidingModeConfig,
    SlidingModeController as SlidingModeController,
    SuperTwistingConfig as SuperTwistingConfig,
    SuperTwistingController as SuperTwistingController,
    tracking_error as tracking_error,
)
from ._core_stubs.sim import (
    BatchSimulator as BatchSimulator,
    LANE_NOT_STEPPED as LANE_NOT_STEPPED,
    WINDOW_SUMS as WINDOW_SUMS,
    run_batch as run_batch,
    Command as Command,
    CurrentModel as CurrentModel,
    CurrentStep as CurrentStep,
    DepthConfig as DepthConfig,
    DvlConfig as DvlConfig,
    EstimatorConfig as EstimatorConfig,
    EstimatorType as EstimatorType,
    GaussMarkovCurrentConfig as GaussMarkovCurrentConfig,
    ImuConfig as ImuConfig,
    MAX_SUBSTEPS as MAX_SUBSTEPS,
    MAX_WAVE_COMPONENTS as MAX_WAVE_COMPONENTS,
    Observation as Observation,
    PayloadEvent as PayloadEvent,
    RESULT_SERIES as RESULT_SERIES,
    RefusedStepPolicy as RefusedStepPolicy,
    SensorFault as SensorFault,
    SensorFaultKind as SensorFaultKind,
    SensorsConfig as SensorsConfig,
    SimulationConfig as SimulationConfig,
    Simulator as Simulator,
    SinusoidalDisturbance as SinusoidalDisturbance,
    ThrusterFailure as ThrusterFailure,
    UsblConfig as UsblConfig,
    TetherConfig as TetherConfig,
    WaveConfig as WaveConfig,
    WaveSpectrum as WaveSpectrum,
    buoyancy_in_water as buoyancy_in_water,
    run_closed_loop as run_closed_loop,
    run_closed_loop_chunks as run_closed_loop_chunks,
)

__version__: str
