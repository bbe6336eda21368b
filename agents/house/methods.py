"""The house agents by method: A3C, DQN, h-DQN ("Hrl") and HRL-GRG with its ablations.

The names are the grid world's (``dqn``, ``hdqn``, ``hrl_grg``, ...; the grid-world class
of each hands house suites to the class here) plus those that exist only in the houses:
``a3c``, and ``hdqn_explorer`` and ``hrl_grg_explorer``, the paper's methods with a trained
A3C in the back-up node (``docs/house_agents.md``). Each class is a ``HouseAgentConfig`` naming
its method; the method itself is one module, ``objsearch_agents.methods.<method>``, which the
houses run through their adapter (``house.world``) in ``house.policy`` and ``house.train``.
"""

from dataclasses import replace

from objsearch_agents.house.agent import HouseAgent
from objsearch_agents.house.config import HouseAgentConfig

_BASE = HouseAgentConfig()


class A3CAgent(HouseAgent):
    """A3C (paper appendix B.2): an actor-critic on the target's mask and depth."""

    config = replace(_BASE, method="a3c")


class DQNHouseAgent(HouseAgent):
    """DQN: Double DQN on every category's mask, depth and the target's one-hot."""

    config = replace(_BASE, method="dqn")


class HDQNHouseAgent(HouseAgent):
    """h-DQN ("Hrl" in Table 3): a DQN high level over sub-goal categories, the A3C low level."""

    config = replace(_BASE, method="hdqn")


class HDQNExplorerHouseAgent(HDQNHouseAgent):
    """h-DQN whose back-up node runs a trained A3C (our extension; ``HouseAgent.explorer``)."""

    explorer = True


class HRLGRGHouseAgent(HouseAgent):
    """HRL-GRG: the GRG, a high level scoring candidates by relation, the A3C low level."""

    config = replace(_BASE, method="hrl_grg")


class HRLGRGExplorerHouseAgent(HRLGRGHouseAgent):
    """HRL-GRG whose back-up node runs a trained A3C (our extension; ``HouseAgent.explorer``)."""

    explorer = True


class HRLGRGNoRelationHouseAgent(HouseAgent):
    config = replace(_BASE, method="hrl_grg", relation=False)


class HRLGRGNoTerminationHouseAgent(HouseAgent):
    config = replace(_BASE, method="hrl_grg", termination=False)


class HRLGRGNoHighLevelHouseAgent(HouseAgent):
    config = replace(_BASE, method="hrl_grg", high_level=False)
