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

import os
from collections.abc import Callable, Iterable
from typing import (
    Any,
    ClassVar,
    Literal,
    SupportsFloat,
    SupportsIndex,
    SupportsInt,
    TypedDict,
    final,
    overload,
    type_check_only,
)

import numpy
import numpy.typing
from typing_extensions import Self

_Array = numpy.typing.NDArray[numpy.float64]
_ArrayLike = numpy.typing.ArrayLike
_CoriolisForm = Literal["velocity_independent", "kirchhoff"]
_Modification = Literal["none", "sigma", "e_modification", "projection"]
_Saturation = Literal["scale", "clip"]

__version__: str
THETA_NAMES: tuple[str, ...]
"""Names of the 24 columns of :func:`regressor` (the entries of theta), e.g. ``'m'``, ``'X_u|u|'``."""

@type_check_only
class _Enum:
    """What every enum of the core has: an integer value and a name."""

    def __init__(self, value: SupportsInt | SupportsIndex) -> None:
        """The member with this integer value."""
    def __eq__(self, other: object) -> bool: ...
    def __ne__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...
    def __index__(self) -> int: ...
    def __int__(self) -> int: ...
    def __getstate__(self) -> int: ...
    def __setstate__(self, state: SupportsInt | SupportsIndex) -> None: ...
    @property
    def name(self) -> str:
        """The member's name."""
    @property
    def value(self) -> int:
        """The member's integer value."""

@type_check_only
class _Fields:
    """What every configuration struct of the core has: a keyword constructor
    (an unknown keyword is a TypeError), copy and pickle."""

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword (an unknown one is a TypeError)."""
    def __copy__(self) -> Self: ...
    def __deepcopy__(self, memo: dict[int, Any]) -> Self: ...
    def __getstate__(self) -> dict[str, Any]: ...
    def __setstate__(self, state: dict[str, Any]) -> None: ...

@type_check_only
class _ValidatedFields(_Fields):
    """A configuration struct with the C++ validator."""

    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""

@type_check_only
class _SlidingConfig(_ValidatedFields):
    """The configuration of a law on the sliding variable s: Lambda and K_d."""

    @property
    def lambda_(self) -> _Array:
        """Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,), > 0."""
    @lambda_.setter
    def lambda_(self, value: _ArrayLike) -> None: ...
    @property
    def kd(self) -> _Array:
        """K_d, diagonal (6,), >= 0."""
    @kd.setter
    def kd(self, value: _ArrayLike) -> None: ...

@type_check_only
class _SensorConfig(_Fields):
    """A sensor's configuration: its rate and latency."""

    @property
    def rate(self) -> float:
        """[Hz], > 0."""
    @rate.setter
    def rate(self, value: SupportsFloat) -> None: ...
    @property
    def latency(self) -> float:
        """[s], >= 0."""
    @latency.setter
    def latency(self, value: SupportsFloat) -> None: ...

@final
class Status(_Enum):
    """Result of a real-time step; ``ok`` is 0."""

    ok: ClassVar[Status]
    """The step succeeded."""
    near_singularity: ClassVar[Status]
    """Pitch at or near +-90 deg, where the Euler-angle transform is singular."""
    non_finite_input: ClassVar[Status]
    """An input held NaN or Inf."""
    invalid_argument: ClassVar[Status]
    """An input was outside what the function accepts."""
    non_finite_output: ClassVar[Status]
    """The result overflowed; safe values were written instead."""
    __members__: ClassVar[dict[str, Status]]

@type_check_only
class _VehicleParameters(TypedDict):
    """What :meth:`Vehicle.parameters` returns: ``Vehicle(**d)`` rebuilds the vehicle."""

    mass: float
    inertia: _Array
    centre_of_gravity: _Array
    centre_of_buoyancy: _Array
    weight: float
    buoyancy: float
    added_mass: _Array
    linear_damping: _Array
    quadratic_damping: _Array
    coriolis_form: _CoriolisForm

class Vehicle:
    """A 6-DOF vehicle in Fossen's form, ``M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau``.

    Build one with ``Vehicle.nerov()``, ``Vehicle.preset(name)``,
    ``Vehicle.from_file(path)`` or ``Vehicle(mass=..., ...)``. Parameters are
    validated: a bad one raises ``ValueError`` naming the field.
    """

    def __init__(
        self,
        *,
        mass: SupportsFloat,
        inertia: _ArrayLike,
        weight: SupportsFloat,
        buoyancy: SupportsFloat,
        added_mass: _ArrayLike,
        linear_damping: _ArrayLike,
        quadratic_damping: _ArrayLike,
        centre_of_gravity: _ArrayLike | None = None,
        centre_of_buoyancy: _ArrayLike | None = None,
        coriolis_form: _CoriolisForm = "velocity_independent",
    ) -> None:
        """Builds a vehicle from its parameters (SI units, body axes with z down).

        mass [kg] > 0; inertia (3, 3) about the body origin, or its diagonal
        (3,), symmetric; weight W and buoyancy B [N] >= 0; added_mass M_A
        (6, 6) or its diagonal (6,), positive (M_A = -diag(X_udot, ...)),
        symmetric; linear_damping and quadratic_damping (6,) >= 0, with
        D(nu) = diag(lin + quad * |nu|); centre_of_gravity r_g and
        centre_of_buoyancy r_b (3,) [m], default zero; coriolis_form
        ``'velocity_independent'`` (the paper's eq. 39, default) or
        ``'kirchhoff'``. M = M_RB + M_A must be positive definite.
        """
    @staticmethod
    def nerov() -> Vehicle:
        """NEROV, the paper's vehicle, with the numbers of its section 5."""
    @staticmethod
    def from_file(path: str | os.PathLike[str]) -> Vehicle:
        """Loads a vehicle TOML file (format: ``neurov.vehicle_file``).

        A missing, misspelt or wrongly typed field raises
        ``neurov.VehicleFileError`` (a ``ValueError``) naming the file and the field.
        """
    @staticmethod
    def preset(name: str) -> Vehicle:
        """A vehicle shipped with neurov by name: ``'nerov'`` or ``'bluerov2_heavy'``.

        ``neurov.vehicle_file.preset_names()`` lists them; an unknown name
        raises ``ValueError``.
        """
    def parameters(self) -> _VehicleParameters:
        """The parameters as a dict of keyword arguments.

        ``Vehicle(**v.parameters())`` rebuilds the vehicle; ``inertia`` is
        (3, 3) and ``added_mass`` (6, 6).
        """
    @property
    def mass(self) -> float:
        """m [kg]."""
    @property
    def inertia(self) -> _Array:
        """I_o about the body origin, shape (3, 3) [kg m^2]."""
    @property
    def centre_of_gravity(self) -> _Array:
        """r_g, shape (3,) [m], body axes."""
    @property
    def centre_of_buoyancy(self) -> _Array:
        """r_b, shape (3,) [m], body axes (z down)."""
    @property
    def weight(self) -> float:
        """W [N]."""
    @property
    def buoyancy(self) -> float:
        """B [N]."""
    @property
    def added_mass(self) -> _Array:
        """M_A, shape (6, 6)."""
    @property
    def linear_damping(self) -> _Array:
        """D_L, shape (6,)."""
    @property
    def quadratic_damping(self) -> _Array:
        """D_Q, shape (6,)."""
    @property
    def coriolis_form(self) -> _CoriolisForm:
        """``'velocity_independent'`` (the paper's eq. 39) or ``'kirchhoff'``."""
    def mass_matrix(self) -> _Array:
        """M = M_RB + M_A, shape (6, 6), symmetric positive definite."""
    def coriolis(self, nu: _ArrayLike) -> _Array:
        """C(nu) = C_RB(nu) + C_A(nu), skew-symmetric, shape (6, 6); nu is (6,)."""
    def damping(self, nu: _ArrayLike) -> _Array:
        """D(nu) = diag(D_L + D_Q |nu|), shape (6, 6); nu is (6,)."""
    def restoring(self, eta: _ArrayLike) -> _Array:
        """g(eta): gravity and buoyancy forces and moments, shape (6,); eta is (6,)."""
    def acceleration(
        self,
        eta: _ArrayLike,
        nu: _ArrayLike,
        tau: _ArrayLike,
        current: _ArrayLike | None = None,
    ) -> _Array:
        """nu_dot = M^-1 (tau - C(nu) nu - D(nu) nu - g(eta)), shape (6,).

        eta, nu and tau are (6,). With ``current`` (3,), a constant NED current
        velocity [m/s], the hydrodynamic terms use the relative velocity
        nu - nu_c. Raises ``ValueError`` if the result overflows.
        """

