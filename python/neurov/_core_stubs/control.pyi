"""Stub-only piece of :mod:`neurov._core` for type checkers (nothing imports it
at runtime): the layer ``control``, the reference model, tracking error, RBF
network, the controllers and their configurations (``python/bindings/control``)."""

# The pieces share their private helpers (arrays, descriptors, bases).
# pyright: reportPrivateUsage=false

import os
from typing import ClassVar, Literal, SupportsFloat, TypedDict, final, overload, type_check_only

from .core import _Array, _ArrayField, _ArrayLike, _Enum, _Field, _FloatField, _ReadOnly, _ValidatedFields
from .model import Vehicle

_Modification = Literal["none", "sigma", "e_modification", "projection"]

@type_check_only
class _SlidingConfig(_ValidatedFields):
    """The configuration of a law on the sliding variable s: Lambda and K_d."""

    lambda_: _ArrayField = ...
    """Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,), > 0."""
    kd: _ArrayField = ...
    """K_d, diagonal (6,), >= 0."""

@type_check_only
class _Tracking(TypedDict):
    """Tracking error and virtual reference (eq. 11, 14-16); every entry has shape (6,)."""

    eta_tilde: _Array
    eta_tilde_dot: _Array
    s: _Array
    eta_r_dot: _Array
    eta_r_ddot: _Array
    nu_r: _Array
    nu_r_dot: _Array

class ReferenceModel:
    """Reference model of eq. 12-13: ``nu_d_dot = -Lambda_d nu_d + J^T(eta_d) Omega (r - eta_d)``,
    ``eta_d_dot = J(eta_d) nu_d``. Turns a commanded pose r into a smooth desired trajectory."""

    def __init__(self, lambda_d: _ArrayLike, omega: _ArrayLike, eta0: _ArrayLike | None = None) -> None:
        """lambda_d: damping diagonal (6,), > 0; omega: stiffness diagonal (6,), > 0;
        eta0: initial pose (6,), default zero. Starts at rest."""
    def step(self, r: _ArrayLike, dt: SupportsFloat) -> tuple[_Array, _Array, _Array]:
        """Advances by dt with the commanded pose r (6,) held (RK4).

        Returns ``(eta_d, eta_d_dot, eta_d_ddot)``, each (6,). A refused step
        raises ``ValueError`` and changes nothing.
        """
    def reset(self, eta0: _ArrayLike) -> None:
        """Back to rest at eta0 (6,)."""
    eta_d: _ReadOnly[_Array] = ...
    """Current desired pose (6,)."""
    nu_d: _ReadOnly[_Array] = ...
    """Current desired body velocity (6,)."""
    lambda_d: _ReadOnly[_Array] = ...
    """Damping diagonal (6,)."""
    omega: _ReadOnly[_Array] = ...
    """Stiffness diagonal (6,)."""
    pitch_limited: _ReadOnly[bool] = ...
    """True when the last accepted step limited the pitch to +-(pi/2 - 0.2) rad.

    The command's pitch is clamped to that limit and the reference's own
    pitch is held at it; such a step is taken and returns normally.
    False after construction and ``reset()``.
    """

def tracking_error(
    eta: _ArrayLike,
    nu: _ArrayLike,
    eta_d: _ArrayLike,
    eta_d_dot: _ArrayLike,
    eta_d_ddot: _ArrayLike,
    lambda_: _ArrayLike,
) -> _Tracking:
    """Tracking error and virtual reference (eq. 11, 14-16) with the diagonal Lambda (6,).

    Returns a dict of (6,) arrays: eta_tilde, eta_tilde_dot, s, eta_r_dot,
    eta_r_ddot, nu_r, nu_r_dot. Raises ``ValueError`` at the pitch singularity.
    """

MAX_CENTRES: int
"""The most centres a network takes (C++ ``neurov::kMaxCentres``, 65536)."""

