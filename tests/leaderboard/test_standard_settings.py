"""Results made under other rules are not ranked; records must be possible; a submission never
chooses where objsearch writes."""

import copy
import json

from objsearch.cli import main
from objsearch.eval.metrics import summarize
from objsearch.leaderboard import replay, validate
from objsearch.leaderboard.render import render
from objsearch.leaderboard.validate import check_submission, nonstandard_settings, playable_config


def resummarized(results: dict) -> dict:
    results["splits"] = {s: summarize([r for r in results["episodes"] if r["split"] == s]) for s in results["splits"]}
    return results


def test_an_entry_with_another_step_limit_is_refused_from_the_ranked_tables(full_random):
    other = copy.deepcopy(full_random)
    other["config"]["suite_config"]["max_steps"] = 1000
    assert nonstandard_settings(other) == ["max_steps=1000 (standard: 100)"]
    (problem,) = check_submission(other)
    assert problem.startswith("suite settings max_steps=1000 (standard: 100) differ from gridworld's standard")
    assert "--partial" in problem
    assert nonstandard_settings(full_random) == [] and check_submission(full_random) == []


def test_a_partial_entry_with_other_settings_is_shown_apart_with_them_named(tmp_path, random_results):
    other = copy.deepcopy(dict(random_results, partial=True))
    other["config"]["suite_config"]["max_steps"] = 1000
    assert check_submission(other) == []
    store = tmp_path / "submissions" / "gridworld"
    store.mkdir(parents=True)
    (store / "long.json").write_text(json.dumps(other))
    render(tmp_path)
    ranked, apart = (tmp_path / "README.md").read_text().split("## Partial submissions (not ranked)")
    assert "long" not in ranked and "| – | long | random | gt; max\\_steps=1000 (standard: 100) |" not in apart
    assert "| – | long | random | gt; max_steps=1000 (standard: 100) |" in apart


def test_impossible_records_are_refused_by_check(tmp_path, capsys, random_results):
    base = dict(random_results, partial=True)
    cases = [
        (lambda r: r.update(steps=-3), "-3 steps, not within the suite's step limit 0..100"),
        (lambda r: r.update(steps=101), "101 steps, not within the suite's step limit 0..100"),
        (lambda r: r.update(success=True, steps=r["min_steps"] - 1, spl=None), "fewer than the minimal"),
        (lambda r: r.update(spl=0.5 if r["spl"] != 0.5 else 0.25), "does not follow from its success and steps"),
    ]
    for change, message in cases:
        bad = copy.deepcopy(base)
        record = next(r for r in bad["episodes"] if r["min_steps"] > 1)
        change(record)
        resummarized(bad)
        (tmp_path / "bad.json").write_text(json.dumps(bad))
        assert main(["leaderboard", "check", "--partial", str(tmp_path / "bad.json")]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err


def test_a_submissions_cache_dir_is_ignored_by_check_and_verify(tmp_path, monkeypatch, random_results):
    assert playable_config({"mode": "cached", "cache_dir": "/somewhere", "max_steps": 9}) == {
        "mode": "cached",
        "max_steps": 9,
    }
    evil = tmp_path / "evil"
    results = copy.deepcopy(dict(random_results, partial=True))
    results["config"]["suite_config"]["cache_dir"] = str(evil)
    assert check_submission(results) == []  # gridworld has no cache_dir option: it was never looked at
    played = []
    real = replay.run_units
    monkeypatch.setattr(replay, "run_units", lambda config, *a, **k: played.append(config) or real(config, *a, **k))
    assert validate.verify_submission(results, 3) == []
    assert played and all("cache_dir" not in config.suite_config for config in played)
    assert not evil.exists()
