"""Stub-only piece of :mod:`neurov._core` for type checkers (nothing imports it
at runtime): the layer ``model``, the vehicle, kinematics, integrator,
linearisation, regressor and thrusters (``python/bindings/model``)."""

# The pieces share their private helpers (arrays, descriptors, bases).
# pyright: reportPrivateUsage=false

import os
from typing import ClassVar, Literal, SupportsFloat, TypedDict, final, type_check_only

from .core import (
    _Array,
    _ArrayField,
    _ArrayLike,
    _Enum,
    _Field,
    _FloatField,
    _ReadOnly,
    _TupleField,
    _ValidatedFields,
)

_CoriolisForm = Literal["velocity_independent", "kirchhoff"]
_Saturation = Literal["scale", "clip"]

THETA_NAMES: tuple[str, ...]
"""Names of the 24 columns of :func:`regressor` (the entries of theta), e.g. ``'m'``, ``'X_u|u|'``."""

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
    mass: _ReadOnly[float] = ...
    """m [kg]."""
    inertia: _ReadOnly[_Array] = ...
    """I_o about the body origin, shape (3, 3) [kg m^2]."""
    centre_of_gravity: _ReadOnly[_Array] = ...
    """r_g, shape (3,) [m], body axes."""
    centre_of_buoyancy: _ReadOnly[_Array] = ...
    """r_b, shape (3,) [m], body axes (z down)."""
    weight: _ReadOnly[float] = ...
    """W [N]."""
    buoyancy: _ReadOnly[float] = ...
    """B [N]."""
    added_mass: _ReadOnly[_Array] = ...
    """M_A, shape (6, 6)."""
    linear_damping: _ReadOnly[_Array] = ...
    """D_L, shape (6,)."""
    quadratic_damping: _ReadOnly[_Array] = ...
    """D_Q, shape (6,)."""
    coriolis_form: _ReadOnly[_CoriolisForm] = ...
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

def to_body(eta: _ArrayLike, vectors: _ArrayLike) -> _Array:
    """J(eta_k)^-1 v_ki for K poses eta (K, 6) and vectors (K, M, 6): shape (K, M, 6).

    The earth-frame vectors in each pose's body frame, all K in one call.
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

def regressor(nu_r_dot: _ArrayLike, nu_r: _ArrayLike, nu: _ArrayLike, eta: _ArrayLike) -> _Array:
    """Regressor Phi (6, 24) with ``Phi @ theta = M nu_r_dot + C(nu) nu_r + D(nu) nu_r + g(eta)``
    for NEROV's model structure; :data:`THETA_NAMES` names the columns."""

def regressor_parameters(vehicle: Vehicle) -> _Array:
    """The true theta (24,) of a vehicle whose structure the regressor covers.

    That is r_g = 0, diagonal inertia and added mass, r_b on the z axis;
    ``ValueError`` otherwise.
    """

class Saturation(_Enum):
    """How thrusts beyond their limits are brought back."""

    scale: ClassVar[Saturation]
    """Every thruster scaled by one factor: the wrench keeps its direction."""
    clip: ClassVar[Saturation]
    """Each thruster clipped to its limits: the wrench turns."""
    __members__: ClassVar[dict[str, Saturation]]

@final
class ThrusterCurveConfig(_ValidatedFields):
    """One thruster from command to thrust: a table (linearly interpolated), a dead band around the neutral command, supply-voltage scaling, a first-order lag and a slew-rate limit."""

    table: _ArrayField = ...
    """(n, 2) rows of (command, thrust [N] at reference_voltage), commands strictly increasing, 2 <= n <= 256 (a read-only copy)."""
    neutral: _FloatField = ...
    """The command of zero thrust, inside the table."""
    dead_band: _FloatField = ...
    """Half-width of the dead band around neutral (command units), >= 0."""
    reference_voltage: _FloatField = ...
    """Supply voltage [V] at which the table was measured, > 0."""
    voltage_exponent: _FloatField = ...
    """Thrust ~ voltage^exponent at a fixed command, >= 0 (2: an assumption)."""
    time_constant: _FloatField = ...
    """First-order lag of the thrust [s]; 0: none."""
    slew_rate: _FloatField = ...
    """Largest rate of change of the thrust [N/s]; 0: none."""
    def static_thrust(self, command: SupportsFloat, voltage: SupportsFloat) -> float:
        """Steady thrust [N] at a command and supply voltage (the C++ curve)."""
    def command_for(self, thrust: SupportsFloat, voltage: SupportsFloat) -> float:
        """The command whose steady thrust is `thrust` at `voltage` (the curve's inverse), clamped to the table."""

@final
class ThrusterConfig(_ValidatedFields):
    """n thrusters: tau = B u, allocated by the weighted pseudo-inverse, saturated, with a first-order lag."""

    matrix: _ArrayField = ...
    """B (6, n): the wrench of each thruster per unit thrust (a read-only copy)."""
    min_thrust: _ArrayField = ...
    """Lower limits [N] (n,), <= 0 (a read-only copy)."""
    max_thrust: _ArrayField = ...
    """Upper limits [N] (n,), > min_thrust (a read-only copy)."""
    weights: _ArrayField = ...
    """Allocation weights (n,), > 0; empty means all 1 (a read-only copy)."""
    saturation: _Field[Saturation, Saturation] = ...
    """How thrusts beyond their limits are brought back."""
    time_constant: _FloatField = ...
    """First-order lag [s] of linear thrusters; 0 means none (0 with curves)."""
    curves: _TupleField[ThrusterCurveConfig] = ...
    """One command-to-thrust curve per thruster, or empty: linear thrusters (a tuple of copies; assign a list)."""
    supply_voltage: _FloatField = ...
    """Supply voltage [V] of the curves, > 0 with curves."""

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
