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

Optional class hooks: ``worlds()`` names the worlds (``gridworld``, ``house``) whose suites
the agent runs on (the harness refuses other suites before the first episode),
``for_suite(suite, checkpoint)`` builds the agent for a suite instead of ``cls()``, and
``training_runs(suite) -> list[TrainingRun]`` lists the checkpoints of a learned agent made
for the suite by the same recipe with different training seeds: with none given, the
harness evaluates every one and reports across them (``objsearch.eval.runs``).

The batched form (``objsearch-eval --batch N``): N episodes run in lockstep in slots
0..N-1, and an agent that has all three of::

    start_batch(num_slots) -> None                       # once, before the first reset
    reset_batch(tasks: dict[int, AgentTask]) -> None     # these slots begin an episode
    act_batch(observations: dict[int, obs]) -> dict[int, action]   # every busy slot

decides for all slots in one call. Each slot's episode must draw from its own
``task.rng`` exactly as ``reset``/``act`` would, so its record does not depend on N. An
agent without them gets one instance per slot. An agent written in the batched form can
take ``reset``/``act`` from ``OneSlotBatch`` (one episode as a batch of one slot).

Protocols: a suite's episodes end by themselves at the goal (``paper``) or need the agent to
call STOP there (``objectnav``; the action is ``task.stop_action``, None under ``paper``). A
class hook ``protocols()`` names those an agent plays; the harness refuses a suite of another
before the first episode (the learned house agents have no STOP action: ``("paper",)``). An
agent without it plays every protocol.
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import gymnasium
import numpy as np

from objsearch.errors import UserError


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
        camera: the camera's parameters where the env has one (house suites:
            ``objsearch.sim.camera.RenderSettings.intrinsics``: image size, fields of view,
            focal lengths, height, clipping), else None.
        stop_action: the action the agent must take at a goal to succeed, where the suite's
            protocol requires one (house suites of the ``objectnav`` protocol: 6, STOP; STOP
            anywhere else ends the episode as a failure), else None (the episode ends by
            itself on reaching a goal).
        goal_rule: the rule that made the goal poses where the suite has one (house suites:
            ``objsearch.sim.goals.GoalRule.to_json``, e.g. ``near_visible``: a pose that sees
            ``min_pixels`` target pixels of the 64 x 64 goal camera within ``max_distance``
            metres), else None.
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
    camera: dict | None = None
    stop_action: int | None = None
    goal_rule: dict | None = None


CHECKPOINTS_ENV = "OBJSEARCH_CHECKPOINTS"
"""An environment variable naming a folder laid out as the agents' shipped checkpoints
(``SUITE/AGENT[/seedK]``): learned agents then find their training runs there instead
(``objsearch reproduce --out`` sets it for the runs it trained)."""


@contextlib.contextmanager
def checkpoints_from(folder: str | None):
    """``CHECKPOINTS_ENV`` set to ``folder`` meanwhile (unset for None: the shipped weights),
    as it was before afterwards."""
    before = os.environ.pop(CHECKPOINTS_ENV, None)
    if folder is not None:
        os.environ[CHECKPOINTS_ENV] = folder
    try:
        yield
    finally:
        os.environ.pop(CHECKPOINTS_ENV, None)
        if before is not None:
            os.environ[CHECKPOINTS_ENV] = before


@dataclass(frozen=True)
class TrainingRun:
    """One training run of a learned agent: a checkpoint and what it cost.

    Attributes:
        seed: the training seed (``objsearch train --seed``); names the run
            (``objsearch-eval --training-run SEED``).
        checkpoint: the path ``for_suite``/``load`` takes.
        env_steps: environment steps of its training, pretraining included (None: unknown).
        wall_s: seconds of its training, pretraining included (None: unknown).
    """

    seed: int
    checkpoint: str
    env_steps: int | None = None
    wall_s: float | None = None


def build_agent(cls: type, spec: str, checkpoint: str | None = None, suite: str | None = None):
    """An agent of class ``cls`` (named ``spec`` in messages) as the harness builds one: the
    class's ``for_suite(suite, checkpoint)`` where it has one and a suite is given, else
    ``cls()`` with ``load(checkpoint)`` if a checkpoint is given. The class is not checked
    against the suite here (``objsearch.eval.registry.check_supports`` does that first)."""
    if suite is not None:
        factory = getattr(cls, "for_suite", None)
        if callable(factory):
            return factory(suite, checkpoint)
    agent = cls()
    if checkpoint is not None:
        if not callable(getattr(agent, "load", None)):
            raise UserError(f"agent {spec!r} takes no checkpoint (it has no load(path) method)")
        agent.load(checkpoint)
    return agent


@runtime_checkable
class Agent(Protocol):
    """The protocol an evaluated agent follows: ``reset(task)`` at each episode's start, then ``act``."""

    def reset(self, task: AgentTask) -> None:
        """Begin a new episode of ``task``; nothing of the previous episode may carry over."""
        ...

    def act(self, observation: Any) -> Any:
        """The action for ``observation`` (one step)."""
        ...


class OneSlotBatch:
    """Mixin for an agent that has the batched protocol: ``reset`` and ``act`` play one
    episode as a batch of one slot, so the single-episode form is the batched code."""

    def reset(self, task: AgentTask) -> None:
        """Begin ``task`` as the only slot of a batch of one."""
        self.start_batch(1)
        self.reset_batch({0: task})

    def act(self, observation: Any) -> Any:
        """The action of the one slot for ``observation``."""
        return self.act_batch({0: observation})[0]


def is_batched(agent) -> bool:
    """Whether ``agent`` has the batched protocol (``start_batch``, ``reset_batch``, ``act_batch``),
    defined no higher in its class hierarchy than its ``reset`` and ``act``: a subclass that
    overrides ``act`` but inherits ``act_batch`` is played one instance per slot, so its
    ``act`` is what runs."""
    if not all(callable(getattr(agent, name, None)) for name in ("start_batch", "reset_batch", "act_batch")):
        return False
    mro = type(agent).__mro__

    def definer(name: str) -> type | None:
        return next((k for k in mro if name in k.__dict__), None)

    return all(
        definer(single) is None or issubclass(definer(batch), definer(single))
        for single, batch in (("act", "act_batch"), ("reset", "reset_batch"))
    )
