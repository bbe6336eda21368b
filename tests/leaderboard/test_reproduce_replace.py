"""``objsearch reproduce`` never replaces a stored entry that it did not write in that plan
(objsearch.leaderboard.reproduce_run), unless asked with ``--replace``; a partial entry never
takes a full one's place silently. Real runs: random on the grid world, one seed (seconds)."""

import json
import shutil
from pathlib import Path

import pytest

from objsearch.cli import main

SHIPPED = Path(__file__).resolve().parents[2] / "leaderboard" / "submissions" / "gridworld" / "random.json"
ONE_SEED = ["reproduce", "--suite", "gridworld", "--methods", "random", "--seeds", "1", "--quiet"]


@pytest.fixture
def board(tmp_path, monkeypatch):
    """A folder holding ``leaderboard/`` with the shipped, verified random entry (cwd)."""
    stored = tmp_path / "leaderboard" / "submissions" / "gridworld" / "random.json"
    stored.parent.mkdir(parents=True)
    shutil.copyfile(SHIPPED, stored)
    monkeypatch.chdir(tmp_path)
    return stored


def test_without_out_a_stored_entry_is_never_replaced(board, capsys):
    before = board.read_bytes()
    assert main(ONE_SEED) == 2
    err = capsys.readouterr().err
    assert board.read_bytes() == before, "the shipped, verified entry is kept"
    assert f"{board.resolve()} holds an entry that this reproduction did not write" in err
    assert "1500 episodes, verified by replay" in err and "--out DIR" in err and "--replace" in err
    assert not (board.parent.parent.parent / "README.md").exists(), "refused before any step ran"


def test_replace_replaces_it_and_says_so(board, capsys):
    assert main([*ONE_SEED, "--replace"]) == 0
    stored = json.loads(board.read_text())
    assert stored["partial"] and len(stored["episodes"]) == 300
    assert "replacing" in capsys.readouterr().err


def test_an_entry_this_plan_wrote_may_be_written_again(tmp_path, capsys):
    out = tmp_path / "out"
    assert main([*ONE_SEED, "--out", str(out)]) == 0
    stored = out / "leaderboard" / "submissions" / "gridworld" / "random.json"
    first = json.loads(stored.read_text())
    (out / "results" / "gridworld" / "random.json").unlink()  # evaluated again, on another seed
    (out / "steps" / "eval-gridworld-random.json").unlink()
    assert main([*ONE_SEED[:-2], "5", "--quiet", "--out", str(out)]) == 0
    again = json.loads(stored.read_text())
    assert again["seeds"] == [5] and first["seeds"] == [1]
    capsys.readouterr()
    # someone else's entry in its place: not the plan's any more
    shutil.copyfile(SHIPPED, stored)
    (out / "results" / "gridworld" / "random.json").unlink()
    (out / "steps" / "eval-gridworld-random.json").unlink()
    assert main([*ONE_SEED, "--out", str(out)]) == 2
    assert "did not write" in capsys.readouterr().err
    assert stored.read_bytes() == SHIPPED.read_bytes()


def test_a_partial_entry_never_replaces_a_full_one_the_plan_wrote(tmp_path, capsys, monkeypatch):
    """The plan's own full entry (its record says so) and a partial one to add: refused without --replace."""
    from objsearch.leaderboard import reproduce_run
    from objsearch.leaderboard.validate import content_sha256, load_submission

    out = tmp_path / "out"
    assert main([*ONE_SEED, "--out", str(out), "--dry-run"]) == 0
    stored = out / "leaderboard" / "submissions" / "gridworld" / "random.json"
    stored.parent.mkdir(parents=True)
    shutil.copyfile(SHIPPED, stored)
    record = out / "steps" / "add-gridworld-random.json"
    record.parent.mkdir(parents=True)
    record.write_text(
        json.dumps({"step": "add gridworld/random", "stored_sha256": content_sha256(load_submission(stored))})
    )
    monkeypatch.setattr(reproduce_run, "_verify", lambda *a: None)
    assert main([*ONE_SEED, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "is full (1500 episodes" in err and "partial (300 episodes" in err and "--replace" in err
    assert stored.read_bytes() == SHIPPED.read_bytes()
