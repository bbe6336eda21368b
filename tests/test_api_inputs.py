"""``objsearch.evaluate`` and ``objsearch-eval`` refuse a bad step time limit, naming it, before
any episode (no "every episode failed"); an agent object is recorded by its class, never by
a ``name`` it gives itself (objsearch.api, objsearch.cliargs.seconds)."""

import math

import pytest

import objsearch
from objsearch.cli import eval_main
from objsearch.errors import UserError
from objsearch_agents.baselines.random_agent import RandomAgent


@pytest.mark.parametrize("limit", [-1, math.inf, math.nan, "x", True, 1e300])
def test_a_bad_step_time_limit_is_refused_by_name(limit):
    with pytest.raises(UserError, match=r"step_time_limit=.*: give a number of seconds"):
        objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], split="seen-goals", step_time_limit=limit)


def test_a_step_time_limit_of_zero_or_none_is_no_limit():
    for limit in (0, None):
        results = objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1], split="seen-goals", step_time_limit=limit)
        assert not any("error" in r for r in results["episodes"])
        assert results["config"]["step_time_limit"] is None


@pytest.mark.parametrize("text", ["inf", "nan", "1e400", "-1", "1e300"])
def test_a_bad_step_time_limit_flag_is_named(text, capsys):
    with pytest.raises(SystemExit) as exit:
        eval_main(["--agent", "random", "--seeds", "1", "--step-time-limit", text])
    assert exit.value.code == 2
    assert "argument --step-time-limit" in capsys.readouterr().err


def test_an_agent_object_is_recorded_by_its_class_not_its_own_name():
    agent = RandomAgent()
    agent.name = "oracle"  # a claim: the registry's oracle is another agent
    results = objsearch.evaluate(agent, "gridworld", seeds=[1], split="seen-goals")
    assert results["agent"] == "objsearch_agents.baselines.random_agent:RandomAgent"


def test_a_cache_dir_that_is_not_a_path_is_named_when_the_env_is_made():
    import gymnasium

    import objsearch  # noqa: F401  (registers the ids)

    with pytest.raises(ValueError, match=r"cache_dir=5 is not a folder; pass a path"):
        gymnasium.make("ObjSearch/house-single-v1", cache_dir=5)