def rotation(phi: SupportsFloat, theta: SupportsFloat, psi: SupportsFloat) -> _Array:
    """R = Rz(psi) Ry(theta) Rx(phi) (ZYX Euler angles, body to NED), shape (3, 3)."""

def singularity_threshold() -> float:
    """|cos(theta)| below which the Euler-angle transform counts as singular (sqrt of machine epsilon)."""

def is_near_singularity(eta: _ArrayLike) -> bool:
    """True if the pose eta (6,) has its pitch at the Euler-angle singularity."""

def jacobian(eta: _ArrayLike) -> _Array:
    """J(eta) = blockdiag(R, T), shape (6, 6), so that eta_dot = J(eta) @ nu.

    Raises ``ValueError`` naming ``eta`` at the pitch singularity (cos(theta) = 0).
    """

def jacobian_inverse(eta: _ArrayLike) -> _Array:
    """J(eta)^-1 = blockdiag(R^T, T^-1) in closed form, shape (6, 6).

    T^-1 has no division, so this is defined (but rank deficient) at the singularity.
    """

def jacobian_dot(eta: _ArrayLike, nu: _ArrayLike) -> _Array:
    """Time derivative of J along the motion eta_dot = J(eta) nu, shape (6, 6).

    Closed form. Raises ``ValueError`` naming ``eta`` at the pitch singularity.
    """

def rk4_step(
    vehicle: Vehicle,
    eta: _ArrayLike,
    nu: _ArrayLike,
    tau: _ArrayLike,
    dt: SupportsFloat,
    current: _ArrayLike | None = None,
) -> tuple[_Array, _Array]:
    """One fixed-step RK4 step of the 12-state plant with tau held over the step.

    Returns the new ``(eta, nu)``; the inputs are not modified. ``dt`` must be
    finite and > 0; ``current`` (3,) is a constant NED current velocity [m/s].
    Raises ``ValueError`` at the pitch singularity or on overflow.
    """

def plant_derivative(
    vehicle: Vehicle,
    eta: _ArrayLike,
    nu: _ArrayLike,
    tau: _ArrayLike,
    current: _ArrayLike | None = None,
) -> _Array:
    """The 12-state plant's right-hand side ``(eta_dot, nu_dot)``, shape (12,).

    ``eta_dot = J(eta) nu`` and ``nu_dot`` as in :meth:`Vehicle.acceleration`:
    the function :func:`rk4_step` integrates. ``current`` (3,) is a constant
    NED current velocity [m/s]. Raises ``ValueError`` at the pitch singularity.
    """

def plant_jacobians(
    vehicle: Vehicle,
    eta: _ArrayLike,
    nu: _ArrayLike,
    tau: _ArrayLike | None = None,
    current: _ArrayLike | None = None,
) -> tuple[_Array, _Array]:
    """Analytic Jacobians ``(A, B)`` of :func:`plant_derivative` at ``(eta, nu)``.

    ``A = d(eta_dot, nu_dot)/d(eta, nu)``, shape (12, 12), and
    ``B = d(eta_dot, nu_dot)/d tau``, shape (12, 6), in closed form (C++). The
    plant is affine in tau, so ``tau`` (default zero) changes neither.
    Raises ``ValueError`` at the pitch singularity.
    """

# --------------------------------------------------------------------------
# Reference model, tracking error, regressor

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
    @property
    def eta_d(self) -> _Array:
        """Current desired pose (6,)."""
    @property
    def nu_d(self) -> _Array:
        """Current desired body velocity (6,)."""
    @property
    def lambda_d(self) -> _Array:
        """Damping diagonal (6,)."""
    @property
    def omega(self) -> _Array:
        """Stiffness diagonal (6,)."""
    @property
    def pitch_limited(self) -> bool:
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

def regressor(nu_r_dot: _ArrayLike, nu_r: _ArrayLike, nu: _ArrayLike, eta: _ArrayLike) -> _Array:
    """Regressor Phi (6, 24) with ``Phi @ theta = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta)``
    for NEROV's model structure; :data:`THETA_NAMES` names the columns."""

