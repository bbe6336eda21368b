"""``objsearch train`` in a subprocess with tiny budgets: files, resume, exact continuation,
and the trained checkpoint through the evaluation harness."""

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch

from objsearch.eval.runner import EvalConfig, evaluate

TINY = [
    "--set",
    "pretrain_episodes=24",
    "--set",
    "num_envs=8",
    "--set",
    "learning_starts=64",
    "--set",
    "log_every=8",
    "--set",
    "checkpoint_every=8",
    "--set",
    "batch_size=16",
    "--set",
    "update_every=4",
    "--quiet",
]


def train(out: Path, episodes: int, *extra: str, agent: str = "hrl_grg") -> subprocess.CompletedProcess:
    cmd = [
        sys.executable,
        "-m",
        "objsearch.cli",
        "train",
        "--agent",
        agent,
        "--episodes",
        str(episodes),
        "--seed",
        "3",
        "--out",
        str(out),
        *TINY,
        *extra,
    ]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    root = tmp_path_factory.mktemp("train")
    straight = train(root / "straight", 16)
    first = train(root / "resumed", 8)
    second = train(root / "resumed", 16)
    return root, straight, first, second


def test_train_writes_its_files(runs):
    root, straight, _, _ = runs
    assert straight.returncode == 0, straight.stderr
    out = root / "straight"
    for name in ("config.json", "command.txt", "policy.pt", "grg.npz", "state.pt", "log.csv", "pretrain/policy.pt"):
        assert (out / name).exists(), name
    config = json.loads((out / "config.json").read_text())
    assert config["method"] == "hrl_grg" and config["seed"] == 3 and config["num_envs"] == 8
    rows = list(csv.DictReader((out / "log.csv").open()))
    assert rows and {"episodes", "success_rate", "loss_low", "loss_high"} <= set(rows[0])
    assert int(rows[-1]["episodes"]) >= 16
    assert "train" in (out / "command.txt").read_text()


def test_resume_continues_exactly(runs):
    root, straight, first, second = runs
    assert first.returncode == 0 and second.returncode == 0, first.stderr + second.stderr
    a = torch.load(root / "straight" / "policy.pt", weights_only=True)
    b = torch.load(root / "resumed" / "policy.pt", weights_only=True)
    for part in ("low", "high"):
        for key in a[part]:
            torch.testing.assert_close(a[part][key], b[part][key], rtol=0, atol=0)
    ga, gb = (np.load(root / run / "grg.npz")["counts"] for run in ("straight", "resumed"))
    np.testing.assert_array_equal(ga, gb)
    assert (root / "straight" / "log.csv").read_text().split("\n")[1:] != []
    rows_a = [r["episodes"] for r in csv.DictReader((root / "straight" / "log.csv").open())]
    rows_b = [r["episodes"] for r in csv.DictReader((root / "resumed" / "log.csv").open())]
    assert rows_a == rows_b


def test_changed_config_is_refused(runs):
    root = runs[0]
    bad = train(root / "straight", 16, "--set", "lr=0.5")
    assert bad.returncode == 2 and "another config" in bad.stderr


def test_bad_override_and_untrainable_agent(tmp_path):
    bad = train(tmp_path / "x", 4, "--set", "no_such_field=1")
    assert bad.returncode == 2 and "unknown config field" in bad.stderr
    bad = train(tmp_path / "y", 4, agent="random")
    assert bad.returncode == 2 and "cannot be trained" in bad.stderr


def test_a_suite_the_agent_cannot_play_is_refused_before_training(tmp_path):
    # an ObjectNav suite needs STOP, which the learned agents lack; a house agent cannot train in the grid world
    for agent, suite, reason in [
        ("a3c", "house-gen-v2-objectnav", "plays the paper protocol, not the objectnav protocol of suite 'house-gen"),
        ("a3c", "gridworld", "runs in the house world"),
    ]:
        out = tmp_path / agent / suite
        bad = train(out, 4, "--suite", suite, agent=agent)
        assert bad.returncode == 2 and reason in bad.stderr, bad.stderr
        assert not out.exists()


