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


@pytest.mark.parametrize(
    "agent, max_steps, training_run",
    # the learned ones play one of their shipped runs: each plays through the same code
    [("frontier", 40, None), ("grg_frontier", 40, None), ("a3c", 60, 0), ("hrl_grg", 60, 0)],
)
def test_house_agents_in_lockstep_give_the_sequential_records(cache_dir, agent, max_steps, training_run):
    config = EvalConfig(
        agent=agent,
        suite="house-single",
        splits=("seen-goals",),
        seeds=(1,),
        suite_config={"mode": "cached", "cache_dir": cache_dir, "max_steps": max_steps},
        training_run=training_run,
    )
    one = evaluate(config, progress=False, batch=1)
    many = evaluate(config, progress=False, batch=16)
    assert many["episodes"] == one["episodes"]
    assert 0 < sum(r["success"] for r in one["episodes"]) < 100 and not any("error" in r for r in one["episodes"])
    if agent == "grg_frontier":
        assert one["config"]["weights_sha256"], "the GRG it read is recorded"


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
