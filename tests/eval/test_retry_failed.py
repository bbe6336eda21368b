"""--retry-failed: the episodes of a finished run that ended in an agent error (a step-time
limit hit on a busy machine, a crash) are played again, and only those; the others are kept."""

import json
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.eval.runner import EvalConfig, evaluate

CONFIG = EvalConfig(agent="agents_for_tests:FlakyAgent", splits=("unseen-goals",), seeds=(1,))


def errors(results: dict) -> int:
    return sum("error" in r for r in results["episodes"])


def test_only_the_failed_episodes_are_played_again(tmp_path, monkeypatch):
    out = tmp_path / "r.json"
    monkeypatch.setenv("FLAKY_AGENT_FAILS", "even")
    assert errors(evaluate(CONFIG, progress=False, out=out)) == 50
    monkeypatch.setenv("FLAKY_AGENT_FAILS", "all")  # whatever is played now fails
    again = evaluate(CONFIG, progress=False, out=out, retry_failed=True)
    assert errors(again) == 50  # the 50 good records were kept, not played
    monkeypatch.delenv("FLAKY_AGENT_FAILS")
    fixed = evaluate(CONFIG, progress=False, out=out, retry_failed=True)
    assert errors(fixed) == 0 and fixed["splits"]["unseen-goals"]["sr"] == 1.0
    assert fixed["episodes"] == evaluate(CONFIG, progress=False)["episodes"]  # as if it never failed
    assert json.loads(out.read_text()) == fixed and not Path(f"{out}.partial.jsonl").exists()


def test_what_it_cannot_repair_is_refused_by_name(tmp_path, monkeypatch):
    out = tmp_path / "r.json"
    with pytest.raises(UserError, match="--retry-failed needs --out"):
        evaluate(CONFIG, progress=False, retry_failed=True)
    with pytest.raises(UserError, match=f"{out} is not a results file"):
        evaluate(CONFIG, progress=False, out=out, retry_failed=True)
    out.write_text("{")
    with pytest.raises(UserError, match="not a results file written by objsearch-eval"):
        evaluate(CONFIG, progress=False, out=out, retry_failed=True)
    evaluate(CONFIG, progress=False, out=out)
    other = EvalConfig(**{**CONFIG.__dict__, "seeds": (5,)})
    with pytest.raises(UserError, match=r"another evaluation \(seeds: \[1\] there, \[5\] now\)"):
        evaluate(other, progress=False, out=out, retry_failed=True)
