"""Inputs that used to be accepted silently: fractional or string seeds, a bool action, a
fractional step limit, an agent that calls sys.exit."""

import sys

import numpy as np
import pytest

import objsearch
from objsearch.errors import UserError
from objsearch.eval.suites import make_suite


class ReturnsTrue:
    def reset(self, task):
        pass

    def act(self, observation):
        return True  # not an action, though Python counts it as 1


class Exits:
    def reset(self, task):
        pass

    def act(self, observation):
        sys.exit(3)


@pytest.mark.parametrize(
    "seeds, message",
    [
        ([1.7, "5"], "1.7 is not an integer >= 0"),
        ([1, 1], "a seed is given twice"),
        ("15", "give a list"),
        ([], "one seed"),
    ],
)
def test_evaluate_refuses_seeds_that_are_not_distinct_integers(seeds, message):
    with pytest.raises(UserError, match=message):
        objsearch.evaluate("random", "gridworld", seeds=seeds, split="unseen-goals")


def test_numpy_integer_seeds_are_seeds():
    results = objsearch.evaluate("oracle", "gridworld", seeds=np.array([1]), split="unseen-goals")
    assert results["seeds"] == [1] and results["splits"]["unseen-goals"]["sr"] == 1.0


@pytest.mark.parametrize("batch", [1, 8])
def test_an_agent_returning_true_or_calling_sys_exit_fails_its_episodes(batch):
    for agent, error in ((ReturnsTrue(), "invalid action True"), (Exits(), "SystemExit: 3")):
        results = objsearch.evaluate(agent, "gridworld", seeds=[1], split="unseen-goals", batch=batch)
        records = results["episodes"]
        assert len(records) == 100 and not any(r["success"] for r in records)
        assert all(error in r["error"] for r in records), records[0].get("error")


@pytest.mark.parametrize("max_steps", [2.5, 0, -5, True, "100"])
def test_a_step_limit_that_is_not_an_integer_of_at_least_1_is_refused(max_steps):
    with pytest.raises(UserError, match=r"max_steps .*: the step limit is an integer >= 1"):
        make_suite("gridworld", max_steps=max_steps)
    assert make_suite("gridworld", max_steps=np.int64(7)).max_steps == 7
    assert make_suite("gridworld", max_steps=50.0).max_steps == 50


@pytest.mark.parametrize(
    "suite, message",
    [
        (object(), "must be a class or a 'module:Class' string"),
        ("no_such_module_42:Suite", "cannot import no_such_module_42:Suite"),
        ("objsearch.eval.suites.gridworld:NoSuchSuite", "cannot import"),
        (dict, "is not a suite class"),
    ],
)
def test_register_suite_refuses_what_is_no_suite_at_once(suite, message):
    with pytest.raises(UserError, match=message):
        objsearch.register_suite("not-a-suite-42", suite)
    from objsearch.eval.suites import SUITES

    assert "not-a-suite-42" not in SUITES
