"""The grid-world learning agents behind the evaluation protocol, and their ``train`` hook.

``GridAgent`` wraps ``GridPolicy``: ``reset(task)`` starts the option state and takes
``task.rng`` as the only source of randomness; ``act(obs)`` first ends or continues the
current option given the new observation, then picks a sub-goal if needed and an action.
The batched form (``start_batch``/``reset_batch``/``act_batch``, ``objsearch-eval --batch``)
runs N episodes through the same code, one row each, each drawing from its own Generator;
``reset``/``act`` are it with one slot. Evaluation explores with ``eval_epsilon`` (0.1, as the authors evaluated) at both
levels unless the agent is built with ``epsilon=0`` (the ``...Greedy`` classes:
``--agent objsearch_agents.hrl_grg:HRLGRGGreedyAgent``). Inference is deterministic.

``objsearch train`` finds the agent class through the registry and calls its classmethod
``train(...)`` (see ``objsearch/train.py``); the class's ``config`` fixes the method and
its defaults.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from objsearch import digests
from objsearch.errors import UserError
from objsearch.eval.agent import OneSlotBatch
from objsearch_agents.core.rows import RowRandom
from objsearch_agents.gridworld.checkpoint import POLICY_FILE, load_policy
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.policy import GridPolicy

TRAIN_SUITES = ("gridworld",)
# Shipped checkpoints, one folder per agent (policy.pt, grg.npz, config.json, log.csv and
# README.md with the command that trained it); an agent loads its own by default.
CHECKPOINTS = Path(__file__).parent.parent / "checkpoints" / "gridworld"


class GridAgent(OneSlotBatch):
    """A grid-world agent from a ``GridAgentConfig`` (subclasses set ``config``). A subclass
    that sets ``house`` (the same method's ``HouseAgent`` class) runs in the houses too:
    ``for_suite`` and ``train`` hand house suites to it."""

    config = GridAgentConfig()
    train_suites = TRAIN_SUITES
    checkpoint_name: str | None = None
    """Folder of the shipped checkpoint under ``CHECKPOINTS`` (None: none)."""
    house: type | None = None

    @classmethod
    def worlds(cls) -> tuple[str, ...]:
        """The worlds (``gridworld``, ``house``) whose suites this agent runs on."""
        return ("gridworld", "house") if cls.house is not None else ("gridworld",)

    @classmethod
    def protocols(cls) -> tuple[str, ...]:
        """The paper's only: no STOP action, here or in the house agent it hands house suites to."""
        return ("paper",)

    @classmethod
    def for_suite(cls, suite: str, checkpoint: str | os.PathLike | None = None):
        """The agent for ``suite``: this grid-world agent, or the house agent of the same method."""
        from objsearch.eval.suites import suite_world

        if suite_world(suite) == "house" and cls.house is not None:
            return cls.house.for_suite(suite, checkpoint)
        agent = cls()
        if checkpoint is not None:
            agent.load(checkpoint)
        return agent

    @classmethod
    def training_runs(cls, suite: str) -> list:
        """The house agent's training runs for a house suite (the grid world ships one run: none listed)."""
        from objsearch.eval.suites import suite_world

        if suite_world(suite) == "house" and cls.house is not None:
            return cls.house.training_runs(suite)
        return []

    def __init__(self, epsilon: float | None = None):
        self._epsilon_override = epsilon
        self._build(self.config)
        self.loaded_from: str | None = None
        default = self.default_checkpoint()
        if default is not None:
            self.load(default)

    @classmethod
    def default_checkpoint(cls) -> Path | None:
        """The shipped checkpoint this agent loads when given none, if there is one."""
        if cls.checkpoint_name is None:
            return None
        path = CHECKPOINTS / cls.checkpoint_name / POLICY_FILE
        return path if path.exists() else None

    def _build(self, config: GridAgentConfig, num_goals: int = 16) -> None:
        self._use(GridPolicy(config, num_goals=num_goals))

    def _use(self, policy: GridPolicy) -> None:
        self.policy = policy
        self.epsilon = policy.config.eval_epsilon if self._epsilon_override is None else float(self._epsilon_override)

    # -- checkpoints ------------------------------------------------------------------------
    def load(self, path: str | os.PathLike) -> None:
        """Load ``policy.pt`` (or a run directory holding it) and ``grg.npz`` beside it."""
        policy, files = load_policy(path, self._check_method)
        self._use(policy)
        self.loaded_from = str(files[0])
        self.weights_sha256 = digests.of_files(files)

    def _check_method(self, saved: GridAgentConfig, path: Path) -> None:
        """Refuse a checkpoint trained as another method or ablation than this agent's."""
        mine = self.config
        if (saved.method, saved.relation, saved.termination, saved.high_level) != (
            mine.method,
            mine.relation,
            mine.termination,
            mine.high_level,
        ):
            raise UserError(
                f"checkpoint {path} was trained as {saved.name}, not {mine.name}; pick the matching --agent"
            )

    # -- the protocol (one episode, or N in lockstep: the same code, OneSlotBatch) -----------
    def start_batch(self, num_slots: int) -> None:
        self._slots = int(num_slots)
        self.policy.start(self._slots)
        self._rngs = [np.random.default_rng(0)] * self._slots  # draws of an idle slot are thrown away

    def reset_batch(self, tasks: dict) -> None:
        slots = np.array(sorted(tasks), dtype=np.int64)
        self.policy.begin_episodes(slots, np.array([int(tasks[i].goal) for i in slots], np.int64))
        for i in slots:
            self._rngs[i] = tasks[i].rng

    def act_batch(self, observations: dict) -> dict:
        busy = sorted(observations)
        images = np.stack(
            [
                np.asarray(observations[i if i in observations else busy[0]]["image"], dtype=np.uint8)
                for i in range(self._slots)
            ]
        )
        p, rng = self.policy, RowRandom(self._rngs)
        p.advance(images, np.zeros(self._slots, dtype=bool), count=False)  # a no-op for slots on their first step
        eps = np.full(self._slots, self.epsilon)
        if p.config.hierarchical:
            p.select_subgoals(images, eps, rng)
        actions, _ = p.actions(images, eps, rng)
        return {i: int(actions[i]) for i in busy}

    # -- training ----------------------------------------------------------------------------
    @classmethod
    def train(
        cls,
        *,
        suite: str,
        out: str | os.PathLike,
        episodes: int | None = None,
        seed: int = 0,
        overrides: dict[str, str] | None = None,
        fresh: bool = False,
        progress: bool = True,
        command: str | None = None,
        steps: int | None = None,
    ) -> dict:
        """Train this agent (the ``objsearch train`` hook). Returns a summary dict."""
        from dataclasses import replace

        from objsearch.eval.suites import suite_world
        from objsearch_agents.gridworld.train import train

        if cls.house is not None and suite_world(suite) == "house":
            return cls.house.train(
                suite=suite,
                out=out,
                episodes=episodes,
                seed=seed,
                overrides=overrides,
                fresh=fresh,
                progress=progress,
                command=command,
                **({"steps": steps} if steps is not None else {}),
            )
        if steps is not None:
            raise UserError("grid-world agents train for a number of episodes: pass --episodes, not --steps")
        if suite not in cls.train_suites:
            raise UserError(f"agent trains on suites {', '.join(cls.train_suites)}, not {suite!r}")
        config = replace(cls.config, seed=int(seed)).with_overrides(overrides or {})
        if episodes is not None:
            config = replace(config, episodes=int(episodes))
        run = train(config, out, progress=progress, fresh=fresh, command=command)
        return {
            "out": str(out),
            "finished": run.counters["finished"],
            "env_steps": run.counters["env_steps"],
            "interrupted": run.interrupted,
            "wall_s": run.counters["wall_s"],
        }
