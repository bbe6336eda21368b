"""The old import path of the DQN agents (``objsearch_agents.learned``), kept because it is
persisted: the shipped leaderboard entry ``dqn_greedy`` names its agent
``objsearch_agents.dqn:DQNGreedyAgent``, and that string is the registered target of
``dqn_greedy`` (``pyproject.toml``), so the entry replays as a registered agent.
New code imports ``objsearch_agents.learned``."""

from objsearch_agents.learned import DQNAgent, DQNGreedyAgent

__all__ = ["DQNAgent", "DQNGreedyAgent"]
