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
from collections.abc import Iterable, Mapping
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
from typing_extensions import Unpack

_Array = numpy.typing.NDArray[numpy.float64]
_ArrayLike = numpy.typing.ArrayLike
_CoriolisForm = Literal["velocity_independent", "kirchhoff"]
_Modification = Literal["none", "sigma", "e_modification", "projection"]
_Saturation = Literal["scale", "clip"]

__version__: str
THETA_NAMES: tuple[str, ...]
"""Names of the 24 columns of :func:`regressor` (the entries of theta), e.g. ``'m'``, ``'X_u|u|'``."""

@final
class Status:
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

    def __init__(self, value: SupportsInt | SupportsIndex) -> None:
        """The status with this integer value."""
    def __eq__(self, other: object) -> bool: ...
    def __ne__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...
    def __index__(self) -> int: ...
    def __int__(self) -> int: ...
    def __getstate__(self) -> int: ...
    def __setstate__(self, state: SupportsInt | SupportsIndex) -> None: ...
    @property
    def name(self) -> str:
        """The member's name, e.g. ``"ok"``."""
    @property
    def value(self) -> int:
        """The member's integer value (``ok`` is 0)."""

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
class RobustModification:
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

    def __init__(self, value: SupportsInt | SupportsIndex) -> None:
        """The modification with this integer value."""
    def __eq__(self, other: object) -> bool: ...
    def __ne__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...
    def __index__(self) -> int: ...
    def __int__(self) -> int: ...
    def __getstate__(self) -> int: ...
    def __setstate__(self, state: SupportsInt | SupportsIndex) -> None: ...
    @property
    def name(self) -> str:
        """The member's name, e.g. ``"sigma"``."""
    @property
    def value(self) -> int:
        """The member's integer value (``none`` is 0)."""

class PDConfig:
    """Configuration of :class:`PDController`.

    Every field has the C++ default; ``PDConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
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

class PIDConfig:
    """Configuration of :class:`PIDController`.

    Every field has the C++ default; ``PIDConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
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

class SlidingModeConfig:
    """Configuration of :class:`SlidingModeController`.

    Every field has the C++ default; ``SlidingModeConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
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

class LinearAdaptiveConfig:
    """Configuration of :class:`LinearAdaptiveController`.

    Every field has the C++ default; ``LinearAdaptiveConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
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

class NNAdaptiveConfig:
    """Configuration of :class:`NNAdaptiveController`.

    Every field has the C++ default; ``NNAdaptiveConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
    @property
    def lambda_(self) -> _Array:
        """Lambda in s = eta_tilde_dot + Lambda eta_tilde, diagonal (6,), > 0."""
    @lambda_.setter
    def lambda_(self, value: _ArrayLike) -> None: ...
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

class ComputedTorqueConfig:
    """Configuration of :class:`ComputedTorqueController`.

    Every field has the C++ default; ``ComputedTorqueConfig(**fields)`` sets some by
    keyword (an unknown one raises ``TypeError``), and a value of the wrong
    shape or type raises naming its field. The controller's constructor and
    :meth:`validate` run the one C++ validator.
    """

    def __init__(self, **kwargs: Any) -> None:
        """Every field at its default, or as given by keyword."""
    def validate(self) -> None:
        """``ValueError`` naming the first bad field and what it must be; None when valid."""
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

@type_check_only
class _Disturbance(TypedDict):
    """A sinusoidal disturbance on one DOF."""

    dof: int
    amplitude: float
    frequency: float
    phase: float
    start: float

@type_check_only
class _ThrusterFailure(TypedDict):
    """From ``time`` on, thruster ``index`` delivers ``efficiency`` times its thrust."""

    index: int
    efficiency: float
    time: float

@type_check_only
class _SensorFault(TypedDict):
    """A sensor fault from ``start`` to ``end`` [s] on the pose (``eta``) and/or velocity (``nu``) measurement."""

    kind: Literal["freeze", "dropout", "noise_burst"]
    start: float
    end: float
    eta: bool
    nu: bool
    noise_eta: _ArrayLike
    noise_nu: _ArrayLike

@type_check_only
class _CurrentStep(TypedDict):
    """From ``time`` [s] on, the NED current is ``velocity`` (3,) [m/s]."""

    time: float
    velocity: _ArrayLike

@type_check_only
class _SimulationOptions(TypedDict, total=False):
    """Keyword arguments of :func:`run_closed_loop`; only the command is required."""

    dt: SupportsFloat
    substeps: int
    duration: SupportsFloat
    eta0: _ArrayLike
    nu0: _ArrayLike
    command_times: _ArrayLike
    command_poses: _ArrayLike
    command_interpolation: Literal["linear", "hold"]
    lambda_d: _ArrayLike
    omega: _ArrayLike
    disturbances: Iterable[_Disturbance | Mapping[str, Any]]
    current: _ArrayLike
    current_amplitude: _ArrayLike
    current_period: SupportsFloat
    noise_eta: _ArrayLike
    noise_nu: _ArrayLike
    seed: int
    thruster_matrix: _ArrayLike
    thruster_max: _ArrayLike
    thruster_min: _ArrayLike
    thruster_weights: _ArrayLike
    saturation: _Saturation
    thruster_time_constant: SupportsFloat
    thruster_failures: Iterable[_ThrusterFailure | Mapping[str, Any]]
    sensor_faults: Iterable[_SensorFault | Mapping[str, Any]]
    current_steps: Iterable[_CurrentStep | Mapping[str, Any]]
    refused_step_policy: Literal["zero", "hold"]

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
    thrusts: _Array
    theta: _Array
    adaptive_norm: _Array
    controller_status: numpy.typing.NDArray[numpy.uint8]
    plant_status: numpy.typing.NDArray[numpy.uint8]
    faults: numpy.typing.NDArray[numpy.uint8]
    """Per step: bit 1 freeze, 2 dropout, 4 noise burst, 8 a thruster below full efficiency,
    16 the row's eta_d came from a pitch-limited reference step."""
    diverged: bool

@overload
def run_closed_loop(
    vehicle: Vehicle, controller: NNAdaptiveController, **kwargs: Unpack[_SimulationOptions]
) -> _SimulationResult:
    """Runs a closed loop in C++ and returns a dict of arrays (rows at t_k = k dt).

    Keys: t, eta, nu, eta_d, eta_d_dot, tau_demanded, tau_applied,
    disturbance, s, thrusts, theta, adaptive_norm, controller_status,
    plant_status, faults, and diverged (bool). The controller is used as given and
    left in its final state. ``neurov.simulate(scenario)`` is the friendly
    front end.
    """

@overload
def run_closed_loop(
    vehicle: Vehicle, controller: LinearAdaptiveController, **kwargs: Unpack[_SimulationOptions]
) -> _SimulationResult: ...
@overload
def run_closed_loop(
    vehicle: Vehicle, controller: PDController, **kwargs: Unpack[_SimulationOptions]
) -> _SimulationResult: ...
@overload
def run_closed_loop(
    vehicle: Vehicle, controller: PIDController, **kwargs: Unpack[_SimulationOptions]
) -> _SimulationResult: ...
@overload
def run_closed_loop(
    vehicle: Vehicle, controller: SlidingModeController, **kwargs: Unpack[_SimulationOptions]
) -> _SimulationResult: ...
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
