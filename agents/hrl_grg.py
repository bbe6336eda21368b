"""The old import path of the HRL-GRG agents (``objsearch_agents.learned``), kept because it is
persisted: the shipped leaderboard entry ``hrl_grg_greedy`` names its agent
``objsearch_agents.hrl_grg:HRLGRGGreedyAgent``, and that string is the registered target of
``hrl_grg_greedy`` (``pyproject.toml``), so the entry replays as a registered agent.
New code imports ``objsearch_agents.learned``."""

from objsearch_agents.learned import (
    HRLGRGAgent,
    HRLGRGGreedyAgent,
    HRLGRGNoHighLevelAgent,
    HRLGRGNoRelationAgent,
    HRLGRGNoTerminationAgent,
)

__all__ = [
    "HRLGRGAgent",
    "HRLGRGGreedyAgent",
    "HRLGRGNoHighLevelAgent",
    "HRLGRGNoRelationAgent",
    "HRLGRGNoTerminationAgent",
]
