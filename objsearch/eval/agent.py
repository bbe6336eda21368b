"""The agent protocol every evaluated agent follows (after habitat-lab's ``Agent``).

An agent is any object with::

    reset(task: AgentTask) -> None          # a new episode begins
    act(observation) -> action               # one step
    load(path) -> None                       # optional: load weights/checkpoint

The harness creates one agent per worker with no arguments (``cls()``), calls ``load`` if a
checkpoint is given, then for every episode ``reset`` followed by ``act`` until the episode
ends. An agent must not carry state from one episode into the next (results must not
depend on episode order or the number of workers), and must draw all its randomness from
``task.rng``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import gymnasium
import numpy as np


@dataclass
class AgentTask:
    """What an agent is told at the start of an episode.

    Attributes:
        suite: suite name, e.g. ``gridworld``.
        split: split name, e.g. ``unseen-goals``.
        episode_id: index of the episode within its split.
        goal: the goal's id (grid world: goal index 0..15).
        goal_name: the goal's label for reports (grid world: ``g14``).
        observation_space, action_space: the env's spaces.
        rng: this episode's random Generator; the agent's only source of randomness.
        privileged: ground truth the oracle uses (an object with ``shortest_path() ->
            list[action]``). A learning agent must not read it.
    """

    suite: str
    split: str
    episode_id: int
    goal: int
    goal_name: str
    observation_space: gymnasium.Space
    action_space: gymnasium.Space
    rng: np.random.Generator
    privileged: Any = field(default=None, repr=False)


@runtime_checkable
class Agent(Protocol):
    def reset(self, task: AgentTask) -> None: ...

    def act(self, observation: Any) -> Any: ...
