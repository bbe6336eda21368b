"""DQN baseline (paper sec. 4.1): Double DQN on (obstacles, final-goal channel), initialised
from the pretrained goal-reaching low level. See ``gridworld_agent`` for the protocol."""

from dataclasses import replace

from objsearch_agents.gridworld_agent import GridAgent
from objsearch_agents.gridworld_config import GridAgentConfig
from objsearch_agents.house.methods import DQNHouseAgent


class DQNAgent(GridAgent):
    config = replace(GridAgentConfig(), method="dqn")
    checkpoint_name = "dqn"
    house = DQNHouseAgent


class DQNGreedyAgent(DQNAgent):
    """DQN evaluated greedily (epsilon 0; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)
