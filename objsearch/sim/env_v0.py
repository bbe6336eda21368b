"""``ObjSearch/House-v0``: the house env with the observation keys v0 was released with.

v0 gained the ``pose`` and ``collided`` keys in place; they are ``ObjSearch/House-v1``'s now
(``objsearch.sim.env.HouseEnv``, its Version History), and the v0 id gives its first four keys
again, so that code written against v0 (a ``FlattenObservation``, a network over its keys)
keeps working. Everything else is ``HouseEnv``'s: arguments, tasks, actions, rewards, info.
"""

from __future__ import annotations

import numpy as np
from gymnasium import spaces
from gymnasium.vector.utils import batch_space

from objsearch.sim.env import HouseEnv
from objsearch.sim.vector import HouseVectorEnv

V0_KEYS = ("rgb", "depth", "semantic", "target")


class HouseEnvV0(HouseEnv):
    """``HouseEnv`` whose observations hold ``V0_KEYS`` only: ``Dict(rgb, depth, semantic,
    target)``. Use ``ObjSearch/House-v1`` for ``pose`` and ``collided``."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.observation_space = spaces.Dict({key: self.observation_space[key] for key in V0_KEYS})

    def _observe(self) -> dict:
        observation = super()._observe()
        return {key: observation[key] for key in V0_KEYS}


class HouseVectorEnvV0(HouseVectorEnv):
    """``HouseVectorEnv`` whose observations hold ``V0_KEYS`` only (``make_vec`` of v0)."""

    def __init__(self, num_envs: int, **env_kwargs):
        super().__init__(num_envs, **env_kwargs)
        self.single_observation_space = spaces.Dict({key: self.single_observation_space[key] for key in V0_KEYS})
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)

    def _observe(self) -> dict[str, np.ndarray]:
        observation = super()._observe()
        return {key: observation[key] for key in V0_KEYS}