def regressor_parameters(vehicle: Vehicle) -> _Array:
    """The true theta (24,) of a vehicle whose structure the regressor covers.

    That is r_g = 0, diagonal inertia and added mass, r_b on the z axis;
    ``ValueError`` otherwise.
    """

# --------------------------------------------------------------------------
# RBF network and controllers

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
        """centres: (N, n_in), one centre per row; width: sigma for every centre, or (N,)
        per centre, > 0; input_offset and input_scale: (n_in,) input normalisation,
        default identity (the paper's choice). Weights start at zero."""
    def basis(self, x: _ArrayLike) -> _Array:
        """Basis values g(x) for an input x (n_in,), shape (N,)."""
    def output(self, x: _ArrayLike) -> _Array:
        """Network output W g(x) for an input x (n_in,), shape (6,)."""
    @property
    def weights(self) -> _Array:
        """Output weights W, shape (6, N); assignable."""
    @weights.setter
    def weights(self, value: _ArrayLike) -> None: ...
    @property
    def centres(self) -> _Array:
        """Centres, shape (N, n_in)."""
    @property
    def widths(self) -> _Array:
        """Widths sigma_j, shape (N,)."""
    @property
    def input_offset(self) -> _Array:
        """Input offset, shape (n_in,)."""
    @property
    def input_scale(self) -> _Array:
        """Input scale, shape (n_in,)."""
    @property
    def n_inputs(self) -> int:
        """Number of inputs n_in."""
    @property
    def n_centres(self) -> int:
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
    """Configuration of :class:`PDController`.

    Every field has the C++ default; ``PDConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def kp(self) -> _Array:
        """K_p, diagonal (6,), >= 0."""
    @kp.setter
    def kp(self, value: _ArrayLike) -> None: ...
    @property
    def kd(self) -> _Array:
        """K_d, diagonal (6,), >= 0."""
    @kd.setter
    def kd(self, value: _ArrayLike) -> None: ...

class PIDConfig(_ValidatedFields):
    """Configuration of :class:`PIDController`.

    Every field has the C++ default; ``PIDConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def kp(self) -> _Array:
        """K_p, diagonal (6,), >= 0."""
    @kp.setter
    def kp(self, value: _ArrayLike) -> None: ...
    @property
    def ki(self) -> _Array:
        """K_i, diagonal (6,), >= 0."""
    @ki.setter
    def ki(self, value: _ArrayLike) -> None: ...
    @property
    def kd(self) -> _Array:
        """K_d, diagonal (6,), >= 0."""
    @kd.setter
    def kd(self, value: _ArrayLike) -> None: ...
    @property
    def integral_limit(self) -> _Array:
        """Largest |K_i z| per DOF (6,), > 0 [N, N m]."""
    @integral_limit.setter
    def integral_limit(self, value: _ArrayLike) -> None: ...
    @property
    def dt(self) -> float:
        """Control period [s], > 0."""
    @dt.setter
    def dt(self, value: SupportsFloat) -> None: ...

class SlidingModeConfig(_SlidingConfig):
    """Configuration of :class:`SlidingModeController`.

    Every field has the C++ default; ``SlidingModeConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def k(self) -> _Array:
        """Switching gain K (6,), >= 0 [N, N m]."""
    @k.setter
    def k(self, value: _ArrayLike) -> None: ...
    @property
    def phi(self) -> _Array:
        """Boundary-layer width (6,), > 0, in units of s."""
    @phi.setter
    def phi(self, value: _ArrayLike) -> None: ...
    @property
    def theta(self) -> _Array:
        """The nominal model's theta (24,), e.g. ``regressor_parameters(vehicle)``."""
    @theta.setter
    def theta(self, value: _ArrayLike) -> None: ...

class LinearAdaptiveConfig(_SlidingConfig):
    """Configuration of :class:`LinearAdaptiveController`.

    Every field has the C++ default; ``LinearAdaptiveConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def gamma(self) -> _Array:
        """Diagonal of Gamma (24,), >= 0 (0 freezes that parameter); a number sets every entry."""
    @gamma.setter
    def gamma(self, value: SupportsFloat | _ArrayLike) -> None: ...
    @property
    def dt(self) -> float:
        """Control period [s], > 0."""
    @dt.setter
    def dt(self, value: SupportsFloat) -> None: ...
    @property
    def theta0(self) -> _Array:
        """theta_hat(0) (24,): zero, or a nominal guess such as ``regressor_parameters(vehicle)``."""
    @theta0.setter
    def theta0(self, value: _ArrayLike) -> None: ...

class NNAdaptiveConfig(_SlidingConfig):
    """Configuration of :class:`NNAdaptiveController`.

    Every field has the C++ default; ``NNAdaptiveConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def kd(self) -> _Array:
        """K_d, diagonal (6,), >= 0 (0 leaves the network alone)."""
    @kd.setter
    def kd(self, value: _ArrayLike) -> None: ...
    @property
    def gamma(self) -> float:
        """Gamma_w = gamma I, >= 0 (the paper: 0.3)."""
    @gamma.setter
    def gamma(self, value: SupportsFloat) -> None: ...
    @property
    def dt(self) -> float:
        """Control period [s], > 0 (the paper: 0.2)."""
    @dt.setter
    def dt(self, value: SupportsFloat) -> None: ...
    @property
    def modification(self) -> RobustModification:
        """The robust modification: a RobustModification or its name."""
    @modification.setter
    def modification(self, value: RobustModification | _Modification) -> None: ...
    @property
    def sigma_m(self) -> float:
        """Leakage of the sigma-modification (> 0 when used)."""
    @sigma_m.setter
    def sigma_m(self, value: SupportsFloat) -> None: ...
    @property
    def kappa(self) -> float:
        """Gain of the e-modification (> 0 when used)."""
    @kappa.setter
    def kappa(self, value: SupportsFloat) -> None: ...
    @property
    def w_max(self) -> float:
        """Frobenius bound of the projection (> 0 when used)."""
    @w_max.setter
    def w_max(self, value: SupportsFloat) -> None: ...
    @property
    def dead_zone(self) -> float:
        """No adaptation while ||s|| < dead_zone (0 disables), >= 0."""
    @dead_zone.setter
    def dead_zone(self, value: SupportsFloat) -> None: ...

