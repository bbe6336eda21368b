"""objsearch's environments as ``dm_env.Environment``s, for the DeepMind ecosystem (Acme
agents, dm_control-style loops). (Named ``dm_adapter``, not ``dm_env``, so that it never
stands in for the package it wraps.)

``grid_world(**kwargs)``, ``house(**kwargs)`` and ``suite(name, **kwargs)`` make the Gymnasium
envs ``ObjSearch/GridWorld-v0``, ``ObjSearch/House-v1`` and ``ObjSearch/Suite-v1`` with those
arguments and wrap them in ``GymnasiumEnvironment``, which exposes them as dm_control's suites
do: ``observation_spec()`` a dict of named specs (a ``Box`` key a ``BoundedArray``, a
``Discrete`` key a scalar ``DiscreteArray``), ``action_spec()`` a ``DiscreteArray`` named
``action``, and ``TimeStep``s whose discount is 0 when the episode terminates (the goal is
reached, or STOP is called) and 1 when it is truncated (the step limit).
``suite("house-single", split="seen-goals")`` is the one call of dm_control's
``suite.load(domain, task)``: it plays that split's fixed episodes in order, as
``objsearch-eval`` does.

Randomness is explicit: ``seed`` seeds the env's Generator on the first ``reset()``; later
episodes continue from it, so the same seed gives the same episodes (a suite's episodes are
fixed whatever the seed). ``info`` holds the Gymnasium ``info`` of the last reset or step
(``success``, ``steps``, ``min_steps``, ...), which ``TimeStep`` has no place for.
"""

from __future__ import annotations

from typing import Any

import dm_env
import gymnasium
import numpy as np
from dm_env import specs
from gymnasium import spaces

GRID_WORLD_ID = "ObjSearch/GridWorld-v0"
HOUSE_ID = "ObjSearch/House-v1"
SUITE_ID = "ObjSearch/Suite-v1"


def _spec(name: str, space: gymnasium.Space) -> specs.Array:
    """The dm_env spec of a Gymnasium ``Box`` or ``Discrete`` space."""
    if isinstance(space, spaces.Discrete):
        if space.start != 0:
            raise ValueError(f"{name}: a Discrete space starting at {space.start} has no DiscreteArray spec")
        return specs.DiscreteArray(num_values=int(space.n), dtype=np.int64, name=name)
    if isinstance(space, spaces.Box):
        # one bound for the whole array when it is uniform (an image), else per element (a pose)
        low, high = (b.flat[0] if np.all(b == b.flat[0]) else b for b in (space.low, space.high))
        return specs.BoundedArray(space.shape, space.dtype, minimum=low, maximum=high, name=name)
    raise TypeError(f"{name}: no dm_env spec for a {type(space).__name__} space (Box and Discrete have one)")


class GymnasiumEnvironment(dm_env.Environment):
    """A Gymnasium env whose observations are a ``Dict`` of ``Box`` and ``Discrete`` spaces,
    and whose actions a ``Discrete`` space, as a ``dm_env.Environment``.

    Args:
        env: the Gymnasium env (closed with this one).
        seed: seeds the env's Generator on the first reset (None: fresh entropy).
    """

    def __init__(self, env: gymnasium.Env, seed: int | None = None):
        if not isinstance(env.observation_space, spaces.Dict):
            raise TypeError(f"observation space {env.observation_space} is not a Dict of Box and Discrete spaces")
        self.env = env
        self._seed = seed
        self._observation_spec = {key: _spec(key, space) for key, space in env.observation_space.spaces.items()}
        self._action_spec = _spec("action", env.action_space)
        self._reset_next_step = True
        self.info: dict[str, Any] = {}

    def reset(self) -> dm_env.TimeStep:
        """Start an episode (a task drawn with the env's Generator); a ``FIRST`` time step."""
        observation, self.info = self.env.reset(seed=self._seed)
        self._seed = None  # later episodes continue the seeded Generator
        self._reset_next_step = False
        return dm_env.restart(self._observation(observation))

    def step(self, action) -> dm_env.TimeStep:
        """Take ``action``; after a ``LAST`` time step (or before any), start an episode instead."""
        if self._reset_next_step:
            return self.reset()
        observation, reward, terminated, truncated, self.info = self.env.step(int(action))
        observation = self._observation(observation)
        self._reset_next_step = terminated or truncated
        if terminated:
            return dm_env.termination(float(reward), observation)
        if truncated:
            return dm_env.truncation(float(reward), observation)
        return dm_env.transition(float(reward), observation)

    def observation_spec(self) -> dict[str, specs.Array]:
        """A spec for each observation key, named after it."""
        return dict(self._observation_spec)

    def action_spec(self) -> specs.DiscreteArray:
        """The actions: ``DiscreteArray(num_values=N)`` (the env's docstring names them)."""
        return self._action_spec

    def close(self) -> None:
        """Close the Gymnasium env."""
        self.env.close()

    def _observation(self, observation: dict) -> dict[str, np.ndarray]:
        return {key: np.asarray(observation[key], dtype=spec.dtype) for key, spec in self._observation_spec.items()}


def grid_world(seed: int | None = None, **kwargs) -> GymnasiumEnvironment:
    """The paper's grid world (``objsearch.gridworld.env.GridWorldEnv(**kwargs)``) as a dm_env."""
    return GymnasiumEnvironment(gymnasium.make(GRID_WORLD_ID, disable_env_checker=True, **kwargs), seed)


def house(seed: int | None = None, **kwargs) -> GymnasiumEnvironment:
    """The 3D houses (``objsearch.sim.env.HouseEnv(**kwargs)``, e.g. ``houses=[HouseRef(seed=3)]``) as a dm_env."""
    return GymnasiumEnvironment(gymnasium.make(HOUSE_ID, disable_env_checker=True, **kwargs), seed)


def suite(name: str, seed: int | None = None, **kwargs) -> GymnasiumEnvironment:
    """A suite's fixed episodes (``objsearch.eval.suite_env.SuiteEnv(name, **kwargs)``, e.g.
    ``split="seen-goals"``) as a dm_env: each ``reset()`` starts the next episode."""
    return GymnasiumEnvironment(gymnasium.make(SUITE_ID, disable_env_checker=True, suite=name, **kwargs), seed)
