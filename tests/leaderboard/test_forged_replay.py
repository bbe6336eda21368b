"""A forged submission cannot pass ``leaderboard verify``: its replayed sample is drawn with the
verifier's fresh randomness, large enough to catch 5% altered records with probability 0.99;
only registered agents run without --trust; the replay count is stored and shown."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from objsearch.cli import main
from objsearch.eval.metrics import episode_spl, summarize
from objsearch.leaderboard import replay
from objsearch.leaderboard.validate import (
    check_submission,
    miss_probability,
    replay_sample,
    replay_units,
    replayed_of,
    sample_size,
)

BIN = Path(sys.executable).parent


def run(capsys, *args) -> tuple[int, str, str]:
    code = main(["leaderboard", *map(str, args)])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def genuine(tmp_path_factory) -> dict:
    """A real results file: objsearch-eval's random agent on one grid-world split, one seed (100 episodes)."""
    out = tmp_path_factory.mktemp("eval") / "random.json"
    done = subprocess.run(
        [str(BIN / "objsearch-eval"), "--agent", "random", "--suite", "gridworld", "--split", "unseen-goals",
         "--seeds", "1", "--quiet", "--out", str(out)],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return dict(json.loads(out.read_text()), partial=True)


def forge(results: dict, fraction: float = 0.05) -> tuple[dict, set]:
    """``results`` with ``fraction`` of its records turned from failures into successes, every
    summary recomputed with objsearch's own code: self-consistent, it passes every check."""
    fake = json.loads(json.dumps(results))
    failures = [r for r in fake["episodes"] if not r["success"]]
    flipped = failures[:: max(1, len(failures) // math.ceil(fraction * len(fake["episodes"])))]
    flipped = flipped[: math.ceil(fraction * len(fake["episodes"]))]
    for r in flipped:
        r["success"] = True
        r["steps"] = max(r["min_steps"], min(r["steps"], fake["config"]["suite_config"]["max_steps"]))
        r["spl"] = episode_spl(True, r["min_steps"], r["steps"])
    fake["splits"] = {s: summarize([r for r in fake["episodes"] if r["split"] == s]) for s in fake["splits"]}
    return fake, {(r["split"], r["seed"], r["episode_id"], None) for r in flipped}


def test_the_sample_size_catches_five_percent_altered_with_probability_099():
    for total in (1, 10, 100, 200, 1500, 100_000):
        n = sample_size(total)
        assert n <= min(total, 90) and miss_probability(total, n) <= 0.01
        assert n == 0 or miss_probability(total, n - 1) > 0.01  # the smallest such sample
    assert sample_size(100_000) == 90  # (0.95)^90 < 0.01 < (0.95)^89
    assert (0.95**90 <= 0.01) and (0.95**89 > 0.01)


def test_a_forged_sample_is_missed_at_most_one_time_in_a_hundred(genuine):
    fake, flipped = forge(genuine)
    assert len(flipped) == 5 and check_submission(fake) == []
    draws = 3000
    missed = sum(not flipped & set(replay_sample(fake, None, np.random.default_rng(seed))) for seed in range(draws))
    assert missed / draws <= 0.01 + 3 * math.sqrt(0.01 * 0.99 / draws), missed


def test_a_forged_submission_fails_verify_every_time(tmp_path, capsys, monkeypatch, genuine):
    fake, flipped = forge(genuine)
    assert check_submission(fake) == []  # every check on its own content passes
    board = tmp_path / "board"
    (tmp_path / "genuine.json").write_text(json.dumps(genuine))
    (tmp_path / "fake.json").write_text(json.dumps(dict(fake, git_commit="f" * 40)))
    assert run(capsys, "--dir", board, "add", tmp_path / "genuine.json", "--partial", "--create")[0] == 0
    assert run(capsys, "--dir", board, "add", tmp_path / "fake.json", "--partial", "--name", "fake")[0] == 0
    seeds = iter(range(100, 106))  # stand-ins for the OS's randomness: the same code path, repeatable
    monkeypatch.setattr(replay, "fresh_rng", lambda: np.random.default_rng(next(seeds)))
    for _ in range(6):
        code, _, err = run(capsys, "--dir", board, "verify", "gridworld/fake")
        assert code == 2 and "fake.json fails verification: episode unseen-goals/seed 1/" in err, err
        assert "is True in the submission but False when replayed with agent 'random'" in err
    stored = json.loads((board / "submissions/gridworld/fake.json").read_text())
    assert replayed_of(stored) is None  # a failed verification records nothing


def test_verify_with_the_os_randomness_records_the_count_shown_on_the_pages(tmp_path, genuine):
    board = tmp_path / "board"
    (tmp_path / "genuine.json").write_text(json.dumps(genuine))
    objsearch = str(BIN / "objsearch")
    add = subprocess.run(
        [objsearch, "leaderboard", "--dir", str(board), "add", str(tmp_path / "genuine.json"), "--partial", "--create"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert add.returncode == 0, add.stderr
    assert "| – | random | random | gt |" in (board / "README.md").read_text()
    assert "| – |\n" in (board / "README.md").read_text()  # replayed: none yet
    done = subprocess.run(
        [objsearch, "leaderboard", "--dir", str(board), "verify", "gridworld/random"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "(59 of 100 episodes, drawn at random, replayed identical" in done.stdout
    stored = json.loads((board / "submissions/gridworld/random.json").read_text())
    assert replayed_of(stored) == (59, 100) and {k: v for k, v in stored.items() if k != "verified"} == genuine
    assert " | 59/100 |\n" in (board / "README.md").read_text()
    assert '["replayed","replayed"]' in (board / "index.html").read_text()  # a column of the page (full entries)
    done = subprocess.run(
        [objsearch, "leaderboard", "--dir", str(board), "verify", "gridworld/random", "--episodes", "all"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0 and "(100 of 100 episodes" in done.stdout, done.stderr
    assert " | 100/100 |\n" in (board / "README.md").read_text()
    assert check_submission(json.loads((board / "submissions/gridworld/random.json").read_text())) == []

    # a file that claims its own verification: add drops it
    claimed = dict(genuine, git_commit="c" * 40, verified={"replayed": 100, "episodes": 100, "sha256": "0" * 64})
    (tmp_path / "claimed.json").write_text(json.dumps(claimed))
    add = subprocess.run(
        [objsearch, "leaderboard", "--dir", str(board), "add", str(tmp_path / "claimed.json"), "--partial",
         "--name", "claimed"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert add.returncode == 0 and "dropped" in add.stderr, add.stderr
    assert "verified" not in json.loads((board / "submissions/gridworld/claimed.json").read_text())


def test_every_episode_with_episodes_all_catches_any_forgery(tmp_path, genuine):
    fake, _ = forge(genuine, fraction=0.01)  # one record: only a full replay is sure to find it
    board = tmp_path / "board"
    (tmp_path / "fake.json").write_text(json.dumps(fake))
    objsearch = str(BIN / "objsearch")
    args = ["leaderboard", "--dir", str(board)]
    add = subprocess.run([objsearch, *args, "add", str(tmp_path / "fake.json"), "--partial", "--create"], timeout=300)
    assert add.returncode == 0
    done = subprocess.run(
        [objsearch, *args, "verify", "--all", "--episodes", "all"], capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 2 and "fails verification" in done.stderr and len(done.stderr.splitlines()) == 1
    assert len(replay_units(fake)) == 100


def test_the_same_results_under_a_second_name_are_refused(tmp_path, capsys, genuine):
    board = tmp_path / "board"
    (tmp_path / "genuine.json").write_text(json.dumps(genuine))
    assert run(capsys, "--dir", board, "add", tmp_path / "genuine.json", "--partial", "--create")[0] == 0
    code, _, err = run(capsys, "--dir", board, "add", tmp_path / "genuine.json", "--partial", "--name", "hrl_grg_v3")
    assert code == 2 and "holds the same results as the stored entry" in err and "random.json" in err