class ComputedTorqueConfig(_SlidingConfig):
    """Configuration of :class:`ComputedTorqueController`.

    Every field has the C++ default; ``ComputedTorqueConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    @property
    def vehicle(self) -> Vehicle | None:
        """The nominal model, a Vehicle (None until set)."""
    @vehicle.setter
    def vehicle(self, value: Vehicle) -> None: ...

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
    @property
    def s(self) -> _Array:
        """Filtered tracking error s of the last step, shape (6,)."""
    @property
    def tracking(self) -> _Tracking:
        """Tracking error and virtual reference of the last step (a dict of (6,) arrays)."""

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
    @property
    def config(self) -> NNAdaptiveConfig:
        """A copy of the configuration the controller was built from."""
    @property
    def weights(self) -> _Array:
        """Current weights W, shape (6, N); assignable (warm start)."""
    @weights.setter
    def weights(self, value: _ArrayLike) -> None: ...
    @property
    def weight_norm(self) -> float:
        """||W||_F."""
    @property
    def network_output(self) -> _Array:
        """W g(x) of the last step (before its update), shape (6,)."""
    @property
    def basis(self) -> _Array:
        """g(x) of the last step, shape (N,)."""
    @property
    def adapted(self) -> bool:
        """Whether the last step moved the weights (False in the dead zone)."""
    @property
    def n_centres(self) -> int:
        """Number of centres N."""
    @property
    def centres(self) -> _Array:
        """Centres, shape (N, 24)."""
    @property
    def widths(self) -> _Array:
        """Widths sigma_j, shape (N,)."""
    @property
    def input_offset(self) -> _Array:
        """Input offset of the network's normalisation, shape (24,)."""
    @property
    def input_scale(self) -> _Array:
        """Input scale of the network's normalisation, shape (24,)."""
    def save(self, path: str | os.PathLike[str]) -> None:
        """Writes W and its network to a .npz file (format: neurov.weights)."""
    def load(self, path: str | os.PathLike[str]) -> None:
        """Sets W from a file written by save(); WeightsFileError names a misfit."""
    @property
    def modification(self) -> _Modification:
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
    @property
    def config(self) -> LinearAdaptiveConfig:
        """A copy of the configuration the controller was built from."""
    @property
    def theta(self) -> _Array:
        """Current estimate theta_hat (24,); assignable."""
    @theta.setter
    def theta(self, value: _ArrayLike) -> None: ...
    @property
    def model_output(self) -> _Array:
        """Phi theta_hat of the last step, shape (6,)."""

class PDController(_Controller):
    """PD baseline in the earth frame: ``tau = -J^T (K_p eta_tilde + K_d eta_tilde_dot)``."""

    @overload
    def __init__(self, config: PDConfig) -> None:
        """Builds the controller from its configuration object; ``ValueError`` names a bad field."""
    @overload
    def __init__(self, kp: _ArrayLike, kd: _ArrayLike) -> None:
        """kp, kd: diagonal gains (6,), >= 0."""
    @property
    def config(self) -> PDConfig:
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
    @property
    def config(self) -> PIDConfig:
        """A copy of the configuration the controller was built from."""
    @property
    def integral(self) -> _Array:
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
    @property
    def config(self) -> SlidingModeConfig:
        """A copy of the configuration the controller was built from."""
    @property
    def model_output(self) -> _Array:
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
    @property
    def config(self) -> ComputedTorqueConfig:
        """A copy of the configuration the controller was built from."""
    @property
    def model_output(self) -> _Array:
        """M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta) of the last step, shape (6,)."""

# --------------------------------------------------------------------------
# Closed-loop simulation and thrust allocation

# --------------------------------------------------------------------------
# The configuration of a run (neurov/sim/config.hpp), field by field: Python
# holds the C++ object. Fixed-size vectors are writable views into it;
# dynamic arrays (command times and poses, thruster arrays) are read-only
# copies and lists of structs tuples of copies: assign them whole.

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

class Saturation(_Enum):
    """How thrusts beyond their limits are brought back."""

    scale: ClassVar[Saturation]
    """Every thruster scaled by one factor: the wrench keeps its direction."""
    clip: ClassVar[Saturation]
    """Each thruster clipped to its limits: the wrench turns."""
    __members__: ClassVar[dict[str, Saturation]]

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

    @property
    def latency(self) -> float:
        """[s], >= 0 (acoustic travel and processing)."""
    @latency.setter
    def latency(self, value: SupportsFloat) -> None: ...
    @property
    def noise(self) -> float:
        """Standard deviation per axis [m], >= 0."""
    @noise.setter
    def noise(self, value: SupportsFloat) -> None: ...
    @property
    def bias(self) -> _Array:
        """NED [m] (3,)."""
    @bias.setter
    def bias(self, value: _ArrayLike) -> None: ...

@final
class DvlConfig(_SensorConfig):
    """A Doppler velocity log: body velocity over ground."""

    @property
    def noise(self) -> float:
        """Standard deviation per axis [m/s], >= 0."""
    @noise.setter
    def noise(self, value: SupportsFloat) -> None: ...
    @property
    def dropout_rate(self) -> float:
        """Probability that a sample has no bottom lock, in [0, 1)."""
    @dropout_rate.setter
    def dropout_rate(self, value: SupportsFloat) -> None: ...
    @property
    def bias(self) -> _Array:
        """[m/s] (3,)."""
    @bias.setter
    def bias(self, value: _ArrayLike) -> None: ...

@final
class DepthConfig(_SensorConfig):
    """A pressure depth sensor: z, down positive."""

    @property
    def noise(self) -> float:
        """Standard deviation [m], >= 0."""
    @noise.setter
    def noise(self, value: SupportsFloat) -> None: ...
    @property
    def bias(self) -> float:
        """[m]."""
    @bias.setter
    def bias(self, value: SupportsFloat) -> None: ...

@final
class ImuConfig(_SensorConfig):
    """An AHRS/IMU: attitude and gyro rates, the gyro's bias walking."""

    @property
    def attitude_noise(self) -> float:
        """Standard deviation of the angles [rad], >= 0."""
    @attitude_noise.setter
    def attitude_noise(self, value: SupportsFloat) -> None: ...
    @property
    def gyro_noise(self) -> float:
        """Standard deviation of the rates [rad/s], >= 0."""
    @gyro_noise.setter
    def gyro_noise(self, value: SupportsFloat) -> None: ...
    @property
    def gyro_bias_walk(self) -> float:
        """Bias random walk [rad/s/sqrt(s)], >= 0."""
    @gyro_bias_walk.setter
    def gyro_bias_walk(self, value: SupportsFloat) -> None: ...
    @property
    def gyro_bias(self) -> _Array:
        """Initial gyro bias [rad/s] (3,)."""
    @gyro_bias.setter
    def gyro_bias(self, value: _ArrayLike) -> None: ...

