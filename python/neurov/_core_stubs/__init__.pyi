"""Stub-only pieces of :mod:`neurov._core`, one per layer of its bindings
(``core``, ``model``, ``control``, ``sim``, as in ``python/bindings``).

They exist for type checkers only: ``neurov/_core.pyi`` re-exports every
public name from them, and nothing imports them at runtime. Import from
``neurov``.
"""
