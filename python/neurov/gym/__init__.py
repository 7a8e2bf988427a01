"""neurov as a Gymnasium environment (the extra ``neurov[gym]``).

Importing this module registers ``neurov/Tracking-v0``::

    import gymnasium
    import neurov.gym
    env = gymnasium.make("neurov/Tracking-v0", scenario="paper_fig3")
    envs = gymnasium.make_vec("neurov/Tracking-v0", num_envs=256,
                              vectorization_mode="vector_entry_point", scenario="paper_fig3")

or, without the import, ``gymnasium.make("neurov.gym:neurov/Tracking-v0", ...)``.
"""

from __future__ import annotations

try:
    import gymnasium
except ImportError as e:  # pragma: no cover - the extra is not installed
    raise ImportError("neurov.gym needs Gymnasium: pip install 'neurov[gym]'") from e

from neurov.gym.limits import single_dof_limits
from neurov.gym.tracking import TrackingEnv, resolve_scenario
from neurov.gym.vector import TrackingVectorEnv

__all__ = ["TrackingEnv", "TrackingVectorEnv", "resolve_scenario", "single_dof_limits"]

if "neurov/Tracking-v0" not in gymnasium.registry:
    gymnasium.register(id="neurov/Tracking-v0", entry_point="neurov.gym.tracking:TrackingEnv",
                       vector_entry_point="neurov.gym.vector:TrackingVectorEnv")