class RbfNetwork:
    """Radial-basis-function network (eq. 30).

    ``g_j(x) = exp(-||x_hat - xi_j||^2 / (2 sigma_j^2))``, output ``W g(x)``
    with W (6, N); ``x_hat = (x - input_offset) * input_scale``.
    """

    def __init__(
        self,
        centres: _ArrayLike,
        width: SupportsFloat | _ArrayLike,
        input_offset: _ArrayLike | None = None,
        input_scale: _ArrayLike | None = None,
    ) -> None:
        """centres: (N, n_in), one centre per row, N at most MAX_CENTRES (65536); width:
        sigma for every centre, or (N,) per centre, > 0; input_offset and input_scale: (n_in,) input normalisation,
        default identity (the paper's choice). Weights start at zero."""
    def basis(self, x: _ArrayLike) -> _Array:
        """Basis values g(x) for an input x (n_in,), shape (N,)."""
    def output(self, x: _ArrayLike) -> _Array:
        """Network output W g(x) for an input x (n_in,), shape (6,)."""
    weights: _ArrayField = ...
    """Output weights W, shape (6, N); assignable."""
    centres: _ReadOnly[_Array] = ...
    """Centres, shape (N, n_in)."""
    widths: _ReadOnly[_Array] = ...
    """Widths sigma_j, shape (N,)."""
    input_offset: _ReadOnly[_Array] = ...
    """Input offset, shape (n_in,)."""
    input_scale: _ReadOnly[_Array] = ...
    """Input scale, shape (n_in,)."""
    n_inputs: _ReadOnly[int] = ...
    """Number of inputs n_in."""
    n_centres: _ReadOnly[int] = ...
    """Number of centres N."""

@final
class RobustModification(_Enum):
    """Robust modification of the NN controller's adaptive law."""

    none: ClassVar[RobustModification]
    """The paper's pure gradient law."""
    sigma: ClassVar[RobustModification]
    """Leakage: W_dot += -sigma_m W Gamma_w."""
    e_modification: ClassVar[RobustModification]
    """Leakage in proportion to the error: W_dot += -kappa ||J^-1 s|| W Gamma_w."""
    projection: ClassVar[RobustModification]
    """After each update, W scaled back onto ||W||_F <= w_max."""
    __members__: ClassVar[dict[str, RobustModification]]

class PDConfig(_ValidatedFields):
    """Configuration of :class:`PDController`."""

    kp: _ArrayField = ...
    """K_p, diagonal (6,), >= 0."""
    kd: _ArrayField = ...
    """K_d, diagonal (6,), >= 0."""

class PIDConfig(_ValidatedFields):
    """Configuration of :class:`PIDController`."""

    kp: _ArrayField = ...
    """K_p, diagonal (6,), >= 0."""
    ki: _ArrayField = ...
    """K_i, diagonal (6,), >= 0."""
    kd: _ArrayField = ...
    """K_d, diagonal (6,), >= 0."""
    integral_limit: _ArrayField = ...
    """Largest |K_i z| per DOF (6,), > 0 [N, N m]."""
    dt: _FloatField = ...
    """Control period [s], > 0."""

class SlidingModeConfig(_SlidingConfig):
    """Configuration of :class:`SlidingModeController`."""

    k: _ArrayField = ...
    """Switching gain K (6,), >= 0 [N, N m]."""
    phi: _ArrayField = ...
    """Boundary-layer width (6,), > 0, in units of s."""
    theta: _ArrayField = ...
    """The nominal model's theta (24,), e.g. ``regressor_parameters(vehicle)``."""

class SuperTwistingConfig(_SlidingConfig):
    """Configuration of :class:`SuperTwistingController`."""

    alpha: _ArrayField = ...
    """alpha, gain of |s|^(1/2) sgn(s) per unit inertia (6,), > 0."""
    beta: _ArrayField = ...
    """beta, integral gain per unit inertia (6,), > 0."""
    force_limit: _ArrayField = ...
    """Largest force of the sliding terms per DOF (6,), > 0 [N, N m] (anti-windup of the integral term)."""
    theta: _ArrayField = ...
    """The nominal model's theta (24,), e.g. ``regressor_parameters(vehicle)``."""
    dt: _FloatField = ...
    """Control period [s], > 0: the implicit step."""

