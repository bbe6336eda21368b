"""Agents that fail, stall or get interrupted do not take the evaluation down with them."""

import json

import pytest
from agents_for_tests import InterruptedAgent

from objsearch.errors import UserError
from objsearch.eval.runner import EvalConfig, evaluate

ONE_SPLIT = {"splits": ("unseen-goals",), "seeds": (1,)}


def test_an_agent_that_raises_fails_its_episodes_and_the_run_goes_on():
    results = evaluate(EvalConfig(agent="agents_for_tests:RaisingAgent", **ONE_SPLIT), progress=False)
    for r in results["episodes"]:
        if r["episode_id"] % 2 == 0:
            assert not r["success"] and r["error"] == "RuntimeError: boom"
        else:
            assert r["success"] and "error" not in r
    assert results["splits"]["unseen-goals"]["sr"] == 0.5


def test_a_step_over_the_time_limit_fails_the_episode():
    config = EvalConfig(agent="agents_for_tests:SlowAgent", step_time_limit=0.5, splits=("unseen-goals",), seeds=(1,))
    results = evaluate(config, progress=False)
    first, *rest = results["episodes"]
    assert not first["success"] and "step time limit of 0.5 s exceeded at step 0" in first["error"]
    assert all(r["success"] for r in rest)


def test_an_invalid_action_fails_the_episode():
    results = evaluate(EvalConfig(agent="agents_for_tests:BadActionAgent", **ONE_SPLIT), progress=False)
    assert all("invalid action 7" in r["error"] for r in results["episodes"])
    assert results["splits"]["unseen-goals"]["sr"] == 0.0


def test_an_interrupted_run_resumes_without_losing_or_repeating_episodes(tmp_path):
    out = tmp_path / "results.json"
    config = EvalConfig(agent="agents_for_tests:InterruptedAgent", splits=("unseen-goals", "all-goals"), seeds=(1, 5))
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = 130, 0
    with pytest.raises(KeyboardInterrupt):
        evaluate(config, progress=False, out=out)
    partial = tmp_path / "results.json.partial.jsonl"
    assert not out.exists()
    assert len(partial.read_text().splitlines()) == 1 + 130
    with open(partial, "a") as f:
        f.write('{"split": "unseen-go')  # a write cut short by the interruption

    InterruptedAgent.interrupt_after, InterruptedAgent.resets = None, 0
    resumed = evaluate(config, progress=False, out=out)
    assert InterruptedAgent.resets == 400 - 130, "only the missing episodes run again"
    assert not partial.exists()
    assert json.loads(out.read_text()) == resumed

    InterruptedAgent.resets = 0
    fresh = evaluate(config, progress=False, out=tmp_path / "fresh.json")
    assert InterruptedAgent.resets == 400
    assert resumed == fresh


def test_partial_results_of_another_run_are_refused(tmp_path):
    out = tmp_path / "r.json"
    (tmp_path / "r.json.partial.jsonl").write_text('{"partial_results_of": {"agent": "random"}}\n')
    with pytest.raises(UserError, match="partial results of another evaluation"):
        evaluate(EvalConfig(agent="oracle", **ONE_SPLIT), progress=False, out=out)


def test_ray_executor_gives_the_local_results():
    pytest.importorskip("ray")
    config = EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1, 5))
    local = evaluate(config, progress=False)
    distributed = evaluate(config, progress=False, executor="ray", workers=2)
    assert distributed == local
