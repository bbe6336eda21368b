"""The learning methods, one module each: ``a3c``, ``dqn``, ``hdqn`` and ``hrl_grg`` (its
ablations are switches of the config: ``relation``, ``termination``, ``high_level``).

A method is a small strategy object (``base.Method``): which networks it has, how its high
level chooses a sub-goal, when it ends an option besides the shared rules, and its
Q-learning loss. The policies and the training loop run any method through it and never
ask which one it is. The houses use these strategies; the grid world's policy still has
its own (issue 31: one strategy per method for both worlds is the next step).
"""

from __future__ import annotations

import importlib

METHODS = ("a3c", "dqn", "hdqn", "hrl_grg")


def method_of(name: str):
    """The strategy of method ``name`` (one of ``METHODS``)."""
    if name not in METHODS:
        raise KeyError(name)
    return importlib.import_module(f"objsearch_agents.methods.{name}").METHOD
