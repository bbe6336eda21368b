"""The house agents: observation tables, their adapter for the methods (``world``), networks,
config, policy, checkpoints, trainer, the agents by method (``methods``) and the GRG figure.
It never imports the grid world's package (``objsearch_agents.gridworld``; ``tests/test_layers.py``)."""
