"""``--batch N``: episodes in lockstep give the records of a sequential run."""

import json

import pytest
from agents_for_tests import BadActionAgent, InterruptedAgent, RaisingAgent

from objsearch.eval.agent import is_batched
from objsearch.eval.runner import EvalConfig, evaluate
from objsearch_agents.baselines.oracle import OracleAgent
from objsearch_agents.baselines.random_agent import RandomAgent


def test_batched_agents_are_recognised_and_overrides_are_not_lost():
    assert is_batched(RandomAgent()) and is_batched(OracleAgent())
    # a subclass that overrides act() but inherits act_batch() must be played through act()
    assert not is_batched(RaisingAgent()) and not is_batched(BadActionAgent())


@pytest.mark.parametrize(
    "agent", ["random", "oracle", "agents_for_tests:RaisingAgent", "agents_for_tests:BadActionAgent"]
)
def test_batch_sizes_give_identical_records(agent):
    config = EvalConfig(agent=agent, splits=("unseen-goals",), seeds=(1, 5))
    one = evaluate(config, progress=False, batch=1)
    for batch in (7, 64):
        assert evaluate(config, progress=False, batch=batch)["episodes"] == one["episodes"], batch
    if "Raising" in agent:
        assert sum("error" in r for r in one["episodes"]) == 100  # the even episodes failed, the run went on


def test_batched_workers_give_identical_records():
    config = EvalConfig(agent="random", splits=("all-goals",), seeds=(1,))
    assert evaluate(config, progress=False, workers=2, batch=16) == evaluate(config, progress=False)


def test_an_interrupted_batched_run_resumes_to_the_sequential_records(tmp_path):
    out = tmp_path / "results.json"
    config = EvalConfig(agent="agents_for_tests:InterruptedAgent", splits=("unseen-goals", "all-goals"), seeds=(1, 5))
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = 130, 0
    with pytest.raises(KeyboardInterrupt):
        evaluate(config, progress=False, out=out, batch=16)
    kept = len((tmp_path / "results.json.partial.jsonl").read_text().splitlines()) - 1
    assert 0 < kept <= 130
    InterruptedAgent.interrupt_after, InterruptedAgent.resets = None, 0
    resumed = evaluate(config, progress=False, out=out, batch=16)
    assert InterruptedAgent.resets == 400 - kept, "only the missing episodes run again"
    sequential = evaluate(config, progress=False)
    assert resumed["episodes"] == sequential["episodes"] and json.loads(out.read_text()) == resumed
