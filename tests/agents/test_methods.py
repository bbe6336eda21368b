"""Each method is one strategy module (``objsearch_agents.methods``) that both worlds run;
nothing in the agents asks which method it is running, and every reference agent, greedy
variants included, is registered under its own name."""

import re
from pathlib import Path

import pytest

import objsearch_agents
from objsearch_agents.methods import METHODS, method_of

AGENTS = Path(objsearch_agents.__file__).parent


def test_no_method_branches_remain_in_the_agents():
    branch = re.compile(r"method ==|method in\b|method !=")
    found = [
        f"{path.relative_to(AGENTS)}:{n}: {line.strip()}"
        for path in sorted(AGENTS.rglob("*.py"))
        for n, line in enumerate(path.read_text().splitlines(), 1)
        if branch.search(line)
    ]
    assert not found, "branch on the method's name; ask its strategy instead:\n" + "\n".join(found)


@pytest.mark.parametrize("name", METHODS)
def test_each_method_is_one_module_with_one_strategy(name):
    method = method_of(name)
    assert method.name == name and type(method).__module__ == f"objsearch_agents.methods.{name}"


@pytest.mark.parametrize(
    "name, path",
    [
        ("dqn_greedy", "objsearch_agents.dqn:DQNGreedyAgent"),
        ("hdqn_greedy", "objsearch_agents.hdqn:HDQNGreedyAgent"),
        ("hrl_grg_greedy", "objsearch_agents.hrl_grg:HRLGRGGreedyAgent"),
    ],
)
def test_greedy_variants_have_their_own_names(name, path):
    from objsearch.eval.registry import make_agent, resolve_agent

    assert resolve_agent(name) is resolve_agent(path)
    agent = make_agent(name, suite="gridworld")
    assert agent.epsilon == 0.0 and agent.loaded_from
