"""The learned agents by registered name: DQN, h-DQN, HRL-GRG and its ablations in both
worlds, and the grid world's greedy variants (the names of ``pyproject.toml``'s
``objsearch.agents`` table; the house-only ``a3c`` and ``*_explorer`` are
``house.methods``' classes).

Each class is a grid-world agent (``gridworld.agent.GridAgent``, its ``config`` naming the
method and ablation, ``checkpoint_name`` its shipped folder) whose ``house`` is the same
method's house agent (``house.methods``): ``for_suite`` and ``train`` hand house suites to
it. This module is the one place that pairs the two worlds, which never import each other.
The method itself is one module, ``methods/<method>.py``.

HRL-GRG's ablations (paper table 2): ``-relation`` (no weighting of the candidate channel),
``-termination`` (options end only on reaching the sub-goal or running out of steps),
``-high-level`` (no network: the visible candidate with the best plan value).
"""

from __future__ import annotations

from dataclasses import replace

from objsearch_agents.gridworld.agent import GridAgent
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.house import methods as house

_GRID = GridAgentConfig()
_HRL_GRG = replace(_GRID, method="hrl_grg")


class DQNAgent(GridAgent):
    """DQN baseline (paper sec. 4.1): Double DQN on (obstacles, final-goal channel),
    initialised from the pretrained goal-reaching low level."""

    config = replace(_GRID, method="dqn")
    checkpoint_name = "dqn"
    house = house.DQNHouseAgent


class HDQNAgent(GridAgent):
    """h-DQN baseline (paper appendix A.1): a 17-channel high level with the one-hot goal
    after the trunk and 17 outputs (16 goals + "random"), argmax over the visible
    candidates; the low level is the pretrained DQN, trained on the intrinsic reward."""

    config = replace(_GRID, method="hdqn")
    checkpoint_name = "hdqn"
    house = house.HDQNHouseAgent


class HRLGRGAgent(GridAgent):
    """HRL-GRG (Ye et al., CVPR 2021): ``methods/hrl_grg.py``."""

    config = _HRL_GRG
    checkpoint_name = "hrl_grg"
    house = house.HRLGRGHouseAgent


class HRLGRGNoRelationAgent(GridAgent):
    config = replace(_HRL_GRG, relation=False)
    checkpoint_name = "hrl_grg_no_relation"
    house = house.HRLGRGNoRelationHouseAgent


class HRLGRGNoTerminationAgent(GridAgent):
    config = replace(_HRL_GRG, termination=False)
    checkpoint_name = "hrl_grg_no_termination"
    house = house.HRLGRGNoTerminationHouseAgent


class HRLGRGNoHighLevelAgent(GridAgent):
    config = replace(_HRL_GRG, high_level=False)
    checkpoint_name = "hrl_grg_no_high_level"
    house = house.HRLGRGNoHighLevelHouseAgent


class DQNGreedyAgent(DQNAgent):
    """DQN evaluated greedily (epsilon 0; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)


class HDQNGreedyAgent(HDQNAgent):
    """h-DQN evaluated greedily (epsilon 0; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)


class HRLGRGGreedyAgent(HRLGRGAgent):
    """HRL-GRG evaluated greedily (epsilon 0 at both levels; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)
