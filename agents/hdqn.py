"""h-DQN baseline (paper appendix A.1): a 17-channel high level with the one-hot goal after
the trunk and 17 outputs (16 goals + "random"), argmax over the visible candidates; the low
level is the pretrained DQN, trained on the intrinsic reward. No graph, no plan termination."""

from dataclasses import replace

from objsearch_agents.gridworld_agent import GridAgent
from objsearch_agents.gridworld_config import GridAgentConfig
from objsearch_agents.house.methods import HDQNHouseAgent


class HDQNAgent(GridAgent):
    config = replace(GridAgentConfig(), method="hdqn")
    checkpoint_name = "hdqn"
    house = HDQNHouseAgent


class HDQNGreedyAgent(HDQNAgent):
    """h-DQN evaluated greedily (epsilon 0; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)
