"""HRL-GRG (Ye et al., CVPR 2021) and its three ablations, in the grid world.

A Goals Relational Graph (``objsearch_agents.grg``) counted from the low level's options;
a high-level network that scores one candidate at a time on (obstacles, candidate channel
times its plan value C(sg -> g)); the pretrained low level; the back-up "random" sub-goal;
options that end when a later node of the plan from the sub-goal becomes visible.

Ablations (paper table 2): ``-relation`` (no weighting of the candidate channel),
``-termination`` (options end only on reaching the sub-goal or after 10 steps),
``-high-level`` (no network: the visible candidate with the best plan value).
"""

from dataclasses import replace

from objsearch_agents.gridworld_agent import GridAgent
from objsearch_agents.gridworld_config import GridAgentConfig
from objsearch_agents.house import methods as house_methods

_BASE = replace(GridAgentConfig(), method="hrl_grg")


class HRLGRGAgent(GridAgent):
    config = _BASE
    checkpoint_name = "hrl_grg"
    house = house_methods.HRLGRGHouseAgent


class HRLGRGNoRelationAgent(GridAgent):
    config = replace(_BASE, relation=False)
    checkpoint_name = "hrl_grg_no_relation"
    house = house_methods.HRLGRGNoRelationHouseAgent


class HRLGRGNoTerminationAgent(GridAgent):
    config = replace(_BASE, termination=False)
    checkpoint_name = "hrl_grg_no_termination"
    house = house_methods.HRLGRGNoTerminationHouseAgent


class HRLGRGNoHighLevelAgent(GridAgent):
    config = replace(_BASE, high_level=False)
    checkpoint_name = "hrl_grg_no_high_level"
    house = house_methods.HRLGRGNoHighLevelHouseAgent


class HRLGRGGreedyAgent(HRLGRGAgent):
    """HRL-GRG evaluated greedily (epsilon 0 at both levels; grid world only)."""

    house = None

    def __init__(self):
        super().__init__(epsilon=0.0)
