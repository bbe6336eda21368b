"""A run with failed episodes says so first: the count, the first error and its traceback,
before the table; a run where every episode failed exits 1."""

import os
import subprocess
import sys
from pathlib import Path

BIN = Path(sys.executable).parent
ARGS = ["--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1", "--quiet"]
ENV = {**os.environ, "PYTHONPATH": str(Path(__file__).parent)}


def evaluate_cli(agent):
    return subprocess.run(
        [str(BIN / "objsearch-eval"), "--agent", agent, *ARGS],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=ENV,
        timeout=300,
    )


def test_the_first_traceback_comes_before_the_table():
    out = evaluate_cli("agents_for_tests:RaisingAgent")
    assert out.returncode == 0, out.stdout
    assert out.stdout.startswith(
        "50 of 100 episode(s) failed with an agent error; the first, unseen-goals/seed 1/0: RuntimeError: boom\n"
    )
    trace = out.stdout.index('agents_for_tests.py", line')
    assert trace < out.stdout.index('raise RuntimeError("boom")') < out.stdout.index("Unseen Goals")
    assert "objsearch/eval/" not in out.stdout[: out.stdout.index("Unseen Goals")], "the harness's frames are left out"


def test_a_run_where_every_episode_failed_exits_1():
    out = evaluate_cli("agents_for_tests:BadActionAgent")
    assert out.returncode == 1 and "every episode failed" in out.stdout
