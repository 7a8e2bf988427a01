"""Ctrl-C and SIGTERM during a tuning: an orderly stop, never one in the
middle of Optuna's bookkeeping.

While a tuning runs (:func:`stopping`), SIGINT and SIGTERM raise
:class:`TuneStopped` (a ``KeyboardInterrupt`` carrying the signal) where
the tuning is, as Ctrl-C does by default, except inside :func:`deferred`:
there the signal is only noted, and raised when the deferred part ends or
when a :func:`live` part inside it begins. A tuning defers Optuna's loop
(asking for a trial, telling its result: an interrupt there left a raw
``UnboundLocalError`` from Optuna and a trial "running" for ever) and lets
the signal through only inside the objective, where Optuna marks the trial
failed and hands the interrupt on. One signal stops the tuning; later ones
while it stops are noted, not raised, so that a second Ctrl-C cannot cut
the stopping short and leave worker processes behind.

Outside the main thread (where Python runs no signal handler) these are
no-ops, and Ctrl-C behaves as it does by default."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from typing import Any

__all__ = ["TuneStopped", "deferred", "live", "stopping"]

_STOPS = (signal.SIGINT, signal.SIGTERM)


class TuneStopped(KeyboardInterrupt):
    """Ctrl-C (SIGINT) or SIGTERM during a tuning; `signum` is the signal
    (``neurov tune`` exits with 128 + it)."""

    def __init__(self, signum: int = signal.SIGINT) -> None:
        super().__init__()
        self.signum = int(signum)


class _State:
    installed = 0
    """How many :func:`stopping` blocks are open (they nest)."""
    pending: int | None = None
    """The first signal received and not yet raised."""
    raised = False
    """Whether a signal was raised: later ones are only noted."""
    armed = True
    """Whether a signal is raised at once (False inside :func:`deferred`)."""


_state = _State()


def _handler(signum: int, frame: Any) -> None:
    if _state.pending is None and not _state.raised:
        _state.pending = signum
    if _state.armed:
        _raise_pending()


def _raise_pending() -> None:
    if _state.pending is not None and not _state.raised:
        signum, _state.pending = _state.pending, None
        _state.raised = True
        raise TuneStopped(signum)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextlib.contextmanager
def stopping() -> Iterator[None]:
    """SIGINT and SIGTERM raise :class:`TuneStopped` inside (but inside
    :func:`deferred`); the previous handlers come back when it ends."""
    if not _main_thread():
        yield
        return
    previous = None
    if _state.installed == 0:
        previous = [signal.signal(s, _handler) for s in _STOPS]
        _state.pending, _state.raised, _state.armed = None, False, True
    _state.installed += 1
    try:
        yield
    finally:
        _state.installed -= 1
        if previous is not None:
            for s, handler in zip(_STOPS, previous):
                signal.signal(s, handler)


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """A signal received inside is raised when this ends (or when a
    :func:`live` part inside begins), not in the middle of what it guards;
    within a stopping tuning, later signals are never raised."""
    if not _main_thread() or _state.installed == 0:
        yield
        return
    armed, _state.armed = _state.armed, False
    try:
        yield
    finally:
        _state.armed = armed
    if armed:
        _raise_pending()


@contextlib.contextmanager
def live() -> Iterator[None]:
    """Inside a :func:`deferred` part: a signal (pending or new) is raised
    at once here."""
    if not _main_thread() or _state.installed == 0:
        yield
        return
    armed, _state.armed = _state.armed, True
    try:
        _raise_pending()
        yield
    finally:
        _state.armed = armed
