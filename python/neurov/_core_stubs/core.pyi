"""Stub-only piece of :mod:`neurov._core` for type checkers (nothing imports it
at runtime): what every layer's stub uses, the fields' descriptors and the
enum and configuration bases, and the layer ``core`` (:class:`Status`).

Every field of the core is a pybind11 property; here it is one line,
``kp: _ArrayField = ...``, a descriptor that states once what reading gives
and what assigning takes: ``_Field[get, set]`` for a property with a setter,
``_ReadOnly[get]`` for one without.
"""

from collections.abc import Iterable
from typing import (
    Any,
    ClassVar,
    Generic,
    SupportsFloat,
    SupportsIndex,
    SupportsInt,
    TypeVar,
    final,
    overload,
    type_check_only,
)

import numpy
import numpy.typing
from typing_extensions import Never, Self

_Array = numpy.typing.NDArray[numpy.float64]
_ArrayLike = numpy.typing.ArrayLike

_G = TypeVar("_G")
_S = TypeVar("_S")
_T = TypeVar("_T")

# One class for both kinds, with __get__ and __set__ on it: pyright takes a
# descriptor whose __get__ comes from a base for a symmetric one, and after
# `config.kp = [...]` would type `config.kp` as the list.
@final
@type_check_only
class _Field(Generic[_G, _S]):
    """A field: reading it from an instance gives a _G (from the class, the
    property), assigning takes an _S."""

    @overload
    def __get__(self, instance: None, owner: type[Any], /) -> property: ...
    @overload
    def __get__(self, instance: object, owner: type[Any] | None = None, /) -> _G: ...
    def __set__(self, instance: object, value: _S, /) -> None: ...

# A property without a setter: no value may be assigned (at runtime, AttributeError).
_ReadOnly = _Field[_G, Never]
# Reading gives a new float64 array or a view; assigning takes anything
# numpy.asarray turns into a real array of the field's shape.
_ArrayField = _Field[_Array, _ArrayLike]
_FloatField = _Field[float, SupportsFloat]
_IntField = _Field[int, SupportsIndex]
_BoolField = _Field[bool, bool]
# A list of structs: reading gives a tuple of copies, assigning takes any iterable.
_TupleField = _Field[tuple[_T, ...], Iterable[_T]]

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
    name: _ReadOnly[str] = ...
    """The member's name."""
    value: _ReadOnly[int] = ...
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
    """A configuration struct with the C++ validator.

    Every field has the C++ default; ``Config(**fields)`` sets some by keyword
    (an unknown one raises ``TypeError``), and a value of the wrong shape or
    type raises naming its field. :meth:`validate` and whatever takes the
    struct (a controller's constructor, the simulator, :func:`run_closed_loop`)
    run the one C++ validator.
    """

    def validate(self) -> None:
        """:class:`ValidationError` (a ``ValueError`` carrying ``field`` and ``index``) naming the first bad field and what it must be; None when valid."""

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

class NeurovError(ValueError):
    """The base of every error neurov raises for bad input (a ValueError)."""

class ValidationError(NeurovError):
    """A configuration refused by its C++ validator. Attributes: field (the offending field's C++ name), index (the element, row-major for a matrix, or -1 for the whole field), value (the offending value, None for a whole matrix) and expected (what the field must satisfy)."""

    field: str
    index: int
    value: float | None
    expected: str
