"""``objsearch-eval --episodes N``: a quick look at the first N episodes of each split, marked
partial, which the leaderboard refuses in one line."""

import json

import pytest

from objsearch.cli import main
from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.eval.suites import make_suite


def test_episodes_plays_the_first_n_of_each_split_and_marks_the_results_partial():
    results = evaluate(EvalConfig(agent="random", seeds=(1, 5), episodes=3), progress=False)
    suite = make_suite("gridworld")
    for split in suite.splits:
        first = [ep.episode_id for ep in suite.episodes(split)[:3]]
        played = [(r["seed"], r["episode_id"]) for r in results["episodes"] if r["split"] == split]
        assert played == [(seed, i) for seed in (1, 5) for i in first]
        assert results["splits"][split]["episodes"] == 6
    assert results["partial"] is True and results["config"]["episodes"] == 3
    whole = evaluate(EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1,)), progress=False)
    assert "partial" not in whole and "episodes" not in whole["config"]  # results without it are as before
    assert whole["episodes"][:3] == [r for r in results["episodes"] if r["split"] == "unseen-goals" and r["seed"] == 1]


def test_the_table_says_partial_and_the_leaderboard_refuses_it_in_one_line(tmp_path, capsys):
    out = tmp_path / "quick.json"
    assert main(["eval", "--agent", "random", "--episodes", "2", "--quiet", "--out", str(out)]) == 0
    table = capsys.readouterr().out
    assert "partial: the first 2 episodes of each split only (--episodes)" in table
    assert json.loads(out.read_text())["partial"] is True
    board = tmp_path / "board"
    for extra in ([], ["--partial"]):  # not even apart, unranked: it is a look, not a result
        assert main(["leaderboard", "--dir", str(board), "add", str(out), "--create", *extra]) == 2
        err = capsys.readouterr().err
        assert "played only the first 2 episodes of each split (objsearch-eval --episodes)" in err, err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not list(board.glob("submissions/*/*.json"))


def test_episodes_must_be_a_positive_count(capsys):
    with pytest.raises(SystemExit) as exit:
        main(["eval", "--episodes", "0", "--quiet"])
    assert exit.value.code == 2 and "--episodes" in capsys.readouterr().err