class LinearAdaptiveConfig(_SlidingConfig):
    """Configuration of :class:`LinearAdaptiveController`."""

    gamma: _Field[_Array, SupportsFloat | _ArrayLike] = ...
    """Diagonal of Gamma (24,), >= 0 (0 freezes that parameter); a number sets every entry."""
    dt: _FloatField = ...
    """Control period [s], > 0."""
    theta0: _ArrayField = ...
    """theta_hat(0) (24,): zero, or a nominal guess such as ``regressor_parameters(vehicle)``."""

class NNAdaptiveConfig(_SlidingConfig):
    """Configuration of :class:`NNAdaptiveController`."""

    kd: _ArrayField = ...
    """K_d, diagonal (6,), >= 0 (0 leaves the network alone)."""
    gamma: _FloatField = ...
    """Gamma_w = gamma I, >= 0 (the paper: 0.3)."""
    dt: _FloatField = ...
    """Control period [s], > 0 (the paper: 0.2)."""
    modification: _Field[RobustModification, RobustModification | _Modification] = ...
    """The robust modification: a RobustModification or its name."""
    sigma_m: _FloatField = ...
    """Leakage of the sigma-modification (> 0 when used)."""
    kappa: _FloatField = ...
    """Gain of the e-modification (> 0 when used)."""
    w_max: _FloatField = ...
    """Frobenius bound of the projection (> 0 when used)."""
    dead_zone: _FloatField = ...
    """No adaptation while ||s|| < dead_zone (0 disables), >= 0."""

class ComputedTorqueConfig(_SlidingConfig):
    """Configuration of :class:`ComputedTorqueController`."""

    vehicle: _Field[Vehicle | None, Vehicle] = ...
    """The nominal model, a Vehicle (None until set)."""

@type_check_only
class _Controller:
    """What every controller has (a stub-only base: at runtime the classes are unrelated)."""

    def step(
        self,
        eta: _ArrayLike,
        nu: _ArrayLike,
        eta_d: _ArrayLike,
        eta_d_dot: _ArrayLike,
        eta_d_ddot: _ArrayLike,
    ) -> _Array:
        """One control step; returns tau (6,), the body forces and moments.

        eta (6,) and nu (6,) are the measured pose and body velocity; eta_d,
        eta_d_dot, eta_d_ddot (6,) the desired motion in the earth frame. A
        NaN/Inf input, or the pitch singularity, raises ``ValueError`` and
        leaves the controller exactly as it was.
        """
    def reset(self) -> None:
        """Back to the initial state and a zero history."""
    s: _ReadOnly[_Array] = ...
    """Filtered tracking error s of the last step, shape (6,)."""
    tracking: _ReadOnly[_Tracking] = ...
    """Tracking error and virtual reference of the last step (a dict of (6,) arrays)."""
    type_name: ClassVar[str]
    """Its ``type`` in a scenario file (a key of :data:`BUILT_IN_CONTROLLERS`)."""
    title: ClassVar[str]
    """Its name in tables and plots."""
    Config: ClassVar[type]
    """Its configuration class."""

BUILT_IN_CONTROLLERS: dict[str, type[_Controller]]
"""The built-in controllers, type name -> class, in the order of the C++ list
(neurov/control/built_in_controllers.hpp)."""

