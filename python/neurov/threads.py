"""The numerical libraries' thread count, set by neurov where it matters.

NumPy's and SciPy's BLAS (OpenBLAS, MKL) start a thread per core for every
matrix product. For the small, many products of an identification fit those
threads cost more than they give (on a loaded 2-core machine the fit took
2.6 times as long as with one thread) and their order of summation makes the
last digits depend on the machine's core count. :func:`one_blas_thread`
runs a function with one BLAS thread (threadpoolctl), whatever
``OPENBLAS_NUM_THREADS`` says, and restores the count after.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["one_blas_thread"]

F = TypeVar("F", bound=Callable[..., Any])


def one_blas_thread(function: F) -> F:
    """`function`, run with the BLAS libraries limited to one thread."""

    @functools.wraps(function)
    def limited(*args: Any, **kwargs: Any) -> Any:
        # Deferred: threadpoolctl inspects the loaded libraries; `import neurov` needs none of it.
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return limited  # type: ignore[return-value]
