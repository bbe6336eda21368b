"""``objsearch reproduce``: Table 4 on ``rooms`` for one method (a3c, two training runs, with
random as the table's baseline) rebuilt from nothing in the test-sized configuration into
``--out``, locally (interrupted, then resumed) and with ``--executor ray`` on a local Ray
cluster, with the same records; the dry run of Table 3; bad input."""

import copy
import json
import os
import re

import pytest

from objsearch.cli import main
from objsearch.leaderboard import reproduce_run
from objsearch.leaderboard.validate import verify_submission

TINY = ["reproduce", "table4", "--methods", "a3c", "--config", "tiny", "--runs", "2", "--quiet"]
ENTRIES = ("random", "a3c")


def entry(out, name: str) -> dict:
    return json.loads((out / "leaderboard" / "submissions" / "rooms" / f"{name}.json").read_text())


@pytest.fixture(scope="module")
def reproduced(tmp_path_factory, cache_dir):
    """Two tiny reproductions of Table 4, {executor: (out folder, calls of each step kind when resumed)}:
    the local one interrupted at its first leaderboard add, then run again."""
    out = tmp_path_factory.mktemp("reproduce")
    calls = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("OBJSEARCH_CACHE", cache_dir)  # training reads it, and the Ray workers inherit it

        def interrupted(*args):
            raise KeyboardInterrupt("stopped by the test")

        mp.setattr(reproduce_run, "_add", interrupted)
        assert main([*TINY, "--out", str(out / "local")]) == 130
        mp.undo()
        mp.setenv("OBJSEARCH_CACHE", cache_dir)
        for kind in ("train", "eval", "add"):
            real = getattr(reproduce_run, f"_{kind}")
            mp.setattr(
                reproduce_run,
                f"_{kind}",
                lambda *a, real=real, kind=kind: calls.setdefault(kind, []).append(a[0]) or real(*a),
            )
        assert main([*TINY, "--out", str(out / "local")]) == 0
        mp.undo()
        mp.setenv("OBJSEARCH_CACHE", cache_dir)
        assert main([*TINY, "--out", str(out / "ray"), "--executor", "ray", "--workers", "2"]) == 0
    return out, calls


def test_an_interrupted_reproduction_resumes_without_redoing_finished_steps(reproduced):
    out, calls = reproduced
    steps = sorted(p.stem for p in (out / "local" / "steps").glob("*.json"))
    assert len(steps) == 9 and {"train-rooms-a3c-seed0", "train-rooms-a3c-seed1"} <= set(steps)
    assert "train" not in calls  # trained before the interrupt: not again
    assert [a["agent"] for a in calls["eval"]] == ["a3c"]  # random's evaluation was finished
    assert [a["entry"] for a in calls["add"]] == ["random", "a3c"]


def test_tiny_table4_from_nothing_locally_and_on_ray_gives_the_same_records(reproduced):
    out, _ = reproduced
    for name in ENTRIES:
        local, ray = entry(out / "local", name), entry(out / "ray", name)
        assert local["partial"] and local["suite"] == "rooms" and local["verified"]["replayed"] == 5
        assert ray["episodes"] == local["episodes"] and ray["splits"] == local["splits"]
        assert ray["config"]["weights_sha256"] == local["config"]["weights_sha256"]
    trained = entry(out / "local", "a3c")
    # both runs, found in --out's checkpoints (not the shipped ones), played on the same episodes
    runs = {run["seed"]: run for run in trained["training_runs"]}
    assert sorted(runs) == [0, 1] and len(trained["episodes"]) == 2 * 1000
    assert runs[0]["weights_sha256"] != runs[1]["weights_sha256"]
    assert all(
        str(out / "local" / "checkpoints" / "rooms" / "a3c") in run["loaded_checkpoint"] for run in runs.values()
    )
    # the entry says where its weights were, so a plain verify (no $OBJSEARCH_CHECKPOINTS) replays them
    assert trained["config"]["checkpoints"] == str(out / "local" / "checkpoints")
    assert "OBJSEARCH_CHECKPOINTS" not in os.environ
    assert verify_submission(trained, k=2) == []
    moved = copy.deepcopy(trained)
    moved["config"]["checkpoints"] = str(out / "nowhere")
    assert "which is no folder here" in verify_submission(moved, k=2)[0]
    tables = {executor: (out / executor / "table4.md").read_text() for executor in ("local", "ray")}
    assert tables["local"].startswith("## Table 4") and "| A3C | gt | 2 | **" in tables["local"]
    assert tables["ray"].replace(str(out / "ray"), str(out / "local")) == tables["local"]
    assert (out / "ray" / "steps" / "train-rooms-a3c-seed0.json").is_file()


def test_a_finished_reproduction_runs_only_the_render_again(reproduced, capsys, monkeypatch, cache_dir):
    out, _ = reproduced
    monkeypatch.setenv("OBJSEARCH_CACHE", cache_dir)
    assert main([*TINY, "--out", str(out / "local")]) == 0
    assert "8 done already, 1 to run" in capsys.readouterr().err


def test_dry_run_of_table3_lists_the_training_runs_and_the_estimated_hours(capsys, tmp_path):
    assert main(["reproduce", "table3", "--dry-run"]) == 0
    shown = capsys.readouterr().out
    assert "train house-single/hrl_grg/seed2" in shown and "train house-multi/dqn/seed1" in shown
    done, to_train = map(int, re.search(r"training runs: (\d+) done, (\d+) to train", shown).groups())
    assert done >= 12 and to_train > 0  # a3c and hrl_grg ship 3 runs on both suites; dqn and others one
    hours = [line for line in shown.splitlines() if line.startswith("estimated time to run:")]
    assert hours and float(hours[0].split()[4]) > 1 and "hours" in hours[0]
    assert "log.csv of another seed's run (agents/checkpoints/house-single/dqn" in shown
    # the rows trained on the predictions too: their own runs, from the recipes shipped in predicted/
    assert "done  train house-single/a3c/predicted " in shown
    assert "eval house-single/hrl_grg_explorer_predicted_trained" in shown
    assert "eval house-single/dqn_predicted_trained" not in shown  # no such run is shipped: nothing to reproduce


@pytest.mark.parametrize(
    "argv, said",
    [
        (["table5"], "unknown table 'table5'; choose one of table1, table2, table3, table4"),
        (["table4", "--methods", "dqn"], "--methods dqn: not in table4 (its methods: a3c, scene_priors"),
        (["--suite", "rooms", "--methods", "hrl-grg"], "unknown agent 'hrl-grg'; did you mean 'hrl_grg'?"),
        (["table4", "--config", "tiny"], "pass --out DIR"),
        (["table4", "--splits", "test"], "--splits test: not a split of rooms (its splits: seen-env-seen-goals"),
    ],
)
def test_bad_input_names_the_input_and_the_fix(argv, said, capsys):
    assert main(["reproduce", *argv, "--dry-run"]) == 2
    assert said in capsys.readouterr().err
