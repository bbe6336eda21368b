"""The grid-world agents' checkpoint format: the files of a training run's folder and the
evaluable policy among them. Training (``gridworld.train``) writes it, the agents
(``gridworld.agent``) read it, so evaluating never imports the trainer.

A run's folder holds ``config.json`` (the ``GridAgentConfig``), ``command.txt``, ``log.csv``,
``state.pt`` (everything needed to resume) and the evaluable policy: ``policy.pt``, a
weights-only torch file (``objsearch.torchfile``) of ``{"config": the config's JSON,
"num_goals": int, "low": state dict, "high": state dict or None}``, with ``grg.npz`` beside
it for the agents that keep a goals relational graph. The shipped checkpoints
(``agents/checkpoints/gridworld/<agent>/``) are such folders.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.policy import GridPolicy

POLICY_FILE, STATE_FILE, CONFIG_FILE, LOG_FILE, GRG_FILE = "policy.pt", "state.pt", "config.json", "log.csv", "grg.npz"
POLICY_EXPECTED = "a grid-world policy.pt written by objsearch train"


def save_policy(policy: GridPolicy, out: Path) -> None:
    """The evaluable policy: ``policy.pt`` (network weights and config) and ``grg.npz``."""
    state = {
        "config": policy.config.to_json(),
        "num_goals": policy.num_goals,
        "low": policy.low.state_dict(),
        "high": policy.high.state_dict() if policy.high is not None else None,
    }
    torchfile.save(out / POLICY_FILE, state)
    if policy.grg is not None:
        policy.grg.save(out / GRG_FILE)


def load_policy_file(path: Path) -> dict:
    """The contents of a ``policy.pt``; a file that is not one is a ``UserError``."""
    state = torchfile.load(path, POLICY_EXPECTED)
    if not isinstance(state, dict) or not {"config", "num_goals", "low"} <= set(state):
        raise UserError(
            f"checkpoint {path} is not a grid-world policy.pt (no config/low weights); "
            "pass one written by objsearch train --suite gridworld"
        )
    return state


def load_policy(
    path: str | os.PathLike, check: Callable[[GridAgentConfig, Path], None] | None = None
) -> tuple[GridPolicy, list[Path]]:
    """The policy of ``policy.pt`` at ``path`` (or in the run folder ``path``), with the GRG of
    ``grg.npz`` beside it if its method keeps one, and the files read (for their digest).

    ``check(config, path)`` sees the stored config before any network is built, to refuse
    one trained for another agent. Contents that do not fit are a ``UserError``."""
    from objsearch_agents.core.grg import GoalsRelationalGraph

    path = torchfile.policy_path(path, POLICY_FILE)
    state = load_policy_file(path)
    files = [path]
    with torchfile.fitting(path, POLICY_EXPECTED):
        saved = GridAgentConfig.from_json(state["config"], f"checkpoint {path}")
        if check is not None:
            check(saved, path)
        policy = GridPolicy(saved, num_goals=int(state["num_goals"]))
        policy.low.load_state_dict(state["low"])
        if policy.high is not None:
            policy.high.load_state_dict(state["high"])
    if policy.grg is not None:
        files.append(path.parent / GRG_FILE)
        policy.grg = GoalsRelationalGraph.load(files[-1])
        policy.refresh_plans()
    return policy, files
