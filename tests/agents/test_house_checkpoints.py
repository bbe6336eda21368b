"""The house agents' checkpoints: every shipped run loads and says how it was made, other
methods' and suites' checkpoints are refused with the command that makes the right one
(batched evaluation gives the sequential records: ``tests/eval/test_lockstep.py``)."""

from dataclasses import replace
from pathlib import Path

import pytest
import torch

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch.sim.camera import AGENT_CAMERA, CameraMismatchError
from objsearch_agents.house.agent import CHECKPOINTS
from objsearch_agents.house.checkpoint import save_policy
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.policy import HousePolicy


def test_house_agents_refuse_other_checkpoints_and_suites(tmp_path):
    from objsearch.eval.registry import make_agent

    with pytest.raises(UserError, match="runs in the house world"):
        make_agent("a3c", suite="gridworld")
    policy = HousePolicy(replace(HouseAgentConfig(), method="dqn", suite="house-multi"))
    save_policy(policy, tmp_path)
    with pytest.raises(UserError, match="trained as dqn, not hrl_grg"):
        make_agent("hrl_grg", str(tmp_path), suite="house-multi")
    with pytest.raises(UserError, match="trained on suite house-multi"):
        make_agent("dqn", str(tmp_path), suite="house-single")
    assert make_agent("dqn", str(tmp_path), suite="house-multi").policy.config.method == "dqn"
    state = torch.load(tmp_path / "policy.pt", weights_only=True)
    assert state["camera"] == AGENT_CAMERA.to_json()  # policies record the camera their agent sees
    state["camera"] = {**AGENT_CAMERA.to_json(), "width": 128}
    torchfile.save(tmp_path / "policy.pt", state)
    with pytest.raises(
        CameraMismatchError,
        match=r"house policy checkpoint .*policy.pt was made for camera \[width=128 .*"
        r"the agent camera \(objsearch.sim.camera.AGENT_CAMERA\) is \[width=64 .*differ in width\); retrain it "
        r"\(objsearch train --agent dqn --suite house-multi\)",
    ):
        make_agent("dqn", str(tmp_path), suite="house-multi")
    del state["camera"]
    torchfile.save(tmp_path / "policy.pt", state)
    with pytest.raises(CameraMismatchError, match="camera record is missing, incomplete or unreadable"):
        make_agent("dqn", str(tmp_path), suite="house-multi")
    (tmp_path / "policy.pt").write_text("not a checkpoint")
    with pytest.raises(UserError, match="policy.pt does not match its digest"):
        make_agent("dqn", str(tmp_path), suite="house-multi")
    (tmp_path / "SHA256SUMS").unlink()  # a file with no recorded digest is read, and refused for what it holds
    with pytest.raises(UserError, match="cannot read checkpoint"):
        make_agent("dqn", str(tmp_path), suite="house-multi")
    assert not (CHECKPOINTS / "house-gen" / "hrl_grg_no_relation").exists()
    with pytest.raises(UserError, match="objsearch train --agent hrl_grg_no_relation --suite house-gen"):
        make_agent("hrl_grg_no_relation", suite="house-gen")


def test_every_shipped_house_checkpoint_loads():
    """Every shipped run loads under its name, and says how it was made: the agent's folder is
    its seed-0 run (loaded by default), ``seed<N>/`` the same recipe with ``--seed N``."""
    from objsearch.eval.registry import make_agent, resolve_agent

    shipped = sorted(CHECKPOINTS.glob("house-*/*/policy.pt"))
    assert len(shipped) >= 13
    for path in shipped:
        suite, name = path.parent.parent.name, path.parent.name
        agent = make_agent(name, suite=suite)
        assert agent.loaded_from == str(path) and agent.policy.config.name == name
        runs = resolve_agent(name).training_runs(suite)
        assert runs[0].checkpoint == str(path.parent) and runs[0].seed == 0
        recipe = (path.parent / "command.txt").read_text().split(" --seed ")[0].split(" --quiet")[0]
        assert recipe.startswith(f"objsearch train --agent {name} --suite {suite}")
        for run in runs:
            folder = Path(run.checkpoint)
            assert make_agent(name, run.checkpoint, suite=suite).policy.config.seed == run.seed
            assert {"SHA256SUMS", "command.txt", "config.json", "log.csv"} <= {f.name for f in folder.iterdir()}
            assert run.env_steps and run.wall_s  # its cost, its starting checkpoints' included
            if run.seed:
                assert folder.name == f"seed{run.seed}" and f"--seed {run.seed}" in (folder / "command.txt").read_text()


def test_the_explorer_extension_has_its_own_name(tmp_path):
    """The paper's hierarchical methods have no explorer in their back-up node: a run with
    one is ``<method>_explorer``, under that name only."""
    from objsearch.eval.registry import make_agent
    from objsearch_agents.house.methods import HRLGRGExplorerHouseAgent, HRLGRGHouseAgent

    with pytest.raises(UserError, match="train hrl_grg_explorer, not hrl_grg .*pass --agent hrl_grg_explorer"):
        HRLGRGHouseAgent.train(suite="house-single", out=tmp_path, overrides={"explorer": "a3c/policy.pt"})
    with pytest.raises(UserError, match="train hrl_grg, not hrl_grg_explorer"):
        HRLGRGExplorerHouseAgent.train(suite="house-single", out=tmp_path, overrides={"explorer": ""})
    explorer = CHECKPOINTS / "house-single" / "hrl_grg_explorer"
    with pytest.raises(UserError, match="trained as hrl_grg_explorer, not hrl_grg; pick --agent hrl_grg_explorer"):
        make_agent("hrl_grg", str(explorer), suite="house-single")
    assert not list(tmp_path.iterdir())  # refused before anything was written