def test_trained_checkpoint_through_the_harness(runs, tmp_path):
    from objsearch.gridworld.dataset import DATA_DIR

    root = runs[0]
    tasks = tmp_path / "few.jsonl"
    tasks.write_text("\n".join((DATA_DIR / "tasks" / "unseen-goals.jsonl").read_text().splitlines()[:10]) + "\n")
    config = EvalConfig(
        agent="hrl_grg",
        seeds=(1,),
        checkpoint=str(root / "straight"),
        suite_config={"maps": str(DATA_DIR / "test"), "tasks": str(tasks)},
    )
    assert evaluate(config, progress=False)["splits"]["few"]["episodes"] == 10


def test_ctrl_c_checkpoints_and_exits_130(tmp_path):
    import signal
    import time

    out = tmp_path / "interrupted"
    cmd = [
        sys.executable,
        "-m",
        "objsearch.cli",
        "train",
        "--agent",
        "dqn",
        "--episodes",
        "100000",
        "--seed",
        "3",
        "--out",
        str(out),
        *TINY,
    ]
    proc = subprocess.Popen(
        cmd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=dict(os.environ, OMP_NUM_THREADS="1"),
        preexec_fn=lambda: signal.signal(
            signal.SIGINT, signal.SIG_DFL
        ),  # as in a terminal (not a background job's SIG_IGN)
    )
    try:
        deadline = time.monotonic() + 120
        while not (out / "state.pt").exists():  # the first checkpoint: training is under way
            assert proc.poll() is None and time.monotonic() < deadline, (
                proc.stderr.read() if proc.poll() is not None else "timeout"
            )
            time.sleep(0.2)
        proc.send_signal(signal.SIGINT)
        _, stderr = proc.communicate(timeout=120)
    finally:
        proc.kill()
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    rows = list(csv.DictReader(open(out / "log.csv")))
    state = torch.load(out / "state.pt", weights_only=False)
    assert rows and state, "the interrupted run left a resumable checkpoint"


def test_house_training_cli_writes_a_checkpoint_that_resumes_and_evaluates(tmp_path, cache_dir):
    tiny = [
        "--set",
        "pretrain_steps=1000",
        "--set",
        "num_envs=4",
        "--set",
        "log_every=500",
        "--set",
        "checkpoint_every=500",
        "--set",
        "learning_starts=100",
        "--set",
        "update_every=8",
        "--quiet",
    ]
    env = dict(os.environ, OMP_NUM_THREADS="1", OBJSEARCH_CACHE=cache_dir)

    def house_train(steps: int):
        cmd = [
            sys.executable,
            "-m",
            "objsearch.cli",
            "train",
            "--agent",
            "hrl_grg",
            "--suite",
            "house-single",
            "--steps",
            str(steps),
            "--out",
            str(tmp_path / "run"),
            *tiny,
        ]
        return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)

    first = house_train(1000)
    assert first.returncode == 0, first.stderr
    run = tmp_path / "run"
    for name in ("policy.pt", "grg.npz", "state.pt", "log.csv", "config.json", "command.txt", "pretrain/policy.pt"):
        assert (run / name).exists(), name
    assert json.loads((run / "config.json").read_text())["suite"] == "house-single"
    assert "--suite house-single" in (run / "command.txt").read_text()
    second = house_train(2000)  # resumes from state.pt
    assert second.returncode == 0, second.stderr
    rows = list(csv.DictReader(open(run / "log.csv")))
    assert [int(r["env_steps"]) for r in rows] == [500, 1000, 1500, 2000]
    wrong = subprocess.run(
        [
            sys.executable,
            "-m",
            "objsearch.cli",
            "train",
            "--agent",
            "hrl_grg",
            "--suite",
            "house-single",
            "--episodes",
            "5",
            "--out",
            str(tmp_path / "x"),
            "--quiet",
        ],
        capture_output=True,
        text=True,
        env=env,
    )
    assert wrong.returncode == 2 and "pass --steps" in wrong.stderr
    results = evaluate(
        EvalConfig(
            agent="hrl_grg",
            suite="house-single",
            splits=("seen-goals",),
            seeds=(1,),
            checkpoint=str(run),
            suite_config={"mode": "cached", "cache_dir": cache_dir, "max_steps": 20},
        ),
        progress=False,
        batch=16,
    )
    assert not any("error" in r for r in results["episodes"])
