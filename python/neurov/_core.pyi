"""neurov's C++ core: vehicle dynamics, Euler-angle kinematics and integrator
(double precision). Import from ``neurov``, not from here.

Every array argument accepts anything ``numpy.asarray`` turns into a real
(float or integer) array of the stated shape: lists, integer arrays,
non-contiguous and read-only arrays. A wrong shape, NaN or Inf raises
``ValueError`` and a wrong dtype (str, complex, object, bool) or ``None``
raises ``TypeError``; both name the argument. Scalars are real numbers (not
``bool``). Every returned array is a new, writeable ``float64`` array.
"""

import os
from typing import ClassVar, Literal, SupportsFloat, SupportsIndex, SupportsInt, TypedDict, final, type_check_only

import numpy
import numpy.typing

_Array = numpy.typing.NDArray[numpy.float64]
_ArrayLike = numpy.typing.ArrayLike
_CoriolisForm = Literal["velocity_independent", "kirchhoff"]

__version__: str

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
