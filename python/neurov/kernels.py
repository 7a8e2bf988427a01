"""NEUROV_KERNEL, the environment variable that pins the copy of the RBF
network's loops (docs/studies.md, "Reproducibility"). The C++ core reads it
once and cannot say that a value is misspelt or that this CPU lacks the path
asked for; this module says so, as a warning, when neurov is imported."""
from __future__ import annotations

import os
import warnings

from neurov import _core

#: The values NEUROV_KERNEL accepts ("auto" or unset: the fastest the CPU has).
CHOICES = ("generic", "avx2", "avx512", "auto")


def kernel_path() -> str:
    """The copy of the RBF loops in use: "avx512", "avx2", or the build's
    own ("sse2" on the x86-64 baseline, "neon", ...; NEUROV_KERNEL=generic)."""
    return _core._kernel_isa()


def check_kernel_request() -> None:
    """Warns (RuntimeWarning) if NEUROV_KERNEL is not one of :data:`CHOICES`,
    or names a path this CPU or build cannot run (the core then uses the best
    below it)."""
    want = os.environ.get("NEUROV_KERNEL", "")
    if want in ("", "auto"):
        return
    if want not in CHOICES:
        warnings.warn(f"NEUROV_KERNEL={want!r} is not one of {', '.join(map(repr, CHOICES))}: "
                      f"ignored, the RBF loops use {kernel_path()!r}", RuntimeWarning, stacklevel=3)
        return
    got = kernel_path()
    if want != "generic" and got.split("-")[0] != want:
        warnings.warn(f"NEUROV_KERNEL={want!r}: this CPU or build cannot run it; the RBF loops "
                      f"use {got!r}", RuntimeWarning, stacklevel=3)