class NNAdaptiveController(_Controller):
    """Direct adaptive RBF-network controller (eq. 35, 37).

    ``tau = W g(x) - J^T K_d s`` with ``x = [nu_r_dot; nu_r; nu; eta]`` (24
    inputs), then ``W <- W - dt (J^-1 s) g(x)^T Gamma_w``. tau uses the
    weights from before the update.
    """

    @overload
    def __init__(
        self, network: RbfNetwork, config: NNAdaptiveConfig, *, learning_rates: _ArrayLike | None = None
    ) -> None:
        """network: an RbfNetwork with 24 inputs (copied; its weights are W(0)); config:
        an NNAdaptiveConfig; learning_rates (N,): per-centre Gamma_w."""
    @overload
    def __init__(
        self,
        network: RbfNetwork,
        lambda_: _ArrayLike,
        kd: _ArrayLike,
        gamma: SupportsFloat = 0.3,
        dt: SupportsFloat = 0.2,
        *,
        modification: _Modification = "none",
        sigma_m: SupportsFloat = 0.0,
        kappa: SupportsFloat = 0.0,
        w_max: SupportsFloat = 0.0,
        dead_zone: SupportsFloat = 0.0,
        learning_rates: _ArrayLike | None = None,
    ) -> None:
        """network: an RbfNetwork with 24 inputs (copied; its weights are W(0));
        lambda_: Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma:
        Gamma_w = gamma I (the paper: 0.3); dt: control period [s] (the paper:
        0.2). Robust modifications (off by default): ``'sigma'`` (sigma_m > 0),
        ``'e_modification'`` (kappa > 0) or ``'projection'`` (||W||_F <= w_max);
        dead_zone: no adaptation while ||s|| < dead_zone; learning_rates (N,):
        per-centre Gamma_w."""
    config: _ReadOnly[NNAdaptiveConfig] = ...
    """A copy of the configuration the controller was built from."""
    weights: _ArrayField = ...
    """Current weights W, shape (6, N); assignable (warm start)."""
    weight_norm: _ReadOnly[float] = ...
    """||W||_F."""
    network_output: _ReadOnly[_Array] = ...
    """W g(x) of the last step (before its update), shape (6,)."""
    basis: _ReadOnly[_Array] = ...
    """g(x) of the last step, shape (N,)."""
    adapted: _ReadOnly[bool] = ...
    """Whether the last step moved the weights (False in the dead zone)."""
    n_centres: _ReadOnly[int] = ...
    """Number of centres N."""
    centres: _ReadOnly[_Array] = ...
    """Centres, shape (N, 24)."""
    widths: _ReadOnly[_Array] = ...
    """Widths sigma_j, shape (N,)."""
    input_offset: _ReadOnly[_Array] = ...
    """Input offset of the network's normalisation, shape (24,)."""
    input_scale: _ReadOnly[_Array] = ...
    """Input scale of the network's normalisation, shape (24,)."""
    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes W and its network to a .npz file (format: neurov.laws.weights)."""
    def load(self, path: str | os.PathLike[str]) -> None:
        """Sets W from a file written by save(); WeightsFileError names a misfit."""
    modification: _ReadOnly[_Modification] = ...
    """The robust modification in use."""

class LinearAdaptiveController(_Controller):
    """Linearly parameterised adaptive controller (eq. 26, 28; Fossen and Sagatun).

    ``tau = Phi theta_hat - J^T K_d s``, ``theta_hat <- theta_hat - dt Gamma
    Phi^T J^-1 s``. Knows NEROV's model structure (see :func:`regressor`),
    not its parameters.
    """

    @overload
    def __init__(self, config: LinearAdaptiveConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(
        self,
        lambda_: _ArrayLike,
        kd: _ArrayLike,
        gamma: SupportsFloat | _ArrayLike,
        dt: SupportsFloat = 0.2,
        theta0: _ArrayLike | None = None,
    ) -> None:
        """lambda_: Lambda diagonal (6,), > 0; kd: K_d diagonal (6,), >= 0; gamma:
        Gamma diagonal, a number or (24,), >= 0; dt: control period [s]; theta0:
        theta_hat(0) (24,), default zero (``regressor_parameters(vehicle)`` gives
        the true one)."""
    config: _ReadOnly[LinearAdaptiveConfig] = ...
    """A copy of the configuration the controller was built from."""
    theta: _ArrayField = ...
    """Current estimate theta_hat (24,); assignable."""
    model_output: _ReadOnly[_Array] = ...
    """Phi theta_hat of the last step, shape (6,)."""

class PDController(_Controller):
    """PD baseline in the earth frame: ``tau = -J^T (K_p eta_tilde + K_d eta_tilde_dot)``."""

    @overload
    def __init__(self, config: PDConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(self, kp: _ArrayLike, kd: _ArrayLike) -> None:
        """kp, kd: diagonal gains (6,), >= 0."""
    config: _ReadOnly[PDConfig] = ...
    """A copy of the configuration the controller was built from."""

class PIDController(_Controller):
    """PID baseline in the earth frame with anti-windup.

    ``tau = -J^T (K_p eta_tilde + K_i z + K_d eta_tilde_dot)``, z the integral
    of eta_tilde, ``|K_i z| <= integral_limit`` per DOF and no integration
    further into the limit.
    """

    @overload
    def __init__(self, config: PIDConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(
        self,
        kp: _ArrayLike,
        ki: _ArrayLike,
        kd: _ArrayLike,
        integral_limit: _ArrayLike,
        dt: SupportsFloat = 0.2,
    ) -> None:
        """kp, ki, kd: diagonal gains (6,), >= 0; integral_limit: largest |K_i z| per DOF
        (6,), > 0 [N, N m]; dt: control period [s]."""
    config: _ReadOnly[PIDConfig] = ...
    """A copy of the configuration the controller was built from."""
    integral: _ReadOnly[_Array] = ...
    """The integrator state z (6,), the limited time integral of eta_tilde."""

class SlidingModeController(_Controller):
    """Sliding-mode controller with a boundary layer.

    ``tau = Phi theta - J^T (K_d s + K sat(s / phi))``, with theta the
    nominal model's parameters (see :func:`regressor`).
    """

    @overload
    def __init__(self, config: SlidingModeConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(
        self,
        lambda_: _ArrayLike,
        kd: _ArrayLike,
        k: _ArrayLike,
        phi: _ArrayLike,
        theta: _ArrayLike,
    ) -> None:
        """lambda_: Lambda (6,), > 0; kd: K_d (6,), >= 0; k: switching gain (6,), >= 0;
        phi: boundary-layer width (6,), > 0; theta: the nominal model (24,), e.g.
        ``regressor_parameters(vehicle)``."""
    config: _ReadOnly[SlidingModeConfig] = ...
    """A copy of the configuration the controller was built from."""
    model_output: _ReadOnly[_Array] = ...
    """The nominal model's f of the last step, shape (6,)."""

