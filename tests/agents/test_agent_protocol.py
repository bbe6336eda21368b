"""Every learning agent plays through the evaluation harness (untrained: it must run, not
score), draws its randomness from task.rng only, and refuses a mismatched checkpoint."""

import pytest

from objsearch.errors import UserError
from objsearch.eval.registry import make_agent
from objsearch.eval.runner import EvalConfig, evaluate
from objsearch.gridworld.dataset import DATA_DIR

AGENTS = ["dqn", "hdqn", "hrl_grg", "hrl_grg_no_relation", "hrl_grg_no_termination", "hrl_grg_no_high_level"]


@pytest.fixture(scope="module")
def task_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("tasks") / "few.jsonl"
    lines = (DATA_DIR / "tasks" / "all-goals.jsonl").read_text().splitlines()[:4]
    path.write_text("\n".join(lines) + "\n")
    return str(path)


@pytest.mark.parametrize("agent", AGENTS)
def test_untrained_agent_runs_through_the_harness(agent, task_file):
    config = EvalConfig(agent=agent, seeds=(1, 5), suite_config={"maps": str(DATA_DIR / "test"), "tasks": task_file})
    results = evaluate(config, progress=False)
    again = evaluate(config, progress=False)
    assert results["splits"]["few"]["episodes"] == 8
    assert [e["steps"] for e in results["episodes"]] == [e["steps"] for e in again["episodes"]]  # task.rng only


def test_greedy_variant_and_wrong_checkpoint(tmp_path, task_file):
    from objsearch_agents.gridworld.checkpoint import save_policy

    greedy = make_agent("objsearch_agents.hrl_grg:HRLGRGGreedyAgent")
    assert greedy.epsilon == 0.0 and make_agent("hrl_grg").epsilon == 0.1
    save_policy(make_agent("hdqn").policy, tmp_path)
    with pytest.raises(UserError, match="trained as hdqn"):
        make_agent("hrl_grg", str(tmp_path))
    make_agent("hdqn", str(tmp_path))  # the matching agent loads it
    with pytest.raises(UserError, match="does not exist"):
        make_agent("dqn", str(tmp_path / "nowhere"))


@pytest.mark.parametrize("agent", ["dqn", "hrl_grg"])
def test_batched_evaluation_gives_the_sequential_records(agent):
    from objsearch.eval.agent import is_batched

    assert is_batched(make_agent(agent))
    config = EvalConfig(agent=agent, splits=("unseen-goals",), seeds=(1,))
    assert evaluate(config, progress=False, batch=64)["episodes"] == evaluate(config, progress=False)["episodes"]