@final
class SensorsConfig(_Fields):
    """The sensors of a run, each optional; none configured: ideal sensing."""

    @property
    def usbl(self) -> UsblConfig | None:
        """A UsblConfig, or None."""
    @usbl.setter
    def usbl(self, value: UsblConfig | None) -> None: ...
    @property
    def dvl(self) -> DvlConfig | None:
        """A DvlConfig, or None."""
    @dvl.setter
    def dvl(self, value: DvlConfig | None) -> None: ...
    @property
    def depth(self) -> DepthConfig | None:
        """A DepthConfig, or None."""
    @depth.setter
    def depth(self, value: DepthConfig | None) -> None: ...
    @property
    def imu(self) -> ImuConfig | None:
        """An ImuConfig, or None."""
    @imu.setter
    def imu(self, value: ImuConfig | None) -> None: ...
    def any(self) -> bool:
        """Some sensor is configured."""

@final
class EstimatorConfig(_Fields):
    """What the controller is given from the sensors; the EKF's measurement noises are the sensors' own."""

    @property
    def type(self) -> EstimatorType:
        """An EstimatorType."""
    @type.setter
    def type(self, value: EstimatorType) -> None: ...
    @property
    def linear_acceleration_noise(self) -> float:
        """sqrt of the PSD of the velocities' random walk [m/s^2/sqrt(Hz)], >= 0."""
    @linear_acceleration_noise.setter
    def linear_acceleration_noise(self, value: SupportsFloat) -> None: ...
    @property
    def angular_acceleration_noise(self) -> float:
        """sqrt of the PSD of the rates' random walk [rad/s^2/sqrt(Hz)], >= 0."""
    @angular_acceleration_noise.setter
    def angular_acceleration_noise(self, value: SupportsFloat) -> None: ...
    @property
    def initial_std(self) -> _Array:
        """Standard deviations of the initial estimate (15,): position, angles, body velocity, rates, gyro bias."""
    @initial_std.setter
    def initial_std(self, value: _ArrayLike) -> None: ...

@final
class SinusoidalDisturbance(_Fields):
    """A force or moment in one body DOF: amplitude * sin(2 pi frequency (t - start) + phase) for t >= start."""

    @property
    def dof(self) -> int:
        """0..5: surge, sway, heave, roll, pitch, yaw."""
    @dof.setter
    def dof(self, value: SupportsIndex) -> None: ...
    @property
    def amplitude(self) -> float:
        """[N] or [N m]."""
    @amplitude.setter
    def amplitude(self, value: SupportsFloat) -> None: ...
    @property
    def frequency(self) -> float:
        """[Hz]."""
    @frequency.setter
    def frequency(self, value: SupportsFloat) -> None: ...
    @property
    def phase(self) -> float:
        """[rad]."""
    @phase.setter
    def phase(self, value: SupportsFloat) -> None: ...
    @property
    def start(self) -> float:
        """[s]."""
    @start.setter
    def start(self, value: SupportsFloat) -> None: ...

@final
class ThrusterFailure(_Fields):
    """Thruster ``index`` works at ``efficiency`` (0: failed) from ``time`` on."""

    @property
    def index(self) -> int:
        """The thruster (a column of the thruster matrix)."""
    @index.setter
    def index(self, value: SupportsIndex) -> None: ...
    @property
    def efficiency(self) -> float:
        """In [0, 1]."""
    @efficiency.setter
    def efficiency(self, value: SupportsFloat) -> None: ...
    @property
    def time(self) -> float:
        """[s]."""
    @time.setter
    def time(self, value: SupportsFloat) -> None: ...

@final
class SensorFault(_Fields):
    """A sensor fault over [start, end): the measurement of eta and/or nu freezes, drops out (NaN) or gets extra white noise."""

    @property
    def kind(self) -> SensorFaultKind:
        """What the fault does."""
    @kind.setter
    def kind(self, value: SensorFaultKind) -> None: ...
    @property
    def start(self) -> float:
        """[s]."""
    @start.setter
    def start(self, value: SupportsFloat) -> None: ...
    @property
    def end(self) -> float:
        """[s], >= start."""
    @end.setter
    def end(self, value: SupportsFloat) -> None: ...
    @property
    def eta(self) -> bool:
        """Affects the pose measurement."""
    @eta.setter
    def eta(self, value: bool) -> None: ...
    @property
    def nu(self) -> bool:
        """Affects the velocity measurement."""
    @nu.setter
    def nu(self, value: bool) -> None: ...
    @property
    def noise_eta(self) -> _Array:
        """Standard deviations (6,); noise_burst only."""
    @noise_eta.setter
    def noise_eta(self, value: _ArrayLike) -> None: ...
    @property
    def noise_nu(self) -> _Array:
        """Standard deviations (6,); noise_burst only."""
    @noise_nu.setter
    def noise_nu(self, value: _ArrayLike) -> None: ...

@final
class GaussMarkovCurrentConfig(_Fields):
    """A current whose speed, direction and vertical angle wander about their means as first-order Gauss-Markov processes (Fossen 2011, 8.3)."""

    @property
    def speed(self) -> float:
        """Mean speed [m/s], within [speed_min, speed_max]."""
    @speed.setter
    def speed(self, value: SupportsFloat) -> None: ...
    @property
    def speed_std(self) -> float:
        """Stationary standard deviation [m/s], >= 0."""
    @speed_std.setter
    def speed_std(self, value: SupportsFloat) -> None: ...
    @property
    def time_constant(self) -> float:
        """Of all three processes [s], > 0."""
    @time_constant.setter
    def time_constant(self, value: SupportsFloat) -> None: ...
    @property
    def speed_min(self) -> float:
        """Lower bound of the speed given out [m/s], >= 0."""
    @speed_min.setter
    def speed_min(self, value: SupportsFloat) -> None: ...
    @property
    def speed_max(self) -> float:
        """Upper bound of the speed given out [m/s]."""
    @speed_max.setter
    def speed_max(self, value: SupportsFloat) -> None: ...
    @property
    def direction(self) -> float:
        """Mean direction the current flows toward [deg from north]."""
    @direction.setter
    def direction(self, value: SupportsFloat) -> None: ...
    @property
    def direction_std(self) -> float:
        """[deg], >= 0."""
    @direction_std.setter
    def direction_std(self, value: SupportsFloat) -> None: ...
    @property
    def vertical_angle(self) -> float:
        """Mean angle below the horizontal plane [deg], positive flowing down."""
    @vertical_angle.setter
    def vertical_angle(self, value: SupportsFloat) -> None: ...
    @property
    def vertical_angle_std(self) -> float:
        """[deg], >= 0."""
    @vertical_angle_std.setter
    def vertical_angle_std(self, value: SupportsFloat) -> None: ...