class ComputedTorqueController(_Controller):
    """Computed-torque (inverse-dynamics) controller on a nominal vehicle.

    ``tau = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) - J^T K_d s`` with
    the vehicle's own M, C(nu), D(nu) and g(eta), in either Coriolis form.
    """

    @overload
    def __init__(self, config: ComputedTorqueConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(self, vehicle: Vehicle, lambda_: _ArrayLike, kd: _ArrayLike) -> None:
        """vehicle: the nominal model (its parameters are copied); lambda_: Lambda (6,),
        > 0; kd: K_d (6,), >= 0."""
    config: _ReadOnly[ComputedTorqueConfig] = ...
    """A copy of the configuration the controller was built from."""
    model_output: _ReadOnly[_Array] = ...
    """M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) of the last step, shape (6,)."""

class SuperTwistingController(_Controller):
    """Super-twisting sliding-mode controller, implicit (chattering-free) discretisation.

    ``tau = Phi theta - J^T M (c s + alpha |s|^(1/2) sgn(s) + v)``,
    ``v_dot = beta sgn(s)``, ``c = K_d / M``, evaluated at the s of the next
    step that it predicts (Brogliato, Polyakov and Efimov 2020); the sliding
    terms are limited to force_limit and v does not wind up.
    """

    @overload
    def __init__(self, config: SuperTwistingConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(
        self,
        lambda_: _ArrayLike,
        kd: _ArrayLike,
        alpha: _ArrayLike,
        beta: _ArrayLike,
        force_limit: _ArrayLike,
        theta: _ArrayLike,
        dt: SupportsFloat = 0.2,
    ) -> None:
        """The configuration's fields by name (see SuperTwistingConfig); ``ValueError`` names a bad one."""
    config: _ReadOnly[SuperTwistingConfig] = ...
    """A copy of the configuration the controller was built from."""
    integral: _ReadOnly[_Array] = ...
    """The integral term v (6,), in units of s per second."""
