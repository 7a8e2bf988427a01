"""Many runs stepped together: :class:`PythonLanes`, the batch interface of
``neurov._core.BatchSimulator`` over single simulators, and
:func:`run_batched_policy`, a batched Python policy driving a batch."""

from neurov.batching.lanes import PythonLanes
from neurov.batching.policy_loop import run_batched_policy

__all__ = ["PythonLanes", "run_batched_policy"]
