"""A policy trained on a perception network's predictions records that network, and the
harness refuses to evaluate it on another network's predictions."""

from types import SimpleNamespace

import pytest

from objsearch.errors import UserError
from objsearch.eval.plan import check_perception
from objsearch_agents.house.checkpoint import load_policy, save_policy
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.policy import HousePolicy


def test_the_policy_file_keeps_the_perception_network_it_learned_from(tmp_path):
    policy = HousePolicy(HouseAgentConfig(method="a3c", observation="predicted"))
    save_policy(policy, tmp_path / "pred", "fbad46808c207764")
    save_policy(policy, tmp_path / "gt")
    assert load_policy(tmp_path / "pred")[0].perception_key == "fbad46808c207764"
    assert load_policy(tmp_path / "gt")[0].perception_key is None


def test_an_agent_trained_on_one_networks_predictions_is_refused_on_anothers():
    agent = SimpleNamespace(trained_perception_key="fbad46808c207764", loaded_from="runs/x/policy.pt")

    def suite(key):
        return SimpleNamespace(predictor=None if key is None else SimpleNamespace(key=key), perception="net.pt")

    check_perception(agent, suite("fbad46808c207764"))  # the network it learned from
    check_perception(agent, suite(None))  # ground truth: what it saw is a choice of the evaluation, not a mismatch
    check_perception(SimpleNamespace(trained_perception_key=None), suite("0123456789abcdef"))  # trained on gt
    check_perception(object(), suite("0123456789abcdef"))  # an agent that records nothing (random, a user's own)
    with pytest.raises(UserError, match="trained on the predictions of perception network fbad46808c207764, not"):
        check_perception(agent, suite("0123456789abcdef"))
