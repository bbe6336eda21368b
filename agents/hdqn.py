"""The old import path of the h-DQN agents (``objsearch_agents.learned``), kept because it is
persisted: the shipped leaderboard entry ``hdqn_greedy`` names its agent
``objsearch_agents.hdqn:HDQNGreedyAgent``, and that string is the registered target of
``hdqn_greedy`` (``pyproject.toml``), so the entry replays as a registered agent.
New code imports ``objsearch_agents.learned``."""

from objsearch_agents.learned import HDQNAgent, HDQNGreedyAgent

__all__ = ["HDQNAgent", "HDQNGreedyAgent"]