@final
class WaveConfig(_Fields):
    """Linear deep-water waves realised from a spectrum as a sum of seeded components."""

    @property
    def spectrum(self) -> WaveSpectrum:
        """A WaveSpectrum."""
    @spectrum.setter
    def spectrum(self, value: WaveSpectrum) -> None: ...
    @property
    def hs(self) -> float:
        """Significant wave height [m], > 0."""
    @hs.setter
    def hs(self, value: SupportsFloat) -> None: ...
    @property
    def tp(self) -> float:
        """Peak period [s], > 0."""
    @tp.setter
    def tp(self, value: SupportsFloat) -> None: ...
    @property
    def gamma(self) -> float:
        """JONSWAP peak enhancement, >= 1."""
    @gamma.setter
    def gamma(self, value: SupportsFloat) -> None: ...
    @property
    def direction(self) -> float:
        """Direction the waves travel toward [deg from north]."""
    @direction.setter
    def direction(self, value: SupportsFloat) -> None: ...
    @property
    def spreading(self) -> float:
        """n of the cos^n directional spreading; 0: long-crested."""
    @spreading.setter
    def spreading(self, value: SupportsFloat) -> None: ...
    @property
    def components(self) -> int:
        """Number of components, 1 to 512."""
    @components.setter
    def components(self, value: SupportsIndex) -> None: ...
    def spectral_density(self, omega: _ArrayLike) -> _Array:
        """S(omega) [m^2 s/rad] at the circular frequencies ``omega`` [rad/s] (0 for omega <= 0); JONSWAP normalised so that its m0 is hs^2/16."""

@final
class PayloadEvent(_Fields):
    """A change of the vehicle at ``time`` that the controller is not told about: mass, buoyancy, damping and added mass."""

    @property
    def time(self) -> float:
        """When it happens [s], >= 0."""
    @time.setter
    def time(self, value: SupportsFloat) -> None: ...
    @property
    def mass(self) -> float:
        """Mass added [kg] (negative: dropped); weight mass * 9.81."""
    @mass.setter
    def mass(self, value: SupportsFloat) -> None: ...
    @property
    def mass_position(self) -> _Array | None:
        """Where the mass sits, body axes [m] (3,); None: the centre of gravity."""
    @mass_position.setter
    def mass_position(self, value: _ArrayLike | None) -> None: ...
    @property
    def buoyancy(self) -> float:
        """Buoyancy added [N] (negative: lost)."""
    @buoyancy.setter
    def buoyancy(self, value: SupportsFloat) -> None: ...
    @property
    def buoyancy_position(self) -> _Array | None:
        """Where it acts, body axes [m] (3,); None: the centre of buoyancy."""
    @buoyancy_position.setter
    def buoyancy_position(self, value: _ArrayLike | None) -> None: ...
    @property
    def damping_scale(self) -> _Array:
        """Factors on the linear and quadratic damping per DOF (6,)."""
    @damping_scale.setter
    def damping_scale(self, value: _ArrayLike) -> None: ...
    @property
    def added_mass_scale(self) -> float:
        """Factor on the added-mass matrix."""
    @added_mass_scale.setter
    def added_mass_scale(self, value: SupportsFloat) -> None: ...

@final
class CurrentStep(_Fields):
    """From ``time`` on, the mean current is ``velocity``."""

    @property
    def time(self) -> float:
        """[s]."""
    @time.setter
    def time(self, value: SupportsFloat) -> None: ...
    @property
    def velocity(self) -> _Array:
        """NED [m/s] (3,)."""
    @velocity.setter
    def velocity(self, value: _ArrayLike) -> None: ...

@final
class Command(_Fields):
    """Commanded poses at increasing times; held before the first and after the last; between them linear or held."""

    @property
    def times(self) -> _Array:
        """(K,) strictly increasing [s] (a read-only copy)."""
    @times.setter
    def times(self, value: _ArrayLike) -> None: ...
    @property
    def poses(self) -> _Array:
        """(K, 6) poses eta (a read-only copy)."""
    @poses.setter
    def poses(self, value: _ArrayLike) -> None: ...
    @property
    def linear(self) -> bool:
        """Linear between the poses; False: piecewise constant."""
    @linear.setter
    def linear(self, value: bool) -> None: ...
    def at(self, t: SupportsFloat) -> _Array:
        """The commanded pose at time t."""

@final
class ThrusterCurveConfig(_ValidatedFields):
    """One thruster from command to thrust: a table (linearly interpolated), a dead band around the neutral command, supply-voltage scaling, a first-order lag and a slew-rate limit."""

    @property
    def table(self) -> _Array:
        """(n, 2) rows of (command, thrust [N] at reference_voltage), commands strictly increasing, 2 <= n <= 256 (a read-only copy)."""
    @table.setter
    def table(self, value: _ArrayLike) -> None: ...
    @property
    def neutral(self) -> float:
        """The command of zero thrust, inside the table."""
    @neutral.setter
    def neutral(self, value: SupportsFloat) -> None: ...
    @property
    def dead_band(self) -> float:
        """Half-width of the dead band around neutral (command units), >= 0."""
    @dead_band.setter
    def dead_band(self, value: SupportsFloat) -> None: ...
    @property
    def reference_voltage(self) -> float:
        """Supply voltage [V] at which the table was measured, > 0."""
    @reference_voltage.setter
    def reference_voltage(self, value: SupportsFloat) -> None: ...
    @property
    def voltage_exponent(self) -> float:
        """Thrust ~ voltage^exponent at a fixed command, >= 0 (2: an assumption)."""
    @voltage_exponent.setter
    def voltage_exponent(self, value: SupportsFloat) -> None: ...
    @property
    def time_constant(self) -> float:
        """First-order lag of the thrust [s]; 0: none."""
    @time_constant.setter
    def time_constant(self, value: SupportsFloat) -> None: ...
    @property
    def slew_rate(self) -> float:
        """Largest rate of change of the thrust [N/s]; 0: none."""
    @slew_rate.setter
    def slew_rate(self, value: SupportsFloat) -> None: ...
    def static_thrust(self, command: SupportsFloat, voltage: SupportsFloat) -> float:
        """Steady thrust [N] at a command and supply voltage (the C++ curve)."""
    def command_for(self, thrust: SupportsFloat, voltage: SupportsFloat) -> float:
        """The command whose steady thrust is `thrust` at `voltage` (the curve's inverse), clamped to the table."""

