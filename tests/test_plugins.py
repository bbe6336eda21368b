"""A third-party agent package plugs in through the entry point, without touching objsearch."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent


@pytest.fixture(scope="module")
def installed_example(tmp_path_factory):
    target = tmp_path_factory.mktemp("site")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-deps",
            "--no-build-isolation",
            "--target",
            str(target),
            str(ROOT / "examples" / "objsearch-greedy-agent"),
        ],
        check=True,
        capture_output=True,
        timeout=300,
    )
    env = dict(os.environ, PYTHONPATH=str(target))
    return env


def test_installed_example_is_listed_and_evaluated_by_name(installed_example, tmp_path):
    listed = subprocess.run(
        [str(BIN / "objsearch-eval"), "--list-agents"], env=installed_example, capture_output=True, text=True
    )
    assert "greedy_visible" in listed.stdout
    out = subprocess.run(
        [
            str(BIN / "objsearch-eval"),
            "--agent",
            "greedy_visible",
            "--suite",
            "gridworld",
            "--split",
            "unseen-goals",
            "--seeds",
            "1,5",
            "--quiet",
            "--out",
            str(tmp_path / "greedy.json"),
        ],
        env=installed_example,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    results = json.loads((tmp_path / "greedy.json").read_text())
    assert results["agent"] == "greedy_visible"
    # it walks straight to a goal in view, so it clearly beats the random agent's ~0.2
    assert results["splits"]["unseen-goals"]["sr"] > 0.35


def test_agent_by_module_path(tmp_path):
    out = subprocess.run(
        [
            str(BIN / "objsearch-eval"),
            "--agent",
            "objsearch_agents.baselines.random_agent:RandomAgent",
            "--suite",
            "gridworld",
            "--split",
            "all-goals",
            "--seeds",
            "1",
            "--quiet",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    assert "RandomAgent" in out.stdout


def test_installed_package_adds_a_suite_by_entry_point(installed_example, tmp_path):
    """The example package's ``objsearch.suites`` entry point makes ``gridworld-short`` a suite
    name on the command line, in worker processes too."""
    out = subprocess.run(
        [
            str(BIN / "objsearch-eval"),
            "--agent",
            "random",
            "--suite",
            "gridworld-short",
            "--split",
            "seen-goals",
            "--seeds",
            "1",
            "--workers",
            "2",
            "--quiet",
            "--out",
            str(tmp_path / "short.json"),
        ],
        env=installed_example,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr
    results = json.loads((tmp_path / "short.json").read_text())
    assert results["suite"] == "gridworld-short"
    assert max(r["steps"] for r in results["episodes"]) == 50  # its step limit, not the grid world's 100
