"""SIGTERM (how Slurm, Kubernetes, ``timeout`` and Ray stop jobs) is handled as Ctrl-C is:
what was done is saved, one line says what and how to resume, the exit status is 143 (130
for Ctrl-C), and nothing is left half-written. Real processes, real signals."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from objsearch.interrupt import Terminated, sigterm_as_interrupt

SLOW_AGENT = '''
import os, time
from objsearch_agents.baselines.oracle import OracleAgent

class Slow(OracleAgent):
    """The oracle, slowed down while SLOW_AGENT is set (the setting is not part of the run's config)."""
    def act(self, obs):
        if os.environ.get("SLOW_AGENT"):
            time.sleep(0.005)
        return super().act(obs)
'''


def start(args: list[str], cwd: Path, **env) -> subprocess.Popen:
    """``objsearch ARGS`` in its own process group (so a signal can go to the group, as
    ``timeout`` and Slurm send it), with SIGINT handled as in a terminal."""
    return subprocess.Popen(
        [sys.executable, "-m", "objsearch.cli", *args],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=dict(os.environ, OMP_NUM_THREADS="1", **env),
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def wait_for(proc: subprocess.Popen, ready, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not ready():
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            pytest.fail(f"never got under way: {proc.communicate()[1][-2000:]}")
        time.sleep(0.05)


def stop(proc: subprocess.Popen, signum: int, group: bool) -> str:
    """Send ``signum`` to the process (or its whole group) and return its stderr."""
    (os.killpg if group else os.kill)(proc.pid, signum)
    try:
        return proc.communicate(timeout=60)[1]
    finally:
        proc.kill()


def lines(path: Path) -> int:
    return len(path.read_text().splitlines()) if path.exists() else 0


@pytest.mark.parametrize(
    "signum, group, workers",
    [(signal.SIGTERM, True, 2), (signal.SIGINT, True, 2), (signal.SIGTERM, False, 1)],
    ids=["sigterm-group-workers2", "ctrl-c-group-workers2", "sigterm-process-batch"],
)
def test_an_interrupted_evaluation_keeps_its_episodes_says_so_and_resumes(tmp_path, signum, group, workers):
    (tmp_path / "slow.py").write_text(SLOW_AGENT)
    out = tmp_path / "r.json"
    partial = tmp_path / "r.json.partial.jsonl"
    args = ["eval", "--agent", "slow.py:Slow", "--suite", "gridworld", "--split", "seen-goals", "--seeds", "1"]
    args += ["--out", str(out)]
    proc = start(args + ["--workers", str(workers), "--batch", "1" if workers > 1 else "8"], tmp_path, SLOW_AGENT="1")
    wait_for(proc, lambda: lines(partial) > 1)
    stderr = stop(proc, signum, group)
    assert proc.returncode == 128 + signum, stderr
    assert "Traceback" not in stderr and "InvalidStateError" not in stderr, stderr
    kept = lines(partial) - 1
    last = stderr.strip().splitlines()[-1]
    by = "SIGTERM" if signum == signal.SIGTERM else "Ctrl-C"
    assert by in last and f"{kept} of 100 episodes saved in {partial}" in last and "rerun" in last, last
    assert not out.exists()
    if workers > 1:
        time.sleep(0.5)
        assert not [p for p in Path("/proc").glob("[0-9]*") if _is_worker_of(p, proc.pid)], "workers left running"

    rerun = subprocess.run(
        [sys.executable, "-m", "objsearch.cli", *args, "--quiet"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert rerun.returncode == 0, rerun.stderr
    assert f"resuming: {kept} of 100 episodes done in {partial}" in rerun.stderr
    results = json.loads(out.read_text())
    units = [(e["seed"], e["episode_id"]) for e in results["episodes"]]
    assert len(units) == len(set(units)) == 100 and not partial.exists()


def _is_worker_of(proc_dir: Path, parent: int) -> bool:
    try:
        return int((proc_dir / "stat").read_text().rsplit(")", 1)[1].split()[1]) == parent
    except (OSError, ValueError, IndexError):
        return False


def test_sigterm_during_grid_training_writes_a_checkpoint_and_exits_143(tmp_path):
    out = tmp_path / "run"
    args = ["train", "--agent", "dqn", "--episodes", "100000", "--seed", "3", "--out", str(out), "--quiet"]
    args += ["--set", "pretrain_episodes=0", "--set", "num_envs=8", "--set", "checkpoint_every=16"]
    proc = start(args, tmp_path)
    wait_for(proc, lambda: (out / "state.pt").exists(), timeout=120)
    stderr = stop(proc, signal.SIGTERM, group=True)
    assert proc.returncode == 143, stderr
    assert "Traceback" not in stderr
    last = stderr.strip().splitlines()[-1]
    assert f"interrupted by SIGTERM: checkpoint written to {out}; rerun the same command to resume" in last, last
    assert not list(out.rglob("*.tmp")), "a temp file was left"
    state = json.loads((out / "config.json").read_text())
    assert state  # the run's files are whole: its config reads back
    import torch

    assert torch.load(out / "state.pt", weights_only=False)["counters"]["finished"] > 0


def test_sigterm_during_generate_leaves_whole_houses_and_exits_143(tmp_path):
    out = tmp_path / "houses"
    proc = start(["generate", "--num", "200", "--no-preview", "--out", str(out)], tmp_path)
    wait_for(proc, lambda: len(list(out.glob("*/spec.json"))) >= 1)
    stderr = stop(proc, signal.SIGTERM, group=False)
    assert proc.returncode == 143, stderr
    assert "Traceback" not in stderr and "interrupted by SIGTERM" in stderr.strip().splitlines()[-1]
    assert not list(out.rglob(".*.tmp")), "a temp file or folder was left"
    for house in (p for p in out.iterdir() if p.is_dir()):
        assert {"house.xml", "spec.json"} <= {f.name for f in house.iterdir()}, f"{house} is half-written"


def test_sigterm_raises_terminated_only_inside_the_block():
    previous = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated):
        with sigterm_as_interrupt():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(1.0)  # not reached: the handler raises first
    assert signal.getsignal(signal.SIGTERM) is previous
    assert issubclass(Terminated, KeyboardInterrupt), "every clean-up written for Ctrl-C runs for SIGTERM"