@final
class ThrusterConfig(_ValidatedFields):
    """n thrusters: tau = B u, allocated by the weighted pseudo-inverse, saturated, with a first-order lag."""

    @property
    def matrix(self) -> _Array:
        """B (6, n): the wrench of each thruster per unit thrust (a read-only copy)."""
    @matrix.setter
    def matrix(self, value: _ArrayLike) -> None: ...
    @property
    def min_thrust(self) -> _Array:
        """Lower limits [N] (n,), <= 0 (a read-only copy)."""
    @min_thrust.setter
    def min_thrust(self, value: _ArrayLike) -> None: ...
    @property
    def max_thrust(self) -> _Array:
        """Upper limits [N] (n,), > min_thrust (a read-only copy)."""
    @max_thrust.setter
    def max_thrust(self, value: _ArrayLike) -> None: ...
    @property
    def weights(self) -> _Array:
        """Allocation weights (n,), > 0; empty means all 1 (a read-only copy)."""
    @weights.setter
    def weights(self, value: _ArrayLike) -> None: ...
    @property
    def saturation(self) -> Saturation:
        """How thrusts beyond their limits are brought back."""
    @saturation.setter
    def saturation(self, value: Saturation) -> None: ...
    @property
    def time_constant(self) -> float:
        """First-order lag [s] of linear thrusters; 0 means none (0 with curves)."""
    @time_constant.setter
    def time_constant(self, value: SupportsFloat) -> None: ...
    @property
    def curves(self) -> tuple[ThrusterCurveConfig, ...]:
        """One command-to-thrust curve per thruster, or empty: linear thrusters (a tuple of copies; assign a list)."""
    @curves.setter
    def curves(self, value: Iterable[ThrusterCurveConfig]) -> None: ...
    @property
    def supply_voltage(self) -> float:
        """Supply voltage [V] of the curves, > 0 with curves."""
    @supply_voltage.setter
    def supply_voltage(self, value: SupportsFloat) -> None: ...

@final
class SimulationConfig(_ValidatedFields):
    """Everything of a closed-loop run but the vehicle and the controller.

    Rows of a run are at t_k = k dt; the force is held over each control
    period and the plant integrated by RK4 at dt / substeps.
    """

    @property
    def dt(self) -> float:
        """Control period [s]."""
    @dt.setter
    def dt(self, value: SupportsFloat) -> None: ...
    @property
    def substeps(self) -> int:
        """RK4 steps per control period."""
    @substeps.setter
    def substeps(self, value: SupportsIndex) -> None: ...
    @property
    def duration(self) -> float:
        """[s]."""
    @duration.setter
    def duration(self, value: SupportsFloat) -> None: ...
    @property
    def eta0(self) -> _Array:
        """Initial pose (6,)."""
    @eta0.setter
    def eta0(self, value: _ArrayLike) -> None: ...
    @property
    def nu0(self) -> _Array:
        """Initial body velocity (6,)."""
    @nu0.setter
    def nu0(self, value: _ArrayLike) -> None: ...
    @property
    def command(self) -> Command:
        """The commanded path."""
    @command.setter
    def command(self, value: Command) -> None: ...
    @property
    def lambda_d(self) -> _Array:
        """Reference-model damping (6,)."""
    @lambda_d.setter
    def lambda_d(self, value: _ArrayLike) -> None: ...
    @property
    def omega(self) -> _Array:
        """Reference-model stiffness (6,)."""
    @omega.setter
    def omega(self, value: _ArrayLike) -> None: ...
    @property
    def disturbances(self) -> tuple[SinusoidalDisturbance, ...]:
        """Sinusoidal forces (a tuple of copies; assign a list)."""
    @disturbances.setter
    def disturbances(self, value: Iterable[SinusoidalDisturbance]) -> None: ...
    @property
    def current(self) -> _Array:
        """Mean current, NED [m/s] (3,)."""
    @current.setter
    def current(self, value: _ArrayLike) -> None: ...
    @property
    def current_amplitude(self) -> _Array:
        """Amplitude of the current's sinusoid per axis (3,)."""
    @current_amplitude.setter
    def current_amplitude(self, value: _ArrayLike) -> None: ...
    @property
    def current_period(self) -> float:
        """[s]; 0 means a constant current."""
    @current_period.setter
    def current_period(self, value: SupportsFloat) -> None: ...
    @property
    def noise_eta(self) -> _Array:
        """Standard deviations of the pose noise (6,)."""
    @noise_eta.setter
    def noise_eta(self, value: _ArrayLike) -> None: ...
    @property
    def noise_nu(self) -> _Array:
        """Standard deviations of the velocity noise (6,)."""
    @noise_nu.setter
    def noise_nu(self, value: _ArrayLike) -> None: ...
    @property
    def seed(self) -> int:
        """Seed of the measurement noise; the current's and the waves' streams are derived from it."""
    @seed.setter
    def seed(self, value: SupportsIndex) -> None: ...
    @property
    def use_thrusters(self) -> bool:
        """Allocate the force to ``thrusters``; False: the force acts directly."""
    @use_thrusters.setter
    def use_thrusters(self, value: bool) -> None: ...
    @property
    def thrusters(self) -> ThrusterConfig:
        """The thruster layout."""
    @thrusters.setter
    def thrusters(self, value: ThrusterConfig) -> None: ...
    @property
    def failures(self) -> tuple[ThrusterFailure, ...]:
        """Thruster failures (a tuple of copies; assign a list)."""
    @failures.setter
    def failures(self, value: Iterable[ThrusterFailure]) -> None: ...
    @property
    def sensor_faults(self) -> tuple[SensorFault, ...]:
        """Sensor faults (a tuple of copies; assign a list)."""
    @sensor_faults.setter
    def sensor_faults(self, value: Iterable[SensorFault]) -> None: ...
    @property
    def current_steps(self) -> tuple[CurrentStep, ...]:
        """Steps of the mean current, in increasing time (a tuple of copies; assign a list)."""
    @current_steps.setter
    def current_steps(self, value: Iterable[CurrentStep]) -> None: ...
    @property
    def refused_step_policy(self) -> RefusedStepPolicy:
        """The force applied on a refused step."""
    @refused_step_policy.setter
    def refused_step_policy(self, value: RefusedStepPolicy) -> None: ...
    @property
    def current_model(self) -> CurrentModel:
        """A CurrentModel."""
    @current_model.setter
    def current_model(self, value: CurrentModel) -> None: ...
    @property
    def gauss_markov_current(self) -> GaussMarkovCurrentConfig:
        """The Gauss-Markov current, used with current_model gauss_markov."""
    @gauss_markov_current.setter
    def gauss_markov_current(self, value: GaussMarkovCurrentConfig) -> None: ...
    @property
    def waves(self) -> WaveConfig | None:
        """A WaveConfig, or None for a calm sea."""
    @waves.setter
    def waves(self, value: WaveConfig | None) -> None: ...
    @property
    def payload(self) -> tuple[PayloadEvent, ...]:
        """Payload events in non-decreasing time (a tuple of copies; assign a list)."""
    @payload.setter
    def payload(self, value: Iterable[PayloadEvent]) -> None: ...
    @property
    def control_delay(self) -> int:
        """Control periods between a measurement and the force computed from it acting, 0..16 (0: in the same period)."""
    @control_delay.setter
    def control_delay(self, value: SupportsIndex) -> None: ...
    @property
    def water_density(self) -> float:
        """[kg/m^3], > 0 (sea water by default); a vehicle file's displaced volume gives its buoyancy as buoyancy_in_water(water_density, volume)."""
    @water_density.setter
    def water_density(self, value: SupportsFloat) -> None: ...
    @property
    def sensors(self) -> SensorsConfig:
        """The sensors; none: ideal sensing."""
    @sensors.setter
    def sensors(self, value: SensorsConfig) -> None: ...
    @property
    def estimator(self) -> EstimatorConfig:
        """The estimator."""
    @estimator.setter
    def estimator(self, value: EstimatorConfig) -> None: ...

