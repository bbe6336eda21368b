"""The command line, run as a user runs it: in a subprocess."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from objsearch.gridworld import dataset
from objsearch.gridworld.maps import save_map
from objsearch.sim.suites import SUITE_NAMES

BIN = Path(sys.executable).parent


def run(*args, cwd=None):
    return subprocess.run([str(BIN / args[0]), *args[1:]], capture_output=True, text=True, cwd=cwd, timeout=300)


def test_list_agents():
    out = run("objsearch-eval", "--list-agents")
    assert out.returncode == 0
    names = [line.split()[0] for line in out.stdout.splitlines()]
    assert {"random", "oracle"} <= set(names)


def test_eval_prints_the_table_and_writes_results(tmp_path):
    out = run(
        "objsearch",
        "eval",
        "--agent",
        "oracle",
        "--suite",
        "gridworld",
        "--split",
        "unseen-goals",
        "--seeds",
        "1,5",
        "--out",
        str(tmp_path / "r.json"),
        "--quiet",
    )
    assert out.returncode == 0, out.stderr
    assert "Unseen Goals" in out.stdout and "AS / MS" in out.stdout
    assert "oracle" in out.stdout and "1.00" in out.stdout
    results = json.loads((tmp_path / "r.json").read_text())
    assert results["agent"] == "oracle" and results["seeds"] == [1, 5]
    assert list(results["splits"]) == ["unseen-goals"]
    split = results["splits"]["unseen-goals"]
    for key in ("sr", "spl", "as", "ms", "episodes", "sr_ci", "spl_ci", "per_goal"):
        assert key in split
    assert split["sr"] == 1.0 and len(results["episodes"]) == 200


def test_without_suite_eval_runs_the_house_benchmark_and_maps_imply_the_grid_world(tmp_path, cache_dir, user_maps):
    out = run(
        "objsearch-eval",
        "--agent",
        "oracle",
        "--split",
        "seen-goals",
        "--seeds",
        "1",
        "--cache-dir",
        cache_dir,
        "--out",
        str(tmp_path / "r.json"),
        "--quiet",
    )
    assert out.returncode == 0, out.stderr
    assert json.loads((tmp_path / "r.json").read_text())["suite"] == "house-single"
    (user_maps / "t.jsonl").write_text('{"map": "map_0100", "start": [1, 1], "goal": 0}\n')
    out = run("objsearch-eval", "--maps", str(user_maps / "maps"), "--tasks", str(user_maps / "t.jsonl"), "--quiet")
    assert out.returncode == 0, out.stderr


def test_objsearch_eval_is_objsearch_eval_subcommand(tmp_path):
    args = ["--agent", "random", "--suite", "gridworld", "--split", "all-goals", "--seeds", "3", "--quiet"]
    a = run("objsearch-eval", *args, "--out", str(tmp_path / "a.json"))
    b = run("objsearch", "eval", *args, "--out", str(tmp_path / "b.json"))
    assert a.returncode == b.returncode == 0
    assert a.stdout == b.stdout
    assert json.loads((tmp_path / "a.json").read_text()) == json.loads((tmp_path / "b.json").read_text())


def assert_clean_error(out, *needles):
    assert out.returncode == 2, (out.returncode, out.stderr)
    assert "Traceback" not in out.stderr
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1, out.stderr
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])


def test_unknown_agent_suite_and_split():
    assert_clean_error(run("objsearch-eval", "--agent", "orcale"), "unknown agent 'orcale'", "did you mean 'oracle'")
    assert_clean_error(run("objsearch-eval", "--suite", "gridwrld"), "unknown suite 'gridwrld'")
    assert_clean_error(run("objsearch-eval", "--suite", "gridworld", "--split", "unseen"), "unknown split 'unseen'")


@pytest.fixture
def user_maps(tmp_path):
    save_map(dataset.test_maps()["map_0100"], tmp_path / "maps")
    return tmp_path


def test_corrupt_map_file(user_maps):
    (user_maps / "maps" / "map_0101.npz").write_bytes(b"garbage")
    (user_maps / "t.jsonl").write_text('{"map": "map_0100", "start": [1, 1], "goal": 0}\n')
    out = run("objsearch-eval", "--maps", str(user_maps / "maps"), "--tasks", str(user_maps / "t.jsonl"))
    assert_clean_error(out, "map_0101.npz")


def test_malformed_task_line(user_maps):
    (user_maps / "t.jsonl").write_text(
        '{"map": "map_0100", "start": [1, 1], "goal": 0}\n{"map": "map_0100", "start": [1, 1]\n'
    )
    out = run("objsearch-eval", "--maps", str(user_maps / "maps"), "--tasks", str(user_maps / "t.jsonl"))
    assert_clean_error(out, "t.jsonl:2", "malformed task line")


def test_unreachable_goal(user_maps):
    m = dataset.test_maps()["map_0100"]
    dist = m.distances_to(tuple(m.goals[0]))
    cut_off = np.argwhere((dist < 0) & (m.obstacles == 0))
    if len(cut_off) == 0:
        pytest.skip("map_0100 has no free cell cut off from goal 0")
    r, c = (int(v) for v in cut_off[0])
    (user_maps / "t.jsonl").write_text(json.dumps({"map": "map_0100", "start": [r, c], "goal": 0}) + "\n")
    out = run("objsearch-eval", "--maps", str(user_maps / "maps"), "--tasks", str(user_maps / "t.jsonl"))
    assert_clean_error(out, "t.jsonl:1", "cannot be reached")


def test_maps_without_tasks():
    assert_clean_error(run("objsearch-eval", "--maps", "somewhere"), "--maps and --tasks go together")


def test_a_flag_of_other_suites_is_refused_naming_the_suites_that_take_it(user_maps):
    assert_clean_error(
        run("objsearch-eval", "--suite", "gridworld", "--render", "live"),
        "--render does not apply to suite 'gridworld'",
        "suites that take it: " + ", ".join(SUITE_NAMES) + ", suite files",
    )
    out = run("objsearch-eval", "--suite", "house-single", "--maps", str(user_maps / "maps"), "--tasks", "t.jsonl")
    assert_clean_error(out, "--maps does not apply to suite 'house-single'", "suites that take it: gridworld")


def test_bad_seeds_are_rejected_by_the_parser():
    out = run("objsearch-eval", "--seeds", "one,two")
    assert out.returncode == 2 and "seeds must be comma-separated integers" in out.stderr


def test_failed_episodes_are_reported_first_and_a_run_that_never_ran_exits_non_zero():
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).parent / "eval")}
    args = ["--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1", "--quiet"]
    out = subprocess.run(
        [str(BIN / "objsearch-eval"), "--agent", "agents_for_tests:BadActionAgent", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert out.returncode == 1, out.stderr
    assert out.stderr.startswith(
        "100 of 100 episode(s) failed with an agent error; the first, unseen-goals/seed 1/0: ValueError"
    )
    assert "every episode failed" in out.stderr
    some = subprocess.run(
        [str(BIN / "objsearch-eval"), "--agent", "agents_for_tests:RaisingAgent", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )
    assert some.returncode == 0 and some.stderr.startswith("50 of 100 episode(s) failed"), some.stderr


def test_an_agent_is_refused_on_a_suite_it_does_not_run_in():
    out = run("objsearch-eval", "--agent", "a3c", "--suite", "gridworld", "--quiet")
    assert_clean_error(out, "runs in the house world", "gridworld")


class _Evil:
    """Pickles to a call that would create a file when unpickled."""

    def __init__(self, target):
        self.target = target

    def __reduce__(self):
        return (Path.touch, (Path(self.target),))


@pytest.mark.parametrize(
    "agent, suite", [("hrl_grg", "gridworld"), ("hrl_grg", "house-single"), ("a3c", "house-single")]
)
def test_checkpoints_are_data_not_code(tmp_path, agent, suite):
    import torch

    marker = tmp_path / "code-ran"
    cases = {"evil.pt": None, "empty.pt": b"", "text.pt": b"not a checkpoint\n", "truncated.pt": None}
    torch.save({"config": _Evil(marker)}, tmp_path / "evil.pt")
    torch.save({"config": {}, "low": {"w": torch.zeros(3)}}, tmp_path / "whole.pt")
    cases["truncated.pt"] = (tmp_path / "whole.pt").read_bytes()[:40]
    for name, data in cases.items():
        if data is not None:
            (tmp_path / name).write_bytes(data)
        out = run("objsearch-eval", "--agent", agent, "--suite", suite, "--checkpoint", str(tmp_path / name), "--quiet")
        assert_clean_error(out, "cannot read checkpoint", name)
    assert not marker.exists(), "loading a checkpoint ran code"
    wrong = run(
        "objsearch-eval", "--agent", agent, "--suite", suite, "--checkpoint", str(tmp_path / "whole.pt"), "--quiet"
    )
    assert_clean_error(wrong, "whole.pt")


def test_every_subcommand_has_help_that_renders():
    """``--help`` of every command and nested subcommand formats (a bare ``%`` in a help text
    makes argparse raise instead of printing it)."""
    import argparse

    from objsearch.cli import build_parser

    todo, seen = [build_parser()], 0
    while todo:
        parser = todo.pop()
        assert parser.format_help()
        seen += 1
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                todo.extend(action.choices.values())
    assert seen > 20, seen
