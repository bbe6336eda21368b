"""The grid-world learning agents behind the evaluation protocol, and their ``train`` hook.

``GridAgent`` wraps ``GridPolicy`` with N = 1: ``reset(task)`` starts the option state and
takes ``task.rng`` as the only source of randomness; ``act(obs)`` first ends or continues
the current option given the new observation, then picks a sub-goal if needed and an
action. Evaluation explores with ``eval_epsilon`` (0.1, as the authors evaluated) at both
levels unless the agent is built with ``epsilon=0`` (the ``...Greedy`` classes:
``--agent objsearch_agents.hrl_grg:HRLGRGGreedyAgent``). Inference is deterministic.

``objsearch train`` finds the agent class through the registry and calls its classmethod
``train(...)`` (see ``objsearch/train.py``); the class's ``config`` fixes the method and
its defaults.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import torch

from objsearch.errors import UserError
from objsearch.eval.agent import AgentTask
from objsearch_agents.gridworld_config import GridAgentConfig
from objsearch_agents.gridworld_policy import GridPolicy

TRAIN_SUITES = ("gridworld",)
# Shipped checkpoints, one folder per agent (policy.pt, grg.npz, config.json, log.csv and
# README.md with the command that trained it); an agent loads its own by default.
CHECKPOINTS = Path(__file__).parent / "checkpoints" / "gridworld"


class GridAgent:
    """A grid-world agent from a ``GridAgentConfig`` (subclasses set ``config``)."""

    config = GridAgentConfig()
    train_suites = TRAIN_SUITES
    checkpoint_name: str | None = None
    """Folder of the shipped checkpoint under ``CHECKPOINTS`` (None: none)."""

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
        path = CHECKPOINTS / cls.checkpoint_name / "policy.pt"
        return path if path.exists() else None

    def _build(self, config: GridAgentConfig, num_goals: int = 16) -> None:
        self.policy = GridPolicy(config, num_goals=num_goals)
        self.epsilon = config.eval_epsilon if self._epsilon_override is None else float(self._epsilon_override)

    # -- checkpoints ------------------------------------------------------------------------
    def load(self, path: str | os.PathLike) -> None:
        """Load ``policy.pt`` (or a run directory holding it) and ``grg.npz`` beside it."""
        from objsearch_agents.grg import GoalsRelationalGraph
        from objsearch_agents.gridworld_train import GRG_FILE, POLICY_FILE, load_policy_file

        path = Path(path)
        if path.is_dir():
            path = path / POLICY_FILE
        if not path.exists():
            raise UserError(f"checkpoint {path} does not exist; pass a policy.pt or a training run directory")
        state = load_policy_file(path)
        saved = GridAgentConfig.from_json(state["config"])
        mine = self.config
        if (saved.method, saved.relation, saved.termination, saved.high_level) != (mine.method, mine.relation, mine.termination, mine.high_level):
            raise UserError(f"checkpoint {path} was trained as {describe(saved)}, not {describe(mine)}; pick the matching --agent")
        self._build(saved, int(state["num_goals"]))
        self.policy.low.load_state_dict(state["low"])
        if self.policy.high is not None:
            self.policy.high.load_state_dict(state["high"])
        if self.policy.grg is not None:
            self.policy.grg = GoalsRelationalGraph.load(path.parent / GRG_FILE)
            self.policy.refresh_plans()
        self.loaded_from = str(path)

    # -- the protocol -------------------------------------------------------------------------
    def reset(self, task: AgentTask) -> None:
        self._rng = task.rng
        self.policy.start(1)
        self.policy.begin_episodes(np.array([0]), np.array([int(task.goal)]))
        self._first = True

    def act(self, observation) -> int:
        p = self.policy
        image = np.asarray(observation["image"], dtype=np.uint8)[None]
        if not self._first:
            p.advance(image, np.zeros(1, dtype=bool), count=False)
        self._first = False
        eps = np.array([self.epsilon])
        if p.config.hierarchical:
            p.select_subgoals(image, eps, self._rng)
        actions, _ = p.actions(image, eps, self._rng)
        return int(actions[0])

    # -- training ----------------------------------------------------------------------------
    @classmethod
    def train(cls, *, suite: str, out: str | os.PathLike, episodes: int | None = None, seed: int = 0,
              overrides: dict[str, str] | None = None, fresh: bool = False, progress: bool = True,
              command: str | None = None) -> dict:
        """Train this agent (the ``objsearch train`` hook). Returns a summary dict."""
        from dataclasses import replace

        from objsearch_agents.gridworld_train import train

        if suite not in cls.train_suites:
            raise UserError(f"agent trains on suites {', '.join(cls.train_suites)}, not {suite!r}")
        config = replace(cls.config, seed=int(seed)).with_overrides(overrides or {})
        if episodes is not None:
            config = replace(config, episodes=int(episodes))
        run = train(config, out, progress=progress, fresh=fresh, command=command)
        return {"out": str(out), "finished": run.counters["finished"], "env_steps": run.counters["env_steps"],
                "interrupted": run.interrupted, "wall_s": run.counters["wall_s"]}


def describe(config: GridAgentConfig) -> str:
    if config.method != "hrl_grg":
        return config.method
    off = [n for n in ("relation", "termination", "high_level") if not getattr(config, n)]
    return "hrl_grg" + "".join(f"_no_{n}" for n in off)
