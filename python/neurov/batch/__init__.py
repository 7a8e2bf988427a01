"""Many runs at once: :func:`simulate_many` runs built-in controllers as
batches of lanes in C++ (``neurov._core.run_batch``, threads, the GIL
released), and Python controllers one by one."""

from neurov.batch.many import simulate_many

__all__ = ["simulate_many"]
