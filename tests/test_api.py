"""The Python API exported from ``objsearch``: evaluate an agent object or name, build and
register suites."""

import pytest

import objsearch
from objsearch.errors import UserError
from objsearch.eval.suites import REGISTERED, SUITES
from objsearch.eval.suites.gridworld import GridWorldSuite
from objsearch_agents.baselines.random_agent import RandomAgent


class TwentyStepGridWorld(GridWorldSuite):
    """A suite of this test module: the grid world in 20 steps."""

    def __init__(self, name="gridworld-20", maps=None, tasks=None, max_steps=20):
        super().__init__(name, maps, tasks, max_steps)


def _records(results):
    return [{k: r[k] for k in ("split", "seed", "episode_id", "success", "steps")} for r in results["episodes"]]


def test_evaluate_an_agent_object_as_the_harness_plays_its_name():
    by_object = objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], split="seen-goals")
    by_name = objsearch.evaluate("random", "gridworld", seeds=[1], split="seen-goals")
    assert by_object["agent"] == "objsearch_agents.baselines.random_agent:RandomAgent"
    assert list(by_object["splits"]) == ["seen-goals"] and len(by_object["episodes"]) > 50
    assert _records(by_object) == _records(by_name)
    # in lockstep the object is copied per slot: the same records
    batched = objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], split="seen-goals", batch=8)
    assert _records(batched) == _records(by_name)


def test_an_object_that_is_not_an_agent_or_wants_processes_is_refused():
    with pytest.raises(UserError, match="no reset"):
        objsearch.evaluate(object(), "gridworld", seeds=[1])
    with pytest.raises(UserError, match="workers=1"):
        objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], workers=2)
    with pytest.raises(UserError, match="unknown split"):
        objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], split="nope")


def test_register_suite_makes_a_name_that_worker_processes_know():
    objsearch.register_suite("gridworld-20", TwentyStepGridWorld)
    objsearch.register_suite("gridworld-20", TwentyStepGridWorld)  # again, the same: allowed
    try:
        suite = objsearch.make_suite("gridworld-20")
        assert suite.max_steps == 20 and suite.splits == GridWorldSuite().splits
        results = objsearch.evaluate("random", "gridworld-20", seeds=[1], split="seen-goals", workers=2)
        assert results["suite"] == "gridworld-20"
        assert max(r["steps"] for r in results["episodes"]) == 20
        with pytest.raises(UserError, match="taken by"):
            objsearch.register_suite("gridworld", TwentyStepGridWorld)
        with pytest.raises(UserError, match=r"\.json"):
            objsearch.register_suite("mine.json", TwentyStepGridWorld)
    finally:
        SUITES.pop("gridworld-20", None)
        REGISTERED.pop("gridworld-20", None)


def test_episodes_gives_a_quick_partial_look_and_seeds_default_to_the_suites_standard_ones():
    quick = objsearch.evaluate("random", "gridworld", split="seen-goals", episodes=3)
    assert quick["seeds"] == [1, 5, 13, 45, 99] and quick.get("partial") is True
    assert sorted({r["episode_id"] for r in quick["episodes"]}) == [0, 1, 2] and len(quick["episodes"]) == 15
    with pytest.raises(UserError, match="episodes=0: give an integer >= 1"):
        objsearch.evaluate("random", "gridworld", episodes=0)
