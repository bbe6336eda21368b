"""The house agents' checkpoint format: the files of a training run's folder and the
evaluable policy among them. Training (``house.train``) writes it, the agents
(``house.agent``) read it, so evaluating never imports the trainer.

A run's folder holds ``config.json`` (the ``HouseAgentConfig``), ``command.txt``,
``log.csv``, ``state.pt`` (everything needed to resume) and the evaluable policy:
``policy.pt``, a weights-only torch file (``objsearch.torchfile``) of ``{"kind":
"objsearch-house-policy", "config": the config's JSON, "camera": the agent camera's JSON,
"ac", "q", "explore": state dicts or None}``, with ``grg.npz`` beside it for HRL-GRG. A policy
trained on predicted observations also holds ``"perception"``: the key of the perception
network whose predictions it learned from (``objsearch.perception.inference.checkpoint_key``).
The shipped checkpoints (``agents/checkpoints/<suite>/<agent>/``) are such folders.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, check_camera
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.policy import HousePolicy

POLICY_FILE, STATE_FILE, CONFIG_FILE, LOG_FILE, GRG_FILE = "policy.pt", "state.pt", "config.json", "log.csv", "grg.npz"
POLICY_KIND = "objsearch-house-policy"


def load_checkpoint_file(path: Path) -> dict:
    """A ``policy.pt`` or ``state.pt`` (tensors and plain data only: nothing is executed)."""
    return torchfile.load(path, "a file written by objsearch train")


def save_policy(policy: HousePolicy, out: Path, perception_key: str | None = None) -> None:
    """The evaluable policy: ``policy.pt`` (config, camera and network weights, and
    ``perception_key`` if it trained on a perception network's predictions) and ``grg.npz``."""
    state = {
        "kind": POLICY_KIND,
        "config": policy.config.to_json(),
        "camera": AGENT_CAMERA.to_json(),
        "ac": policy.ac.state_dict() if policy.ac is not None else None,
        "q": policy.q.state_dict() if policy.q is not None else None,
        "explore": policy.explore.state_dict() if policy.explore is not None else None,
    }
    if perception_key is not None:
        state["perception"] = perception_key
    torchfile.save(out / POLICY_FILE, state)
    if policy.grg is not None:
        policy.grg.save(out / GRG_FILE)


def load_policy(
    path: str | os.PathLike, check: Callable[[HouseAgentConfig, Path], None] | None = None
) -> tuple[HousePolicy, list[Path]]:
    """The policy of ``policy.pt`` at ``path`` (or in the run folder ``path``), with the GRG of
    ``grg.npz`` beside it for HRL-GRG, and the files read (for their digest).

    ``check(config, path)`` sees the stored config before any network is built, to refuse
    one trained for another agent or suite. A file of another kind, another camera or
    contents that do not fit are a ``UserError``."""
    from objsearch_agents.core.grg import GoalsRelationalGraph

    path = torchfile.policy_path(path, POLICY_FILE)
    state = load_checkpoint_file(path)
    if not isinstance(state, dict) or state.get("kind") != POLICY_KIND:
        raise UserError(
            f"checkpoint {path} is not a house agent's policy.pt (a grid-world or other file?); "
            "pass one written by objsearch train --suite house-..."
        )
    files = [path]
    with torchfile.fitting(path, "a house agent's policy.pt written by objsearch train"):
        saved = HouseAgentConfig.from_json(state["config"], f"checkpoint {path}")
        if check is not None:
            check(saved, path)
        check_camera(
            state.get("camera"),
            AGENT_CAMERA,
            source=f"house policy checkpoint {path}",
            expected_name=AGENT_CAMERA_NAME,
            fix=f"retrain it (objsearch train --agent {saved.name} --suite {saved.suite}) or pass a checkpoint "
            "trained with that camera",
        )
        policy = HousePolicy(saved)
        policy.perception_key = state.get("perception")
        if policy.ac is not None:
            policy.ac.load_state_dict(state["ac"])
        if policy.q is not None:
            policy.q.load_state_dict(state["q"])
        if policy.explore is not None:
            policy.explore.load_state_dict(state["explore"])
    if policy.grg is not None:
        files.append(path.parent / GRG_FILE)
        policy.grg = GoalsRelationalGraph.load(files[-1])
        policy.refresh_plans()
    return policy, files
