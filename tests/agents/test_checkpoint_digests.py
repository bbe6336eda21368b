"""Weights are verified before they are trusted: shipped and written checkpoints carry
their sha256 in SHA256SUMS, damaged or wrong files are refused with one line, and results
name the exact weights they used."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import torch

from objsearch import digests, torchfile
from objsearch.errors import UserError
from objsearch.eval.registry import make_agent
from objsearch.perception.inference import SHIPPED_CHECKPOINT, load_checkpoint
from objsearch_agents.house.agent import CHECKPOINTS

SHIPPED_FOLDERS = sorted(
    {p.parent for p in [*CHECKPOINTS.rglob("*.pt"), *CHECKPOINTS.rglob("*.npz")]} | {SHIPPED_CHECKPOINT.parent}
)


def flip_byte(path: Path, at: float = 0.5) -> None:
    data = bytearray(path.read_bytes())
    data[int(len(data) * at)] ^= 0xFF
    path.write_bytes(bytes(data))


def test_every_shipped_checkpoint_file_is_listed_in_its_folders_sha256sums_and_matches():
    assert len(SHIPPED_FOLDERS) >= 20
    for folder in SHIPPED_FOLDERS:
        files = sorted(p.name for p in folder.iterdir() if p.suffix in (".pt", ".npz"))
        sums = digests.recorded(folder)
        assert sorted(sums) == files, folder
        for name in files:
            assert digests.sha256_file(folder / name) == sums[name], folder / name


@pytest.mark.parametrize(
    "suite, agent, damaged",
    [
        ("gridworld", "hrl_grg", "policy.pt"),
        ("gridworld", "hrl_grg", "grg.npz"),
        ("house-single", "hrl_grg", "policy.pt"),
        ("house-single", "a3c", "policy.pt"),
    ],
)
def test_flipped_bytes_in_shipped_weights_are_refused(tmp_path, suite, agent, damaged):
    copy = tmp_path / agent
    shutil.copytree(CHECKPOINTS / suite / agent, copy)
    assert make_agent(agent, str(copy), suite=suite).weights_sha256  # the intact copy loads
    flip_byte(copy / damaged)
    with pytest.raises(UserError, match=f"{damaged} does not match its digest in .*SHA256SUMS"):
        make_agent(agent, str(copy), suite=suite)


def test_the_cli_refuses_damaged_weights_with_one_line_and_exit_2(tmp_path):
    copy = tmp_path / "hrl_grg"
    shutil.copytree(CHECKPOINTS / "gridworld" / "hrl_grg", copy)
    flip_byte(copy / "policy.pt", 0.9)
    out = subprocess.run(
        [
            str(Path(sys.executable).parent / "objsearch-eval"),
            "--agent",
            "hrl_grg",
            "--suite",
            "gridworld",
            "--checkpoint",
            str(copy),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr
    assert "policy.pt does not match its digest" in out.stderr and "restore it" in out.stderr


def test_written_files_are_recorded_and_a_flipped_state_is_not_resumed(tmp_path):
    state = {"config": {"a": 1}, "weights": torch.arange(1000, dtype=torch.float32)}
    torchfile.save(tmp_path / "state.pt", state)
    assert digests.recorded(tmp_path) == {"state.pt": digests.sha256_file(tmp_path / "state.pt")}
    assert torch.equal(torchfile.load(tmp_path / "state.pt", "a state")["weights"], state["weights"])
    flip_byte(tmp_path / "state.pt", 0.8)
    with pytest.raises(UserError, match="state.pt does not match its digest"):
        torchfile.load(tmp_path / "state.pt", "a state")
    (tmp_path / digests.SUMS).write_text("not a sums line\n")
    with pytest.raises(UserError, match="SHA256SUMS line 1"):
        torchfile.load(tmp_path / "state.pt", "a state")


def test_a_damaged_perception_checkpoint_is_refused(tmp_path):
    shutil.copytree(SHIPPED_CHECKPOINT.parent, tmp_path / "checkpoint")
    copy = tmp_path / "checkpoint" / SHIPPED_CHECKPOINT.name
    assert load_checkpoint(copy)["version"]
    flip_byte(copy)
    with pytest.raises(UserError, match="model.pt does not match its digest"):
        load_checkpoint(copy)


def test_a_checkpoint_of_the_right_kind_with_wrong_contents_is_refused(tmp_path):
    state = torchfile.load(CHECKPOINTS / "gridworld" / "dqn" / "policy.pt", "a policy")
    first = next(iter(state["low"]))
    state["low"][first] = torch.zeros(3, 3)  # weights of another shape
    torchfile.save(tmp_path / "grid" / "policy.pt", state)
    with pytest.raises(UserError, match="does not hold what it should.*expected a grid-world policy.pt"):
        make_agent("dqn", str(tmp_path / "grid"), suite="gridworld")
    state = torchfile.load(CHECKPOINTS / "house-single" / "a3c" / "policy.pt", "a policy")
    del state["ac"]
    torchfile.save(tmp_path / "house" / "policy.pt", state)
    with pytest.raises(UserError, match="does not hold what it should.*KeyError"):
        make_agent("a3c", str(tmp_path / "house"), suite="house-single")


def test_an_agent_names_the_weights_it_loaded():
    agent = make_agent("hrl_grg", suite="gridworld")
    folder = CHECKPOINTS / "gridworld" / "hrl_grg"
    assert agent.weights_sha256 == digests.of_files([folder / "policy.pt", folder / "grg.npz"])
    assert make_agent("dqn", suite="gridworld").weights_sha256 != agent.weights_sha256


def test_results_name_the_weights_and_verify_refuses_other_weights(tmp_path):
    from objsearch.eval.runner import EvalConfig, evaluate
    from objsearch.leaderboard.validate import verify_submission

    config = EvalConfig(agent="dqn", suite="gridworld", splits=("seen-goals",), seeds=(1,))
    results = evaluate(config, progress=False, batch=64)
    assert results["config"]["weights_sha256"] == make_agent("dqn", suite="gridworld").weights_sha256
    results["config"]["weights_sha256"] = "0" * 64
    results["partial"] = True  # one split and seed: a partial submission
    assert any("used weights 000000000000" in p for p in verify_submission(results, k=2))


@pytest.mark.parametrize("folder", SHIPPED_FOLDERS, ids=lambda p: str(p.relative_to(p.parents[2])))
def test_shipped_recipes_name_no_path_of_the_training_machine(folder):
    """A shipped command.txt or config.json reruns from a fresh clone: paths in it are
    relative to the repository, never the training machine's (/root/..., /home/...)."""
    import re

    for name in ("command.txt", "config.json"):
        if (folder / name).exists():
            text = (folder / name).read_text()
            assert not re.search(r"(^|[\s\"'=])/(root|home|tmp|work|Users)/", text), f"{folder / name}: {text}"


def test_a_missing_checkpoint_names_the_folder_it_was_looked_for_in(monkeypatch, tmp_path):
    from objsearch_agents.house.agent import CHECKPOINTS_ENV

    monkeypatch.setenv(CHECKPOINTS_ENV, str(tmp_path / "nowhere"))
    with pytest.raises(UserError, match=rf"no a3c checkpoint is in \${CHECKPOINTS_ENV} \(.*nowhere, no such folder\)"):
        make_agent("a3c", suite="house-single")
    monkeypatch.setenv(CHECKPOINTS_ENV, str(tmp_path))  # a folder, without the run
    with pytest.raises(UserError, match=rf"is in \${CHECKPOINTS_ENV} \({tmp_path}\) for suite house-single"):
        make_agent("a3c", suite="house-single")
