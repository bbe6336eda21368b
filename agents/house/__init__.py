"""The house agents: observation tables, networks, policy, trainer and the agents by method."""
