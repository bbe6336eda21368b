"""The grid world's learned agents: its adapter for the methods (``world``: inputs, networks,
losses), observation inputs (``inputs``), networks (``nets``), config (``config``), policy,
checkpoints, trainer (``train``), the evaluable agent (``agent``) and the GRG figure. It never
imports the houses' package (``objsearch_agents.house``; ``tests/test_layers.py``)."""
