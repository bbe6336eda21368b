"""objsearch's reference agents (import package ``objsearch_agents``).

Each agent follows ``objsearch.eval.agent`` and is registered in the entry-point group
``objsearch.agents`` of ``pyproject.toml``.
"""