def buoyancy_in_water(water_density: SupportsFloat, displaced_volume: SupportsFloat) -> float:
    """B = rho g V [N]: the buoyancy of displaced_volume [m^3] in water of water_density [kg/m^3]."""

@type_check_only
class _SimulationResult(TypedDict):
    """What :func:`run_closed_loop` returns: one row per control step t_k = k dt."""

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

    Keys: t, eta, nu, eta_d, eta_d_dot, tau_demanded, tau_applied,
    disturbance, s, thrusts, theta, adaptive_norm, controller_status,
    plant_status, faults, current, wave_velocity, wave_elevation, payload_mass,
    and diverged (bool). The controller is used as given and
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
def bluerov2_heavy_layout() -> tuple[_Array, _Array, list[str]]:
    """The BlueROV2 Heavy's thruster layout of the C++ core (model/bluerov2_heavy.hpp): (positions (8, 3) [m], unit thrust directions (8, 3), names), body axes x forward, y starboard, z down."""

def allocate_thrust(
    matrix: _ArrayLike,
    tau: _ArrayLike,
    max_thrust: _ArrayLike | None = None,
    min_thrust: _ArrayLike | None = None,
    saturation: _Saturation = "scale",
    weights: _ArrayLike | None = None,
) -> tuple[_Array, _Array]:
    """Allocates a wrench tau (6,) to thrusters with configuration matrix (6, n).

    Weighted pseudo-inverse, then saturation (``'scale'`` keeps the
    direction, ``'clip'`` clips each thruster). Returns ``(thrusts (n,),
    produced wrench (6,))``.
    """

# --------------------------------------------------------------------------
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
    @property
    def t(self) -> float:
        """Time t_k [s]."""
    @property
    def eta(self) -> _Array:
        """Measured pose (6,)."""
    @property
    def nu(self) -> _Array:
        """Measured body velocity (6,)."""
    @property
    def eta_d(self) -> _Array:
        """Desired pose (6,)."""
    @property
    def eta_d_dot(self) -> _Array:
        """Its first time derivative (6,)."""
    @property
    def eta_d_ddot(self) -> _Array:
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
    @property
    def observation(self) -> Observation:
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
    @property
    def done(self) -> bool:
        """Every row simulated, or the plant diverged."""
    @property
    def diverged(self) -> bool:
        """The plant diverged (its last row is the one where it did)."""
    @property
    def steps(self) -> int:
        """Rows logged so far."""
    @property
    def planned_steps(self) -> int:
        """Rows of a whole run: round(duration / dt) + 1."""
    @property
    def logged_parameters(self) -> int:
        """Parameters logged per row."""
    @property
    def faults(self) -> int:
        """Fault bits of the sensor faults and pitch limit in the observation."""
    @property
    def state(self) -> tuple[_Array, _Array]:
        """The true (eta, nu) at t_k."""
    @property
    def estimate_covariance(self) -> _Array | None:
        """The EKF's covariance (15, 15) at t_k (position, angles, body velocity, rates, gyro bias), or None without the ekf estimator."""
    @property
    def config(self) -> SimulationConfig:
        """A copy of the configuration."""
    @property
    def log_rows(self) -> int:
        """Rows the log holds at most (the whole run, or the window)."""
    @property
    def logged_from(self) -> int:
        """The run's index of the log's first row (the rows drained before it)."""
    @property
    def log_full(self) -> bool:
        """The log window is full: :meth:`step` refuses until :meth:`drain`."""
    def result(self) -> _SimulationResult:
        """The rows in the log (logged so far, or since the last drain), as the dict
        :func:`run_closed_loop` returns."""
    def drain(self) -> _SimulationResult:
        """The rows in the log, as :meth:`result` gives them, and empties the log so
        that stepping goes on past a full window."""
